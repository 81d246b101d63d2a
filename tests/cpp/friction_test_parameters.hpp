#pragma once
// Shared by the friction tests: parameter sets for each strength law.
#include "friction/friction_law.hpp"

namespace slipstrip::testing {

// Table S1 for the paper law; for the Dieterich-Ruina and regularised laws
// (whose f0 and b have their usual meaning) a typical laboratory set.
inline FrictionParameters parameters_for(StrengthLaw law, StateLaw state_law = StateLaw::aging) {
  FrictionParameters p;
  p.strength_law = law;
  p.state_law = state_law;
  if (law != StrengthLaw::paper) {
    p.f0 = 0.6;
    p.a = 0.01;
    p.b = 0.015;
    p.characteristic_slip = 1e-5;
    p.v_star = 1e-6;
  }
  return p;
}

}  // namespace slipstrip::testing

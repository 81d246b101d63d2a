#pragma once
// A toy interface law, kept with the tests: a linear viscous interface,
// shear_stress = -viscosity * slip_rate with viscosity = 4 eta, loaded by the
// [interface] stress pulse of the free law.  docs/developing.md shows it as
// the example of adding a law: this file, plus one registration line.
#include <memory>
#include <vector>

#include "laws/interface_law.hpp"
#include "laws/interface_pulse.hpp"
#include "config/simulation_config.hpp"

namespace slipstrip::testing {

class ViscousLaw final : public InterfaceLaw {
 public:
  explicit ViscousLaw(const InterfaceSetup& setup)
      : in_(setup.config.interface), length_(setup.config.geometry.length), eta_(setup.eta),
        viscosity_(4.0 * setup.eta), reference_(setup.x.size(), 0.0) {}

  double driving_velocity() const override { return 0.0; }
  std::span<const double> reference_shear_stress() const override { return reference_; }
  void initialise(InterfaceFields& f) override { solve(f, 0.0); }
  void advance(const InterfaceStep& step, InterfaceFields& f) override {
    solve(f, step.time + step.dt);
    integrate_slip(f, step.dt);
  }

 private:
  // pulse - history - eta v = viscosity v.
  void solve(InterfaceFields& f, double t) const {
    for (std::size_t i = 0; i < f.x.size(); ++i) {
      const double load = imposed_stress(in_, in_.stress_amplitude, length_, f.x[i], t);
      f.slip_rate[i] = (load - f.history_stress[i]) / (eta_ + viscosity_);
      f.shear_stress[i] = -viscosity_ * f.slip_rate[i];
    }
  }

  InterfaceConfig in_;
  double length_, eta_, viscosity_;
  std::vector<double> reference_;
};

inline std::unique_ptr<InterfaceLaw> make_viscous_law(const InterfaceSetup& setup) {
  return std::make_unique<ViscousLaw>(setup);
}

}  // namespace slipstrip::testing

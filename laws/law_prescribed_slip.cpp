// interface.law = "prescribed_slip": slip(x, t) = slip_amplitude
// cos(2 pi mode x / L) g(t) is imposed; the shear stress is what the elastic
// response makes it.  A verification law (time histories against inverse
// Laplace transforms, tests/cpp/test_kernels_time_domain.cpp).
#include <cmath>
#include <numbers>

#include "laws/interface_law.hpp"
#include "laws/interface_pulse.hpp"

namespace slipstrip {
namespace {

class PrescribedSlipLaw final : public InterfaceLaw {
 public:
  explicit PrescribedSlipLaw(const InterfaceSetup& setup)
      : in_(setup.config.interface), eta_(setup.eta), reference_(setup.x.size(), 0.0),
        wavenumber_(2.0 * std::numbers::pi * in_.mode / setup.config.geometry.length) {}

  double driving_velocity() const override { return 0.0; }
  std::span<const double> reference_shear_stress() const override { return reference_; }

  void initialise(InterfaceFields& f) override {
    for (std::size_t i = 0; i < f.x.size(); ++i) {
      const double shape = in_.slip_amplitude * std::cos(wavenumber_ * f.x[i]);
      f.slip[i] = shape * pulse_profile(in_, 0.0);
      f.slip_rate[i] = shape * pulse_profile_rate(in_, 0.0);
      f.shear_stress[i] = -eta_ * f.slip_rate[i];
    }
  }

  // Slip is set exactly (not integrated), so it carries no time-step error.
  void advance(const InterfaceStep& step, InterfaceFields& f) override {
    const double t = step.time + step.dt;
    const double g = pulse_profile(in_, t), gdot = pulse_profile_rate(in_, t);
    for (std::size_t i = 0; i < f.x.size(); ++i) {
      const double shape = in_.slip_amplitude * std::cos(wavenumber_ * f.x[i]);
      f.slip_rate[i] = shape * gdot;
      f.shear_stress[i] = -f.history_stress[i] - eta_ * f.slip_rate[i];
      f.slip[i] = shape * g;
    }
  }

 private:
  InterfaceConfig in_;
  double eta_;
  std::vector<double> reference_;
  double wavenumber_;
};

}  // namespace

std::unique_ptr<InterfaceLaw> make_prescribed_slip_law(const InterfaceSetup& setup) {
  return std::make_unique<PrescribedSlipLaw>(setup);
}

}  // namespace slipstrip

// interface.law = "free": no friction; the interface carries an imposed
// shear-stress pulse (stress_amplitude, pulse_center, pulse_width, profile,
// rise_time) and is otherwise traction-free.  A verification law: the slip
// rate is whatever the elastic response and the pulse make it.
#include "laws/interface_law.hpp"
#include "laws/interface_pulse.hpp"

namespace slipstrip {
namespace {

class FreeLaw final : public InterfaceLaw {
 public:
  explicit FreeLaw(const InterfaceSetup& setup)
      : in_(setup.config.interface), length_(setup.config.geometry.length), eta_(setup.eta),
        reference_(setup.x.size(), 0.0) {}

  double driving_velocity() const override { return 0.0; }
  std::span<const double> reference_shear_stress() const override { return reference_; }

  void initialise(InterfaceFields& f) override { solve(f, 0.0); }

  void advance(const InterfaceStep& step, InterfaceFields& f) override {
    solve(f, step.time + step.dt);
    integrate_slip(f, step.dt);
  }

 private:
  // imposed - history - eta v = 0 (the traction on the interface is the pulse).
  void solve(InterfaceFields& f, double t) const {
    for (std::size_t i = 0; i < f.x.size(); ++i) {
      f.slip_rate[i] =
          (imposed_stress(in_, in_.stress_amplitude, length_, f.x[i], t) - f.history_stress[i]) /
          eta_;
      f.shear_stress[i] = -f.history_stress[i] - eta_ * f.slip_rate[i];
    }
  }

  InterfaceConfig in_;
  double length_, eta_;
  std::vector<double> reference_;
};

}  // namespace

std::unique_ptr<InterfaceLaw> make_free_law(const InterfaceSetup& setup) {
  return std::make_unique<FreeLaw>(setup);
}

}  // namespace slipstrip

// Linear stability of steady sliding (stability/linear_stability.hpp) and the
// strip response functions (kernels/strip_response.hpp).  Steady sliding is
// described by a config, exactly as the CLI's `slipstrip stability` does.
#include <pybind11/complex.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <vector>

#include "stability/steady_sliding.hpp"
#include "config/simulation_config.hpp"
#include "friction/friction_law.hpp"
#include "stability/interface_stability.hpp"
#include "stability/linear_stability.hpp"
#include "kernels/strip_response.hpp"

namespace py = pybind11;
using slipstrip::complex;
using slipstrip::ElasticMaterial;
using slipstrip::SimulationConfig;
using slipstrip::SteadySliding;
using slipstrip::steady_sliding_of;

namespace {

py::dict growth_rates(const SimulationConfig& config, const std::vector<double>& wavelengths) {
  std::vector<slipstrip::GrowthRate> rates;
  {
    py::gil_scoped_release release;
    rates = slipstrip::growth_rates(steady_sliding_of(config), wavelengths);
  }
  const auto n = static_cast<py::ssize_t>(rates.size());
  py::array_t<double> w(n), g(n), f(n);
  py::array_t<bool> unstable(n);
  for (py::ssize_t i = 0; i < n; ++i) {
    w.mutable_at(i) = rates[i].wavelength;
    g.mutable_at(i) = rates[i].growth_rate;
    f.mutable_at(i) = rates[i].frequency;
    unstable.mutable_at(i) = rates[i].unstable;
  }
  py::dict d;
  d["wavelength"] = w;
  d["growth_rate"] = g;
  d["frequency"] = f;
  d["unstable"] = unstable;
  return d;
}

py::dict linearise(const SimulationConfig& config) {
  const auto lin = slipstrip::linearise_friction(steady_sliding_of(config));
  py::dict d;
  d["state"] = lin.state;
  d["strength_dv"] = lin.strength_dv;
  d["strength_dstate"] = lin.strength_dstate;
  d["state_rate_dv"] = lin.state_rate_dv;
  d["state_rate_dstate"] = lin.state_rate_dstate;
  return d;
}

}  // namespace

void bind_stability(py::module_& m) {
  m.def("_growth_rates", &growth_rates, py::arg("config"), py::arg("wavelengths"));
  m.def("_linearise_friction", &linearise, py::arg("config"));
  m.def(
      "_most_unstable_root",
      [](const SimulationConfig& config, double wavelength) {
        py::gil_scoped_release release;
        return slipstrip::most_unstable_root(steady_sliding_of(config), wavelength);
      },
      py::arg("config"), py::arg("wavelength"));
  m.def(
      "_characteristic_roots",
      [](const SimulationConfig& config, double wavelength) {
        py::gil_scoped_release release;
        return slipstrip::characteristic_roots(steady_sliding_of(config), wavelength);
      },
      py::arg("config"), py::arg("wavelength"));
  m.def(
      "_critical_wavelength",
      [](const SimulationConfig& config, double lower, double upper, double relative_tolerance) {
        py::gil_scoped_release release;
        return slipstrip::critical_wavelength(steady_sliding_of(config), lower, upper, relative_tolerance);
      },
      py::arg("config"), py::arg("lower"), py::arg("upper"), py::arg("relative_tolerance") = 1e-10);
  m.def(
      "_critical_wavelength_vs_height",
      [](const SimulationConfig& config, const std::vector<double>& heights) {
        py::gil_scoped_release release;
        return slipstrip::critical_wavelength_vs_height(steady_sliding_of(config), heights);
      },
      py::arg("config"), py::arg("heights"));
  // In-plane pairs of different bodies (stability/interface_stability.hpp), the
  // problem read off the config by pair_sliding_of as `slipstrip stability` does.
  m.def(
      "_pair_unstable_roots",
      [](const SimulationConfig& config, double wavelength) {
        const auto pair = slipstrip::pair_sliding_of(config);
        py::gil_scoped_release release;
        return slipstrip::pair_unstable_roots(pair, wavelength);
      },
      py::arg("config"), py::arg("wavelength"));
  m.def(
      "_pair_critical_wavelength_vs_top_height",
      [](const SimulationConfig& config, const std::vector<double>& heights, double shortest, double longest) {
        const auto pair = slipstrip::pair_sliding_of(config);
        py::gil_scoped_release release;
        return slipstrip::pair_critical_wavelength_vs_top_height(pair, heights, shortest, longest);
      },
      py::arg("config"), py::arg("heights"), py::arg("shortest"), py::arg("longest"));
  m.def(
      "_pair_critical_wavelength",
      [](const SimulationConfig& config, double shortest, double longest) {
        const auto pair = slipstrip::pair_sliding_of(config);
        py::gil_scoped_release release;
        return slipstrip::pair_critical_wavelength(pair, shortest, longest);
      },
      py::arg("config"), py::arg("shortest"), py::arg("longest"));
  m.def(
      "_quasi_static_critical_wavelength",
      [](const SimulationConfig& config) {
        return slipstrip::quasi_static_critical_wavelength(steady_sliding_of(config));
      },
      py::arg("config"));
  m.def(
      "_characteristic_function",
      [](const SimulationConfig& config, double wavenumber, complex growth) {
        return slipstrip::characteristic_function(steady_sliding_of(config), wavenumber, growth);
      },
      py::arg("config"), py::arg("wavenumber"), py::arg("growth"));

  // The local interface solve of one node (friction_law.hpp), with the config's
  // friction, normal stress and radiation damping eta = mu / (2 c_s).
  m.def(
      "_solve_slip_rate",
      [](const SimulationConfig& config, double tau_history, double state, double initial_guess) {
        return slipstrip::solve_slip_rate(config.friction, config.loading.normal_stress,
                                          config.material.radiation_damping(), tau_history, state,
                                          initial_guess);
      },
      py::arg("config"), py::arg("tau_history"), py::arg("state"), py::arg("initial_guess"));

  // Kernels, vectorised over wavenumber (and s): NumPy broadcasting applies.
  m.def(
      "strip_response",
      [](const ElasticMaterial& material, double strip_height, py::array_t<double> wavenumber,
         py::array_t<complex> s) {
        return py::vectorize([&](double k, complex z) {
          return slipstrip::strip_response(material, strip_height, k, z);
        })(wavenumber, s);
      },
      py::arg("material"), py::arg("strip_height"), py::arg("wavenumber"), py::arg("s"),
      "S(k, s; H) [Pa/m]: tau^ = -S slip^ (strip_height = inf gives the half-space).");
  m.def(
      "half_space_response",
      [](const ElasticMaterial& material, py::array_t<double> wavenumber, py::array_t<complex> s) {
        return py::vectorize([&](double k, complex z) {
          return slipstrip::half_space_response(material, k, z);
        })(wavenumber, s);
      },
      py::arg("material"), py::arg("wavenumber"), py::arg("s"), "S_inf(k, s) [Pa/m].");
  m.def(
      "strip_static_stiffness",
      [](const ElasticMaterial& material, double strip_height, py::array_t<double> wavenumber) {
        return py::vectorize([&](double k) {
          return slipstrip::strip_static_stiffness(material, strip_height, k);
        })(wavenumber);
      },
      py::arg("material"), py::arg("strip_height"), py::arg("wavenumber"), "S(k, 0; H) [Pa/m].");
}

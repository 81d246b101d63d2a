// Configuration: load/validate (config/config.hpp) and the elastic material
// (kernels/elastic_material.hpp).  Python's Config class (python/slipstrip/
// config.py) subclasses _Config, so a Config *is* a SimulationConfig and can be
// passed to every C++ function without conversion.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "config/config.hpp"
#include "config/config_schema.hpp"
#include "config/resource_estimate.hpp"
#include "kernels/elastic_material.hpp"

namespace py = pybind11;
using slipstrip::ElasticMaterial;
using slipstrip::PlaneCondition;
using slipstrip::SimulationConfig;

namespace {

// Plane conditions by their one spelling (kernels/elastic_material.hpp).
PlaneCondition parse_plane(const std::string& name) {
  std::string allowed;
  for (std::size_t i = 0; i < std::size(slipstrip::kPlaneConditionNames); ++i) {
    if (slipstrip::kPlaneConditionNames[i] == name) return static_cast<PlaneCondition>(i);
    allowed += (i ? " and '" : "'") + std::string(slipstrip::kPlaneConditionNames[i]) + "'";
  }
  throw std::invalid_argument("plane = '" + name + "' is invalid: allowed values are " + allowed);
}

std::string plane_name(PlaneCondition p) {
  return std::string(slipstrip::kPlaneConditionNames[static_cast<std::size_t>(p)]);
}

// A TOML value as the Python value tomllib gives for it.
py::object python_value(const toml::node& node) {
  if (const auto* t = node.as_table()) {
    py::dict out;
    for (const auto& [key, value] : *t) out[py::str(std::string(key.str()))] = python_value(value);
    return out;
  }
  if (const auto* a = node.as_array()) {
    py::list out;
    for (const auto& value : *a) out.append(python_value(value));
    return out;
  }
  if (const auto* s = node.as_string()) return py::str(s->get());
  if (const auto* i = node.as_integer()) return py::int_(i->get());
  if (const auto* f = node.as_floating_point()) return py::float_(f->get());
  if (const auto* b = node.as_boolean()) return py::bool_(b->get());
  throw std::logic_error("config value of a type the schema never writes");
}

const char* type_name(slipstrip::KeyType type) {
  switch (type) {
    case slipstrip::KeyType::number: return "number";
    case slipstrip::KeyType::number_or_inf: return "number_or_inf";
    case slipstrip::KeyType::integer: return "integer";
    case slipstrip::KeyType::choice: return "choice";
    case slipstrip::KeyType::text: return "text";
    case slipstrip::KeyType::numbers: return "numbers";
    case slipstrip::KeyType::friction_parameter: return "friction_parameter";
  }
  return "unknown";
}

// The schema for Python (introspection, GUIs, checks): one dict per key.
py::list config_schema() {
  const SimulationConfig defaults;
  py::list out;
  for (const auto& k : slipstrip::config_keys()) {
    py::dict d;
    d["section"] = std::string(k.section);
    d["name"] = std::string(k.name);
    d["type"] = type_name(k.type);
    d["unit"] = std::string(k.unit);
    d["default"] = k.alternative_to.empty()
                       ? python_value(*slipstrip::config_to_table(defaults)[k.section][k.name].node())
                       : py::none();
    d["allowed"] = k.allowed.bounded() || !k.allowed_message.empty() ? py::object(py::str(slipstrip::allowed_text(k)))
                                                                     : py::object(py::none());
    d["help"] = std::string(k.help);
    d["alternative_to"] = k.alternative_to.empty() ? py::object(py::none())
                                                    : py::object(py::str(std::string(k.alternative_to)));
    py::list choices;
    if (k.choices)
      for (const auto name : k.choices()) choices.append(std::string(name));
    d["choices"] = choices;
    out.append(d);
  }
  return out;
}

}  // namespace

void bind_config(py::module_& m) {
  // Keyword defaults are the struct's (the config defaults, Table S1).
  const ElasticMaterial defaults;
  py::class_<ElasticMaterial>(m, "ElasticMaterial",
                              "Isotropic elastic bulk of the two strips (SI units).")
      .def(py::init([](double shear_modulus, double poisson_ratio, double density, const std::string& plane) {
             ElasticMaterial mat;
             mat.shear_modulus = shear_modulus;
             mat.poisson_ratio = poisson_ratio;
             mat.density = density;
             mat.plane = parse_plane(plane);
             return mat;
           }),
           py::arg("shear_modulus") = defaults.shear_modulus,
           py::arg("poisson_ratio") = defaults.poisson_ratio, py::arg("density") = defaults.density,
           py::arg("plane") = plane_name(defaults.plane))
      .def_readwrite("shear_modulus", &ElasticMaterial::shear_modulus, "mu [Pa]")
      .def_readwrite("poisson_ratio", &ElasticMaterial::poisson_ratio, "nu [-]")
      .def_readwrite("density", &ElasticMaterial::density, "rho [kg/m^3]")
      .def_property(
          "plane", [](const ElasticMaterial& mat) { return plane_name(mat.plane); },
          [](ElasticMaterial& mat, const std::string& name) { mat.plane = parse_plane(name); },
          "'strain' or 'stress'")
      .def_property_readonly("shear_wave_speed", &ElasticMaterial::shear_wave_speed, "c_s [m/s]")
      .def_property_readonly("dilatational_wave_speed", &ElasticMaterial::dilatational_wave_speed, "c_d [m/s]")
      .def_property_readonly("wave_speed_ratio_squared", &ElasticMaterial::wave_speed_ratio_squared,
                             "c_d^2 / c_s^2 [-]")
      .def_property_readonly("effective_modulus", &ElasticMaterial::effective_modulus, "E' [Pa]")
      .def("__repr__", [](const ElasticMaterial& mat) {
        return "ElasticMaterial(shear_modulus=" + py::repr(py::float_(mat.shear_modulus)).cast<std::string>() +
               ", poisson_ratio=" + py::repr(py::float_(mat.poisson_ratio)).cast<std::string>() +
               ", density=" + py::repr(py::float_(mat.density)).cast<std::string>() + ", plane='" +
               plane_name(mat.plane) + "')";
      });

  // Native config.  Construction without arguments gives the defaults exactly
  // as an empty TOML file resolves them (Table S1 of the paper).
  py::class_<SimulationConfig>(m, "_Config")
      .def(py::init([] { return slipstrip::load_config_string(""); }))
      .def("_assign", [](SimulationConfig& self, const SimulationConfig& other) { self = other; })
      .def("to_toml", [](const SimulationConfig& c) { return slipstrip::to_toml(c); },
           "The resolved config as TOML text (every key; reads back to the same values).")
      .def("_as_dict", [](const SimulationConfig& c) { return python_value(slipstrip::config_to_table(c)); },
           "The resolved config as {section: {key: value}}, the values tomllib reads from to_toml().")
      .def_property_readonly("length", [](const SimulationConfig& c) { return c.geometry.length; }, "L [m]")
      .def_property_readonly("height", [](const SimulationConfig& c) { return c.geometry.height; },
                             "H [m] of each strip (inf = half-space)")
      .def_property_readonly("nodes", [](const SimulationConfig& c) { return c.geometry.nodes; }, "N")
      .def_property_readonly("driving_velocity", [](const SimulationConfig& c) { return c.loading.driving_velocity; },
                             "v0 [m/s]")
      .def_property_readonly("normal_stress", [](const SimulationConfig& c) { return c.loading.normal_stress; },
                             "sigma0 [Pa]")
      .def_property_readonly("duration", [](const SimulationConfig& c) { return c.time.duration; }, "[s]")
      .def_property_readonly("delta_th", [](const SimulationConfig& c) { return c.output.delta_th; }, "[m]")
      .def_property_readonly("material", [](const SimulationConfig& c) { return c.material; });

  m.def("config_schema", &config_schema,
        "Every config key (config/config_schema.cpp) as a dict: section, name, type, unit, default, "
        "allowed, help, alternative_to, choices.");
  m.def("plausibility_warnings", &slipstrip::plausibility_warnings, py::arg("config"),
        "The config's plausibility warnings (config/config_schema.hpp): valid values that look like a unit "
        "mistake or degrade the result; [] when none.");
  m.def("run_header", &slipstrip::run_header, py::arg("config"),
        "What the run will cost (steps, wall time, history-operator memory, output size, slip per step) and "
        "its plausibility warnings, as `slipstrip run` prints them.");
  m.def("load_config_file", &slipstrip::load_config_file, py::arg("path"),
        py::arg("overrides") = std::vector<std::string>{},
        "Read, override ('section.key=value') and validate a TOML file.  Raises ConfigError.");
  m.def("load_config_string", &slipstrip::load_config_string, py::arg("toml_text"),
        py::arg("overrides") = std::vector<std::string>{},
        "Parse, override and validate TOML text ('' = defaults).  Raises ConfigError.");
}

// The compiled part of the Python package: slipstrip._slipstrip.
//
// The Python-facing API lives in python/slipstrip/__init__.py; this module is
// a thin layer over the C++ library.  Exceptions keep the C++ message text
// unchanged so that Python users and the CLI report the same diagnostics:
//   ConfigError       -> slipstrip.ConfigError       (subclass of ValueError)
//   std::invalid_argument -> ValueError              (pybind11 default)
//   SimulationError   -> slipstrip.SimulationError   (subclass of RuntimeError)
//   LocalSolveFailure -> slipstrip.LocalSolveFailure (subclass of RuntimeError)
//   io::OutputPathError -> slipstrip.OutputPathError (subclass of ValueError)
//   io::LockHeldError -> slipstrip.LockHeldError     (subclass of ValueError)
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "config/config.hpp"
#include "solver/simulation.hpp"
#include "friction/friction_law.hpp"
#include "io/file_lock.hpp"
#include "io/output_paths.hpp"
#include "slipstrip/version.hpp"

namespace py = pybind11;

// Defined in the other python/bindings/*.cpp files (one per library folder).
void bind_config(py::module_& m);
void bind_simulation(py::module_& m);
void bind_stability(py::module_& m);
void bind_events(py::module_& m);
void bind_io(py::module_& m);

PYBIND11_MODULE(_slipstrip, m) {
  m.doc() = "slipstrip C++ core (use the slipstrip package, not this module directly)";
  m.attr("code_version") = slipstrip::code_version;
  m.attr("git_hash") = slipstrip::git_hash;

  // Registered before the bindings so that they exist when docstrings mention them.
  // pybind11 tries translators newest-first and falls back to its defaults
  // (std::invalid_argument -> ValueError, std::runtime_error -> RuntimeError),
  // so these only take over for the project's own exception types.
  py::register_exception<slipstrip::ConfigError>(m, "ConfigError", PyExc_ValueError);
  py::register_exception<slipstrip::SimulationError>(m, "SimulationError", PyExc_RuntimeError);
  py::register_exception<slipstrip::LocalSolveFailure>(m, "LocalSolveFailure", PyExc_RuntimeError);
  py::register_exception<slipstrip::io::OutputPathError>(m, "OutputPathError", PyExc_ValueError);
  py::register_exception<slipstrip::io::LockHeldError>(m, "LockHeldError", PyExc_ValueError);

  bind_config(m);
  bind_simulation(m);
  bind_stability(m);
  bind_events(m);
  bind_io(m);
}

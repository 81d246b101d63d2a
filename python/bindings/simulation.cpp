// Simulation (solver/simulation.hpp) with zero-copy NumPy views of the interface
// fields, and run_simulation (solver/run.hpp) with a Python progress callback
// and Ctrl-C support.
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <chrono>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <span>
#include <string>

#include "solver/checkpoint.hpp"
#include "solver/run.hpp"
#include "kernels/history_convolution.hpp"
#include "solver/simulation.hpp"

namespace py = pybind11;
using slipstrip::RunProgress;
using slipstrip::RunResult;
using slipstrip::Simulation;

namespace {

using clock_type = std::chrono::steady_clock;

// A Simulation as Python holds it: advance() releases the GIL, so several
// Python threads can call into one object at once; without `busy` their steps
// interleaved inside one another and gave nonsense (slip rates of 1e37 m/s)
// with no error.  Every call that steps or reads the state takes `busy`, so
// calls from several threads are serialised at whole steps: n calls of
// advance(k) end exactly where one advance(n k) does.  The NumPy views are
// not covered (they are the solver's memory): read them when no other thread
// is stepping, or copy.
class PySimulation : public Simulation {
 public:
  explicit PySimulation(const slipstrip::SimulationConfig& config) : Simulation(config) {}
  std::mutex busy;
};

// A value of the simulation read with `busy` held.  Waiting for it happens
// with the GIL released: the thread that holds `busy` never waits for the
// GIL while it does, so there is no deadlock.
template <class R>
auto read_locked(R (Simulation::*get)() const) {
  return [get](PySimulation& sim) {
    py::gil_scoped_release release;
    std::lock_guard lock(sim.busy);
    return (static_cast<const Simulation&>(sim).*get)();
  };
}

// How often the GIL is taken back to look for Ctrl-C while C++ runs: often
// enough that an interrupt feels immediate, rarely enough that other Python
// threads are not slowed down and the solver is not either.
constexpr std::chrono::milliseconds signal_poll_interval{50};

std::span<const double> field_of(const Simulation& sim, const std::string& name) {
  if (name == "x") return sim.x();
  if (name == "slip") return sim.slip();
  if (name == "slip_rate") return sim.slip_rate();
  if (name == "state") return sim.state();
  if (name == "shear_stress") return sim.shear_stress();
  // Empty (a zero-length array) unless the normal stress varies (in-plane
  // dissimilar bodies, docs/bodies.md).
  if (name == "normal_stress") return sim.normal_stress();
  if (name == "effective_normal_stress") return sim.effective_normal_stress();
  if (name == "opening") return sim.opening();
  if (name == "opening_rate") return sim.opening_rate();
  throw std::invalid_argument("field = '" + name +
                              "' is unknown: allowed are x, slip, slip_rate, state, shear_stress, normal_stress, "
                              "effective_normal_stress, opening, opening_rate");
}

// A read-only 1-D array over the solver's own memory.  `owner` (the Python
// Simulation object) becomes the array's base, so the memory outlives every
// view; the vectors never reallocate after construction.  Read-only because the
// solver owns the data: writing into it would silently corrupt the run.
py::array field_view(py::object owner, const std::string& name) {
  const auto data = field_of(owner.cast<const PySimulation&>(), name);
  py::array view(py::dtype::of<double>(), {static_cast<py::ssize_t>(data.size())},
                 {static_cast<py::ssize_t>(sizeof(double))}, data.data(), owner);
  view.attr("setflags")(py::arg("write") = false);
  return view;
}

// Steps until n steps are done, releasing the GIL; Ctrl-C is honoured between
// steps (the simulation stays at a whole step) and raised as KeyboardInterrupt.
// `busy` is held for each stretch of steps between two signal checks.
void advance(PySimulation& sim, long long n) {
  if (n < 0) throw std::invalid_argument("n = " + std::to_string(n) + " is invalid: expected n >= 0 steps");
  long long done = 0;
  while (done < n) {
    {
      py::gil_scoped_release release;
      std::lock_guard lock(sim.busy);
      const auto start = clock_type::now();
      do {
        sim.step();
        ++done;
      } while (done < n && clock_type::now() - start < signal_poll_interval);
    }
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
  }
}

py::dict progress_dict(const RunProgress& p) {
  py::dict d;
  d["time"] = p.time;
  d["duration"] = p.duration;
  d["step"] = p.step;
  d["max_slip_rate"] = p.max_slip_rate;
  d["wall_seconds"] = p.wall_seconds;
  return d;
}

// run_simulation with the GIL released.  The progress callback and the signal
// check take the GIL back.  A Python exception from either (KeyboardInterrupt
// from Ctrl-C, or anything the callback raises) stops the run cleanly -- the
// file is closed with status "interrupted" -- and is then re-raised with the
// RunResult attached as `run_result`.
// `drive` is run_simulation or resume_simulation with the hooks filled in here.
RunResult run_with_hooks(const std::function<RunResult(const slipstrip::RunHooks&)>& drive,
                         py::object progress, double progress_interval) {
  if (!(progress_interval >= 0))
    throw std::invalid_argument("progress_interval = " + std::to_string(progress_interval) +
                                " is invalid: expected >= 0 seconds of wall time");
  std::optional<py::error_already_set> pending;  // touched only with the GIL held
  bool stop = false;
  auto last_poll = clock_type::now();

  slipstrip::RunHooks hooks;
  hooks.progress_interval = progress_interval;
  if (!progress.is_none()) {
    hooks.progress = [&](const RunProgress& p) {
      py::gil_scoped_acquire gil;
      if (pending) return;
      try {
        progress(progress_dict(p));
      } catch (py::error_already_set& e) {
        pending.emplace(std::move(e));
        stop = true;
      }
    };
  }
  hooks.stop_requested = [&] {
    if (stop) return true;
    const auto now = clock_type::now();
    if (now - last_poll < signal_poll_interval) return false;
    last_poll = now;
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) {
      pending.emplace();  // fetches (and clears) the KeyboardInterrupt
      stop = true;
    }
    return stop;
  };
  // A warning (a restart point without checksum) as a Python UserWarning.
  hooks.warning = [&](const std::string& text) {
    py::gil_scoped_acquire gil;
    if (PyErr_WarnEx(PyExc_UserWarning, text.c_str(), 1) != 0 && !pending) {
      pending.emplace();  // warnings turned into errors (-W error) stop the run
      stop = true;
    }
  };

  RunResult result;
  bool setup_cancelled = false;
  {
    py::gil_scoped_release release;
    try {
      result = drive(hooks);
    } catch (const slipstrip::SetupCancelled&) {
      if (!pending) throw;
      setup_cancelled = true;
    }
  }
  if (setup_cancelled) {
    // Stopped during the set-up (no file written): re-raise what stopped it
    // (KeyboardInterrupt from Ctrl-C).
    pending->restore();
    throw py::error_already_set();
  }
  if (pending) {
    try {
      pending->value().attr("run_result") = py::cast(result);
    } catch (py::error_already_set&) {
      // exception types without a __dict__ cannot carry it; the file has the status anyway
    }
    pending->restore();
    throw py::error_already_set();
  }
  return result;
}

RunResult run(const slipstrip::SimulationConfig& config, const std::string& output_path,
              py::object progress, double progress_interval, bool overwrite) {
  return run_with_hooks(
      [&](const slipstrip::RunHooks& hooks) {
        return slipstrip::run_simulation(config, output_path, hooks, overwrite);
      },
      progress, progress_interval);
}

// Continues an interrupted run from its restart point (solver/run.hpp).
RunResult resume(const std::string& output_path, py::object progress, double progress_interval) {
  return run_with_hooks(
      [&](const slipstrip::RunHooks& hooks) { return slipstrip::resume_simulation(output_path, hooks); },
      progress, progress_interval);
}

}  // namespace

void bind_simulation(py::module_& m) {
  py::class_<PySimulation>(m, "_Simulation")
      .def(py::init<const slipstrip::SimulationConfig&>(), py::arg("config"))
      .def("step",
           [](PySimulation& sim) {
             py::gil_scoped_release release;
             std::lock_guard lock(sim.busy);
             sim.step();
           },
           "Advance one time step dt.")
      .def("advance", &advance, py::arg("n"),
           "Advance n time steps with the GIL released.  Ctrl-C raises KeyboardInterrupt "
           "between steps; the simulation is then at a whole step (see step_index).  Calls "
           "from several threads are serialised: each step is whole, and the steps add up.")
      .def_property_readonly("x", [](py::object self) { return field_view(self, "x"); },
                             "Node positions [m] (read-only view of the solver's memory)")
      .def_property_readonly("slip", [](py::object self) { return field_view(self, "slip"); },
                             "Slip [m] (read-only view, updated in place by step())")
      .def_property_readonly("slip_rate", [](py::object self) { return field_view(self, "slip_rate"); },
                             "Slip rate [m/s] (read-only view, updated in place by step())")
      .def_property_readonly("state", [](py::object self) { return field_view(self, "state"); },
                             "State phi [s] (read-only view, updated in place by step())")
      .def_property_readonly("shear_stress", [](py::object self) { return field_view(self, "shear_stress"); },
                             "Shear stress [Pa] (read-only view, updated in place by step())")
      .def_property_readonly("normal_stress", [](py::object self) { return field_view(self, "normal_stress"); },
                             "Compressive normal stress [Pa] (read-only view); empty unless the normal stress "
                             "varies (in-plane dissimilar bodies)")
      .def_property_readonly("effective_normal_stress",
                             [](py::object self) { return field_view(self, "effective_normal_stress"); },
                             "Effective normal stress the friction sees [Pa] (read-only view); empty unless "
                             "the normal stress varies")
      .def_property_readonly("opening", [](py::object self) { return field_view(self, "opening"); },
                             "Opening (gap between the faces, jump of the normal displacement) [m] (read-only "
                             "view); 0 where the faces are in contact; empty unless the normal stress varies")
      .def_property_readonly("opening_rate", [](py::object self) { return field_view(self, "opening_rate"); },
                             "Rate of the opening [m/s] (read-only view); empty unless the normal stress varies")
      .def("_field_address",
           [](const PySimulation& sim, const std::string& name) {
             return reinterpret_cast<std::uintptr_t>(field_of(sim, name).data());
           },
           py::arg("name"), "Address of the C++ vector behind a field (for zero-copy checks).")
      .def_property_readonly("time", read_locked(&Simulation::time), "t [s]")
      .def_property_readonly("step_index", read_locked(&Simulation::step_index))
      .def_property_readonly("time_step", &Simulation::time_step, "dt [s]")
      .def_property_readonly("dx", &Simulation::dx, "[m]")
      .def_property_readonly("radiation_damping", &Simulation::radiation_damping, "mu / (2 c_s) [Pa s/m]")
      .def_property_readonly("reference_shear_stress", &Simulation::reference_shear_stress, "tau_0 [Pa]")
      .def_property_readonly("max_slip_rate", read_locked(&Simulation::max_slip_rate), "[m/s]")
      .def_property_readonly("mean_slip", read_locked(&Simulation::mean_slip), "[m]")
      .def_property_readonly("mean_shear_stress", read_locked(&Simulation::mean_shear_stress), "[Pa]")
      .def_property_readonly("loading_shear_stress", read_locked(&Simulation::loading_shear_stress),
                             "tau_0(t) [Pa] of loading.drive = 'mean_slip_rate' at the last step; NaN otherwise")
      .def_property_readonly("_native_config", [](const PySimulation& sim) { return sim.config(); });

  py::class_<RunResult>(m, "RunResult")
      .def_readonly("status", &RunResult::status, "'completed', 'interrupted' or 'diverged: ...'")
      .def_readonly("simulated_time", &RunResult::simulated_time, "[s]")
      .def_readonly("steps", &RunResult::steps)
      .def_readonly("wall_seconds", &RunResult::wall_seconds, "[s]")
      .def_readonly("time_step", &RunResult::time_step, "[s]")
      .def("__repr__", [](const RunResult& r) {
        return "RunResult(status=" + py::repr(py::str(r.status)).cast<std::string>() +
               ", steps=" + std::to_string(r.steps) +
               ", simulated_time=" + py::repr(py::float_(r.simulated_time)).cast<std::string>() +
               ", wall_seconds=" + py::repr(py::float_(r.wall_seconds)).cast<std::string>() + ")";
      });

  m.def("_run", &run, py::arg("config"), py::arg("output_path"), py::arg("progress") = py::none(),
        py::arg("progress_interval") = 0.5, py::arg("overwrite") = false);
  m.def("checkpoint_path", &slipstrip::checkpoint_path, py::arg("run_path"), "RUN.h5 -> RUN.h5.restart");
  m.def("run_lock_path", &slipstrip::run_lock_path, py::arg("run_path"),
        "RUN.h5 -> RUN.h5.lock (one process per run, solver/checkpoint.hpp)");
  m.def("_resume", &resume, py::arg("output_path"), py::arg("progress") = py::none(),
        py::arg("progress_interval") = 0.5);
}

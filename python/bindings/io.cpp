// io/: the output-path rule, one-line messages and the advisory lock, so
// Python commands apply exactly the rule and the text of the C++ CLI
// (python/slipstrip/paths.py wraps them).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include "io/file_lock.hpp"
#include "io/messages.hpp"
#include "io/output_paths.hpp"

namespace py = pybind11;

void bind_io(py::module_& m) {
  m.def(
      "check_output_paths",
      [](const std::vector<std::tuple<std::string, std::string, bool>>& outputs,
         const std::vector<std::string>& inputs, bool overwrite, const std::string& overwrite_flag) {
        std::vector<slipstrip::io::OutputPath> paths;
        for (const auto& [option, path, directory] : outputs)
          paths.push_back({option, path,
                           directory ? slipstrip::io::OutputPath::Kind::directory
                                     : slipstrip::io::OutputPath::Kind::file});
        slipstrip::io::check_output_paths(paths, inputs, overwrite, overwrite_flag);
      },
      py::arg("outputs"), py::arg("inputs"), py::arg("overwrite"), py::arg("overwrite_flag") = "--overwrite",
      "outputs: [(option, path, is_directory)]; raises OutputPathError (io/output_paths.hpp)");
  m.attr("max_message_chars") = slipstrip::io::kMaxMessageChars;
  m.def("one_line", [](const std::string& text, std::size_t max_chars) { return slipstrip::io::one_line(text, max_chars); }, py::arg("text"),
        py::arg("max_chars") = slipstrip::io::kMaxMessageChars, "io/messages.hpp");

  // A lock held until release() (or garbage collection); the process ending
  // releases it too (io/file_lock.hpp).
  py::class_<slipstrip::io::FileLock>(m, "_FileLock")
      .def(py::init<const std::string&, const std::string&>(), py::arg("path"), py::arg("what"))
      .def_property_readonly("path", &slipstrip::io::FileLock::path);
}

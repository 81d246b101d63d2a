#include "kernels/kernel_cache.hpp"

#include <hdf5.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <vector>

#include "io/attributes.hpp"
#include "io/datasets.hpp"
#include "io/hdf5.hpp"

namespace slipstrip {
namespace {

constexpr const char* kFormat = "slipstrip strip kernels v1";

std::string full_precision(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

// FNV-1a: stable across runs and platforms (std::hash is not).
std::string fnv1a_hex(const std::string& text) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

}  // namespace

std::string strip_kernel_key(const ElasticMaterial& m, double strip_height, double length,
                             int nodes, double time_step) {
  return std::string(kFormat) + "; shear_modulus=" + full_precision(m.shear_modulus) +
         "; poisson_ratio=" + full_precision(m.poisson_ratio) + "; density=" +
         full_precision(m.density) + "; plane=" +
         std::string(kPlaneConditionNames[static_cast<std::size_t>(m.plane)]) +
         "; height=" + full_precision(strip_height) + "; length=" + full_precision(length) +
         "; nodes=" + std::to_string(nodes) + "; time_step=" + full_precision(time_step);
}

StripKernels load_or_compute_strip_kernels(const std::string& cache_dir,
                                           const ElasticMaterial& material, double strip_height,
                                           double length, int nodes, double time_step,
                                           KernelSource* source, const CancelCheck& cancelled) {
  namespace fs = std::filesystem;
  const std::string key = strip_kernel_key(material, strip_height, length, nodes, time_step);
  const fs::path entry = fs::path(cache_dir) / ("strip_kernels_" + fnv1a_hex(key) + ".h5");
  // Every failure below becomes an exception with a message (or a silent
  // recompute): keep HDF5 from printing its own error stack.
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);

  if (fs::exists(entry)) {
    // Entries appear atomically (rename), so an existing file is complete.
    if (H5Fis_hdf5(entry.c_str()) <= 0)
      throw std::invalid_argument("kernel cache entry '" + entry.string() + "' is not an HDF5 file");
    const io::Handle file = io::open_file(entry.string(), io::FileAccess::read_only);
    if (io::read_string_attribute(file, "key") == key) {
      StripKernels k;
      k.time_step = time_step;
      const auto echo = io::read_vector<std::uint64_t>(file, "echo_steps");
      const auto first = io::read_vector<std::uint64_t>(file, "first_oscillator");
      if (echo.size() != 1)
        throw std::runtime_error("kernel cache entry " + entry.string() + " is malformed");
      k.echo_steps = echo[0];
      k.first_oscillator.assign(first.begin(), first.end());
      k.phase = io::read_vector<double>(file, "phase");
      k.weight = io::read_vector<double>(file, "weight");
      if (source) *source = KernelSource::cache;
      return k;
    }
    // Same hash, other inputs: never reuse, and leave the entry alone.
    if (source) *source = KernelSource::computed;
    return compute_strip_kernels(material, strip_height, length, nodes, time_step, cancelled);
  }

  StripKernels k = compute_strip_kernels(material, strip_height, length, nodes, time_step, cancelled);
  if (source) *source = KernelSource::computed;
  std::error_code ec;
  fs::create_directories(cache_dir, ec);
  if (ec)
    throw std::invalid_argument("output.kernel_cache = '" + cache_dir +
                                "': cannot create the directory (" + ec.message() + ")");
  // Write under a private name, then rename: concurrent runs of a scan never
  // see a partial entry, and two writers of the same entry write the same data.
  const fs::path partial = entry.string() + ".partial." + std::to_string(getpid());
  {
    io::Handle file = io::create_file(partial.string());
    io::write_attribute(file, "key", key);
    io::write_attribute(file, "units", "phase: rad (omega dt); weight: Pa/m");
    const std::vector<std::uint64_t> echo{k.echo_steps};
    const std::vector<std::uint64_t> first(k.first_oscillator.begin(), k.first_oscillator.end());
    io::write_vector(file, "echo_steps", echo);
    io::write_vector(file, "first_oscillator", first);
    io::write_vector(file, "phase", k.phase);
    io::write_vector(file, "weight", k.weight);
    io::close_file(file);
  }
  fs::rename(partial, entry, ec);
  if (ec) fs::remove(partial, ec);  // best effort: the kernels are right either way
  return k;
}

}  // namespace slipstrip

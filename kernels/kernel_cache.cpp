#include "kernels/kernel_cache.hpp"

#include <hdf5.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <vector>

#include "core/hdf5_handle.hpp"

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

template <class T>
void write_vector(hid_t group, const char* name, const std::vector<T>& v, hid_t type) {
  const hsize_t n = v.size();
  hdf5::Handle space(H5Screate_simple(1, &n, nullptr), "create dataspace");
  hdf5::Handle set(H5Dcreate2(group, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                   std::string("create dataset ") + name);
  if (n) hdf5::check(H5Dwrite(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), name);
}

template <class T>
std::vector<T> read_vector(hid_t group, const char* name, hid_t type) {
  hdf5::Handle set(H5Dopen2(group, name, H5P_DEFAULT), std::string("open dataset ") + name);
  hdf5::Handle space(H5Dget_space(set), "get dataspace");
  hsize_t n = 0;
  H5Sget_simple_extent_dims(space, &n, nullptr);
  std::vector<T> v(n);
  if (n) hdf5::check(H5Dread(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), name);
  return v;
}

}  // namespace

std::string strip_kernel_key(const ElasticMaterial& m, double strip_height, double length,
                             int nodes, double time_step) {
  return std::string(kFormat) + "; shear_modulus=" + full_precision(m.shear_modulus) +
         "; poisson_ratio=" + full_precision(m.poisson_ratio) + "; density=" +
         full_precision(m.density) + "; plane=" +
         (m.plane == PlaneCondition::strain ? "strain" : "stress") +
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
    hdf5::Handle file(H5Fopen(entry.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT),
                      "open kernel cache entry " + entry.string());
    if (hdf5::read_string_attribute(file, "key") == key) {
      StripKernels k;
      k.time_step = time_step;
      const auto echo = read_vector<unsigned long long>(file, "echo_steps", H5T_NATIVE_ULLONG);
      const auto first = read_vector<unsigned long long>(file, "first_oscillator", H5T_NATIVE_ULLONG);
      if (echo.size() != 1)
        throw std::runtime_error("kernel cache entry " + entry.string() + " is malformed");
      k.echo_steps = echo[0];
      k.first_oscillator.assign(first.begin(), first.end());
      k.phase = read_vector<double>(file, "phase", H5T_NATIVE_DOUBLE);
      k.weight = read_vector<double>(file, "weight", H5T_NATIVE_DOUBLE);
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
    hdf5::Handle file(H5Fcreate(partial.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT),
                      "create kernel cache entry " + partial.string());
    hdf5::write_attribute(file, "key", key);
    hdf5::write_attribute(file, "units", "phase: rad (omega dt); weight: Pa/m");
    const std::vector<unsigned long long> echo{k.echo_steps};
    const std::vector<unsigned long long> first(k.first_oscillator.begin(), k.first_oscillator.end());
    write_vector(file, "echo_steps", echo, H5T_NATIVE_ULLONG);
    write_vector(file, "first_oscillator", first, H5T_NATIVE_ULLONG);
    write_vector(file, "phase", k.phase, H5T_NATIVE_DOUBLE);
    write_vector(file, "weight", k.weight, H5T_NATIVE_DOUBLE);
  }
  fs::rename(partial, entry, ec);
  if (ec) fs::remove(partial, ec);  // best effort: the kernels are right either way
  return k;
}

}  // namespace slipstrip

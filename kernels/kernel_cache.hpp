#pragma once
// HDF5 cache of the strip kernels, so that a parameter scan computes them once.
//
// The key is the canonical text of every input the kernels depend on
// (material, plane condition, H, L, N, dt) written at full precision, plus a
// format version; each entry is a group named by a hash of the key that also
// stores the full key text, which is compared on read (no silent collisions).
// The kernels are closed-form and cheap (slipstrip bench reports the setup
// time), so the cache matters for large N and thick strips, and for scans.
#include <string>

#include "kernels/elastic_material.hpp"
#include "kernels/history_convolution.hpp"

namespace slipstrip {

std::string strip_kernel_key(const ElasticMaterial& material, double strip_height, double length,
                             int nodes, double time_step);

enum class KernelSource { computed, cache };

// Reads the kernels from `cache_path` if an entry for these inputs exists;
// otherwise computes them and adds them to the file (created if needed).
// A file that is not HDF5 is an error naming the path.  Concurrent runs of a
// scan may share one cache: a file locked by another process, or an entry
// created by it first, means "compute and do not store" (the kernels are the
// same either way), never a failed run.
StripKernels load_or_compute_strip_kernels(const std::string& cache_path,
                                           const ElasticMaterial& material, double strip_height,
                                           double length, int nodes, double time_step,
                                           KernelSource* source = nullptr);

}  // namespace slipstrip

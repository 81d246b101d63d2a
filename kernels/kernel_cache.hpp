#pragma once
// HDF5 cache of the strip kernels, so that a parameter scan computes them once.
//
// The cache is a directory with one HDF5 file per set of inputs.  The key is
// the canonical text of every input the kernels depend on (material, plane
// condition, H, L, N, dt) at full precision plus a format version; the file is
// named by a hash of it and stores the full key text, which is compared on read
// (no silent collisions).  Entries are written under a private name and
// renamed into place, so concurrent runs never see a partial entry.
// The kernels are closed-form and cheap (slipstrip bench reports the set-up
// time): the cache is a convenience for large N, thick strips and scans.
#include <string>

#include "kernels/elastic_material.hpp"
#include "kernels/history_convolution.hpp"

namespace slipstrip {

std::string strip_kernel_key(const ElasticMaterial& material, double strip_height, double length,
                             int nodes, double time_step);

enum class KernelSource { computed, cache };

// Reads the kernels from the cache directory if an entry for these inputs
// exists; otherwise computes them and adds the entry (the directory is created
// if needed).  An entry that is not HDF5, or a directory that cannot be
// created, is an error naming the path.
StripKernels load_or_compute_strip_kernels(const std::string& cache_dir,
                                           const ElasticMaterial& material, double strip_height,
                                           double length, int nodes, double time_step,
                                           KernelSource* source = nullptr,
                                           const CancelCheck& cancelled = {});

}  // namespace slipstrip

#pragma once
// Large operator arrays on transparent huge pages (2 MiB) where the system
// grants them on request (Linux, /sys/kernel/mm/transparent_hugepage/enabled
// = madvise or always).
//
// Why: a block history operator on a large 2D interface holds gigabytes whose
// per-step accesses are a few cache lines per Fourier mode, each mode's on its
// own 4 KiB pages (docs/3d.md section 5): on 4 KiB pages nearly every such
// access is a TLB miss, and the hardware prefetchers stop at every page
// boundary.  On 2 MiB pages one TLB entry covers 512 times as much.  The
// arithmetic and its order are unchanged: the results are bit for bit the same.
//
// assign_on_huge_pages(v, n, value) is v.assign(n, value), with the new
// storage advised (madvise MADV_HUGEPAGE) before its first touch, so the
// pages are faulted in as huge pages rather than collapsed later.  Where the
// advice is unavailable or refused it is plain 4 KiB memory: only the speed
// differs.
#include <cstddef>
#include <cstdint>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace slipstrip {

// Advise the whole 2 MiB pages inside [data, data + bytes) (none for a range
// shorter than one).
inline void advise_huge_pages([[maybe_unused]] void* data, [[maybe_unused]] std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t page = std::uintptr_t{2} << 20;
  const auto begin = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t first = (begin + page - 1) & ~(page - 1), last = (begin + bytes) & ~(page - 1);
  if (last > first) madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);  // advice only
#endif
}

template <class T>
void assign_on_huge_pages(std::vector<T>& v, std::size_t n, const T& value) {
  std::vector<T>().swap(v);  // release the old storage, so reserve allocates afresh
  v.reserve(n);              // large blocks come from mmap, untouched
  advise_huge_pages(v.data(), n * sizeof(T));
  v.assign(n, value);  // first touch: within the capacity, no reallocation
}

}  // namespace slipstrip

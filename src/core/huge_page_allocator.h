#pragma once
/// A std::allocator replacement for large, randomly accessed arrays (BVH nodes and leaves): allocations of 256 KiB
/// and more are rounded up to whole 2 MiB pages, 2 MiB aligned and advised to the kernel as transparent huge pages
/// (madvise(MADV_HUGEPAGE), as Embree does), so incoherent traversal of a large tree misses the TLB far less often
/// and a build takes one page fault per 2 MiB it touches. Smaller ones are 64-byte aligned (whole cache lines).
#include <sys/mman.h>

#include <cstddef>
#include <cstdlib>
#include <new>
#include <vector>

namespace pt {

/// Freed huge-page blocks kept for the next allocation of about the same size. Why: every BVH build allocates and
/// frees some 10-30 MB of temporaries (references, node arenas, the collapse plan) and its output, and memory
/// returned to the kernel comes back as fresh pages that the kernel must zero, and on this project's VMs the host
/// too (free-page reporting hands freed guest pages back to the host): a fifth of a bunny build's time went to
/// clear_page in perf. A viewer rebuilds its tree on every mesh load or edit, and a script builds many. Blocks are
/// whole huge pages and are reused for requests of exactly their size (a rebuild asks for the same sizes again), so
/// nothing is wasted; the cache holds at most kMaxBytes and drops its oldest blocks beyond that.
namespace huge_block_cache {
inline constexpr size_t kMaxBytes = size_t(256) << 20;
/// A cached block of exactly `bytes` (a multiple of the huge page), removed from the cache, or nullptr.
void* take(size_t bytes);
/// Keeps the block of `bytes` (as allocated), freeing the oldest blocks beyond kMaxBytes.
void give(void* p, size_t bytes);
/// Bytes held now (for tests).
size_t held_bytes();
/// Frees every cached block (benchmarks that time a cold build; a program done with large meshes).
void release_all();
}  // namespace huge_block_cache

template <class T>
struct HugePageAllocator {
  using value_type = T;
  static constexpr size_t kHugePage = size_t(2) << 20;
  /// From this size on an allocation is rounded up to whole huge pages: a 1 MiB array in 4 KiB pages costs 256
  /// page faults (about 3 ms on this VM), in one huge page one fault and 1 MiB more of resident memory.
  static constexpr size_t kHugeThreshold = size_t(256) << 10;

  HugePageAllocator() = default;
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>&) noexcept {}

  T* allocate(size_t n) {
    const size_t bytes = n * sizeof(T);
    const size_t align = bytes >= kHugeThreshold ? kHugePage : 64;
    const size_t rounded = (bytes + align - 1) / align * align;
    if (align == kHugePage)
      if (void* cached = huge_block_cache::take(rounded)) return static_cast<T*>(cached);
    void* p = std::aligned_alloc(align, rounded == 0 ? align : rounded);
    if (!p) throw std::bad_alloc();
#ifdef MADV_HUGEPAGE
    if (align == kHugePage) madvise(p, rounded, MADV_HUGEPAGE);  // advice only: failure is harmless
#endif
    return static_cast<T*>(p);
  }
  /// Huge blocks go to the cache, with the size allocate gave them.
  void deallocate(T* p, size_t n) noexcept {
    const size_t bytes = n * sizeof(T);
    if (bytes >= kHugeThreshold) huge_block_cache::give(p, (bytes + kHugePage - 1) / kHugePage * kHugePage);
    else std::free(p);
  }

  template <class U>
  bool operator==(const HugePageAllocator<U>&) const noexcept { return true; }
};

/// A vector in huge pages. Also for the build's large temporaries: every first touch of a 4 KiB page is a page
/// fault, which on a virtual machine costs about 10 us; a 1M-triangle build touches 100k pages (a third of its
/// time went to faults), in 2 MiB pages a few hundred.
template <class T>
using HugeVector = std::vector<T, HugePageAllocator<T>>;

}  // namespace pt

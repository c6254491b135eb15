#pragma once
/// A std::allocator replacement for large, randomly accessed arrays (BVH nodes and leaves): allocations of 2 MiB
/// and more are 2 MiB aligned and advised to the kernel as transparent huge pages (madvise(MADV_HUGEPAGE), as
/// Embree does), so incoherent traversal of a large tree misses the TLB far less often. Smaller ones are 64-byte
/// aligned (whole cache lines).
#include <sys/mman.h>

#include <cstddef>
#include <cstdlib>
#include <new>
#include <vector>

namespace pt {

template <class T>
struct HugePageAllocator {
  using value_type = T;
  static constexpr size_t kHugePage = size_t(2) << 20;

  HugePageAllocator() = default;
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>&) noexcept {}

  T* allocate(size_t n) {
    const size_t bytes = n * sizeof(T);
    const size_t align = bytes >= kHugePage ? kHugePage : 64;
    const size_t rounded = (bytes + align - 1) / align * align;
    void* p = std::aligned_alloc(align, rounded == 0 ? align : rounded);
    if (!p) throw std::bad_alloc();
#ifdef MADV_HUGEPAGE
    if (align == kHugePage) madvise(p, rounded, MADV_HUGEPAGE);  // advice only: failure is harmless
#endif
    return static_cast<T*>(p);
  }
  void deallocate(T* p, size_t) noexcept { std::free(p); }

  template <class U>
  bool operator==(const HugePageAllocator<U>&) const noexcept { return true; }
};

/// A vector in huge pages. Also for the build's large temporaries: every first touch of a 4 KiB page is a page
/// fault, which on a virtual machine costs about 10 us; a 1M-triangle build touches 100k pages (a third of its
/// time went to faults), in 2 MiB pages a few hundred.
template <class T>
using HugeVector = std::vector<T, HugePageAllocator<T>>;

}  // namespace pt

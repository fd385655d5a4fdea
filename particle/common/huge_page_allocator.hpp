#pragma once
// An allocator for the large, randomly accessed arrays of the particle engines (states, event slots, cell
// tables). Blocks of 2 MiB or more are aligned to 2 MiB and marked MADV_HUGEPAGE, so that Linux backs them
// with transparent huge pages where it allows (`/sys/kernel/mm/transparent_hugepage/enabled` = madvise or
// always): random access over 10^8 bytes then misses the TLB far less often. Elsewhere it is plain
// aligned allocation.
#include <cstddef>
#include <cstdlib>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace aggkit {

template <class T>
struct HugePageAllocator {
  using value_type = T;
  static constexpr std::size_t huge_page = std::size_t(2) << 20;

  HugePageAllocator() = default;
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>&) {}

  T* allocate(std::size_t n) {
    const std::size_t bytes = n * sizeof(T);
    if (bytes < huge_page) {
      void* p = ::operator new(bytes, std::align_val_t(alignof(T) > 64 ? alignof(T) : 64));
      return static_cast<T*>(p);
    }
    const std::size_t rounded = (bytes + huge_page - 1) / huge_page * huge_page;
    void* p = std::aligned_alloc(huge_page, rounded);
    if (!p) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    madvise(p, rounded, MADV_HUGEPAGE);
#endif
    return static_cast<T*>(p);
  }
  void deallocate(T* p, std::size_t n) {
    if (n * sizeof(T) < huge_page) ::operator delete(p, std::align_val_t(alignof(T) > 64 ? alignof(T) : 64));
    else std::free(p);
  }
  template <class U>
  bool operator==(const HugePageAllocator<U>&) const { return true; }
};

}  // namespace aggkit

// An allocator that takes whole pages from the OS and gives them back on free. For buffers that
// are freed while the program's peak memory is still building up: glibc keeps freed blocks below
// its (self-raising) mmap threshold in its heap, where they still count as resident.
#pragma once
#include <sys/mman.h>

#include <cstddef>
#include <new>

namespace froth {

template <class T>
struct PageAllocator {
  using value_type = T;
  PageAllocator() = default;
  template <class U>
  PageAllocator(const PageAllocator<U>&) {}

  T* allocate(size_t n) {
    void* p = mmap(nullptr, n * sizeof(T), PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) throw std::bad_alloc();
    return static_cast<T*>(p);
  }
  void deallocate(T* p, size_t n) { munmap(p, n * sizeof(T)); }

  template <class U>
  bool operator==(const PageAllocator<U>&) const { return true; }
};

}  // namespace froth

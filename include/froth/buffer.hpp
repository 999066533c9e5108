// The storage of PolyMesh's large arrays (froth/mesh.hpp): a std::vector whose allocator leaves
// new elements uninitialised. Part of those arrays' type, so public; nothing else uses it.
#pragma once
#include <memory>
#include <utility>
#include <vector>

namespace froth {

// std::vector's allocator, except that resize() leaves new elements of trivial types
// uninitialised: the mesh's large arrays are sized first and filled in parallel, and pages that
// are not yet written then cost no memory.
template <class T>
struct UninitializedAllocator : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = UninitializedAllocator<U>;
  };
  UninitializedAllocator() = default;
  template <class U>
  UninitializedAllocator(const UninitializedAllocator<U>&) {}
  template <class U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};
template <class T>
using Buffer = std::vector<T, UninitializedAllocator<T>>;

}  // namespace froth

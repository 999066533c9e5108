// Plain values on the wire between ranks (froth/communicator.hpp): an array of trivially
// copyable records as bytes, and back.
#pragma once
#include <cstring>
#include <type_traits>
#include <vector>

#include "froth/communicator.hpp"

namespace froth {

template <class T>
Communicator::Bytes to_bytes(const T* data, size_t n) {
  static_assert(std::is_trivially_copyable_v<T>);
  Communicator::Bytes out(n * sizeof(T));
  if (n) std::memcpy(out.data(), data, out.size());
  return out;
}

template <class T>
std::vector<T> from_bytes(const Communicator::Bytes& b) {
  static_assert(std::is_trivially_copyable_v<T>);
  std::vector<T> out(b.size() / sizeof(T));
  if (!out.empty()) std::memcpy(static_cast<void*>(out.data()), b.data(), out.size() * sizeof(T));
  return out;
}

}  // namespace froth

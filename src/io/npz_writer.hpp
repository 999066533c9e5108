// NumPy's .npz: a zip archive (stored, not compressed) of .npy arrays, which numpy.load reads
// by name with no help from froth. Arrays are little-endian int64 or float64, C order.
#pragma once
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

namespace froth {

class NpzWriter {
 public:
  explicit NpzWriter(std::ostream& out) : out_(out) {}
  // Appends NAME.npy with the given shape (rows, or rows x columns when columns > 0).
  void add(const std::string& name, const std::vector<double>& values, size_t columns = 0);
  void add(const std::string& name, const std::vector<int64_t>& values, size_t columns = 0);
  void add(const std::string& name, const std::vector<std::string>& values);  // '<U' strings (UTF-8 bytes as code points)
  void finish();  // the central directory; call once, last

 private:
  void add_raw(const std::string& name, const std::string& descr, const char* data, size_t bytes, size_t rows,
               size_t columns);
  struct Entry {
    std::string name;
    uint32_t crc;
    uint64_t size, offset;
  };
  std::ostream& out_;
  std::vector<Entry> entries_;
  uint64_t offset_ = 0;
};

}  // namespace froth

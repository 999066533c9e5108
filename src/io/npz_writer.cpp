#include "io/npz_writer.hpp"

#include <zlib.h>

#include <algorithm>
#include <cstring>

#include <fmt/format.h>

namespace froth {
namespace {

constexpr uint32_t kMax32 = 0xFFFFFFFFu;

template <class T>
void put(std::string& s, T v) {  // little-endian, as x86 and the zip format are
  char bytes[sizeof(T)];
  std::memcpy(bytes, &v, sizeof(T));
  s.append(bytes, sizeof(T));
}

uint32_t crc_of(uint32_t crc, const char* data, size_t bytes) {
  while (bytes > 0) {  // zlib takes at most 2^32 - 1 bytes a call
    const uInt n = uInt(std::min<size_t>(bytes, 1u << 30));
    crc = uint32_t(crc32(crc, reinterpret_cast<const Bytef*>(data), n));
    data += n, bytes -= n;
  }
  return crc;
}

// The .npy header (format 1.0), padded so that the data starts on a 64-byte boundary.
std::string npy_header(const std::string& descr, size_t rows, size_t columns) {
  std::string dict = fmt::format("{{'descr': '{}', 'fortran_order': False, 'shape': ({},{}), }}", descr, rows,
                                 columns ? fmt::format(" {}", columns) : "");
  const size_t unpadded = 10 + dict.size() + 1;
  dict.append((64 - unpadded % 64) % 64, ' ');
  dict += '\n';
  std::string h = "\x93NUMPY";
  h += char(1), h += char(0);
  put(h, uint16_t(dict.size()));
  return h + dict;
}

}  // namespace

void NpzWriter::add(const std::string& name, const std::vector<double>& v, size_t columns) {
  add_raw(name, "<f8", reinterpret_cast<const char*>(v.data()), v.size() * sizeof(double),
          columns ? v.size() / columns : v.size(), columns);
}

void NpzWriter::add(const std::string& name, const std::vector<int64_t>& v, size_t columns) {
  add_raw(name, "<i8", reinterpret_cast<const char*>(v.data()), v.size() * sizeof(int64_t),
          columns ? v.size() / columns : v.size(), columns);
}

void NpzWriter::add(const std::string& name, const std::vector<std::string>& v) {
  size_t width = 1;
  for (const std::string& s : v) width = std::max(width, s.size());
  std::vector<uint32_t> codes(width * v.size(), 0);  // fixed-width UTF-32, zero-padded
  for (size_t k = 0; k < v.size(); ++k)
    for (size_t j = 0; j < v[k].size(); ++j) codes[k * width + j] = static_cast<unsigned char>(v[k][j]);
  add_raw(name, fmt::format("<U{}", width), reinterpret_cast<const char*>(codes.data()), codes.size() * 4, v.size(), 0);
}

void NpzWriter::add_raw(const std::string& array, const std::string& descr, const char* data, size_t bytes,
                        size_t rows, size_t columns) {
  const std::string name = array + ".npy";
  const std::string head = npy_header(descr, rows, columns);
  const uint64_t size = head.size() + bytes;
  const uint32_t crc = crc_of(crc_of(0, head.data(), head.size()), data, bytes);
  // Entries past 4 GiB, or starting past it, carry their sizes in a zip64 extra field.
  const bool zip64 = size >= kMax32 || offset_ >= kMax32;
  std::string h;
  put(h, uint32_t(0x04034b50));
  put(h, uint16_t(zip64 ? 45 : 20));  // version needed
  put(h, uint16_t(0));                 // flags
  put(h, uint16_t(0));                 // stored
  put(h, uint16_t(0));                 // time
  put(h, uint16_t(0x21));              // date: 1980-01-01
  put(h, crc);
  put(h, uint32_t(zip64 ? kMax32 : size));
  put(h, uint32_t(zip64 ? kMax32 : size));
  put(h, uint16_t(name.size()));
  put(h, uint16_t(zip64 ? 20 : 0));
  h += name;
  if (zip64) {
    put(h, uint16_t(1));
    put(h, uint16_t(16));
    put(h, size);
    put(h, size);
  }
  entries_.push_back({name, crc, size, offset_});
  out_.write(h.data(), std::streamsize(h.size()));
  out_.write(head.data(), std::streamsize(head.size()));
  out_.write(data, std::streamsize(bytes));
  offset_ += h.size() + size;
}

void NpzWriter::finish() {
  std::string cd;
  for (const Entry& e : entries_) {
    const bool zip64 = e.size >= kMax32 || e.offset >= kMax32;
    put(cd, uint32_t(0x02014b50));
    put(cd, uint16_t(45));  // made by
    put(cd, uint16_t(zip64 ? 45 : 20));
    put(cd, uint16_t(0));
    put(cd, uint16_t(0));
    put(cd, uint16_t(0));
    put(cd, uint16_t(0x21));
    put(cd, e.crc);
    put(cd, uint32_t(zip64 ? kMax32 : e.size));
    put(cd, uint32_t(zip64 ? kMax32 : e.size));
    put(cd, uint16_t(e.name.size()));
    put(cd, uint16_t(zip64 ? 28 : 0));
    put(cd, uint16_t(0));  // comment
    put(cd, uint16_t(0));  // disk
    put(cd, uint16_t(0));  // internal attributes
    put(cd, uint32_t(0));  // external attributes
    put(cd, uint32_t(zip64 ? kMax32 : e.offset));
    cd += e.name;
    if (zip64) {
      put(cd, uint16_t(1));
      put(cd, uint16_t(24));
      put(cd, e.size);
      put(cd, e.size);
      put(cd, e.offset);
    }
  }
  const uint64_t cd_offset = offset_, cd_size = cd.size();
  if (cd_offset >= kMax32 || entries_.size() >= 0xFFFF) {  // zip64 end of central directory and its locator
    put(cd, uint32_t(0x06064b50));
    put(cd, uint64_t(44));
    put(cd, uint16_t(45));
    put(cd, uint16_t(45));
    put(cd, uint32_t(0));
    put(cd, uint32_t(0));
    put(cd, uint64_t(entries_.size()));
    put(cd, uint64_t(entries_.size()));
    put(cd, cd_size);
    put(cd, cd_offset);
    put(cd, uint32_t(0x07064b50));
    put(cd, uint32_t(0));
    put(cd, cd_offset + cd_size);
    put(cd, uint32_t(1));
  }
  const bool big = cd_offset >= kMax32 || entries_.size() >= 0xFFFF;
  put(cd, uint32_t(0x06054b50));
  put(cd, uint16_t(0));
  put(cd, uint16_t(0));
  put(cd, uint16_t(big ? 0xFFFF : entries_.size()));
  put(cd, uint16_t(big ? 0xFFFF : entries_.size()));
  put(cd, uint32_t(big ? kMax32 : cd_size));
  put(cd, uint32_t(big ? kMax32 : cd_offset));
  put(cd, uint16_t(0));
  out_.write(cd.data(), std::streamsize(cd.size()));
}

}  // namespace froth

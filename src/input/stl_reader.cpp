// STL reader: binary and ASCII (several `solid` blocks allowed). Vertices with bit-equal
// coordinates are merged; nothing is snapped or repaired here.
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <unordered_map>

#include <fmt/format.h>

#include "froth/domain.hpp"
#include "froth/error.hpp"
#include "input/input_file.hpp"
#include "input/vertex_merger.hpp"

namespace froth {
namespace {

void check_finite(const std::string& file, size_t tri, Vec3 p) {
  if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
    fail(ErrorKind::InvalidInput,
         fmt::format("{}: triangle {} has a non-finite coordinate ({}, {}, {})", file, tri, p.x, p.y, p.z));
}

TriangleSurface read_binary(const std::string& file, const std::string& bytes) {
  uint32_t n;
  std::memcpy(&n, bytes.data() + 80, 4);
  TriangleSurface s;
  VertexMerger merge(s);
  s.triangles.reserve(n);
  for (uint32_t t = 0; t < n; ++t) {
    const char* rec = bytes.data() + 84 + size_t(t) * 50;
    std::array<int32_t, 3> tri{};
    for (int v = 0; v < 3; ++v) {
      float xyz[3];
      std::memcpy(xyz, rec + 12 + 12 * v, 12);
      Vec3 p{xyz[0], xyz[1], xyz[2]};
      check_finite(file, t, p);
      tri[v] = merge.add(p);
    }
    s.triangles.push_back(tri);
  }
  return s;
}

TriangleSurface read_ascii(const std::string& file, const std::string& bytes) {
  TriangleSurface s;
  VertexMerger merge(s);
  std::istringstream in(bytes);
  std::string word;
  std::array<int32_t, 3> tri{};
  int corner = 0;
  size_t line_facets = 0;
  while (in >> word) {
    if (word == "solid") {  // a new patch, named by the rest of the line
      std::string name;
      std::getline(in, name);
      const size_t b = name.find_first_not_of(" \t\r"), e = name.find_last_not_of(" \t\r");
      name = b == std::string::npos ? "" : name.substr(b, e - b + 1);
      s.patch_names.push_back(name.empty() ? fmt::format("solid_{}", s.patch_names.size()) : name);
      continue;
    }
    if (word == "vertex") {
      Vec3 p;
      double* xyz[3] = {&p.x, &p.y, &p.z};
      for (double* c : xyz) {
        // strtod, unlike operator>>, also reads "nan" and "inf", which are then named below.
        std::string token;
        char* end = nullptr;
        if (in >> token) *c = std::strtod(token.c_str(), &end);
        if (token.empty() || end != token.c_str() + token.size())
          fail(ErrorKind::InvalidInput,
               fmt::format("{}: facet {}: 'vertex' is not followed by three numbers", file, line_facets));
      }
      check_finite(file, line_facets, p);
      if (corner == 3)
        fail(ErrorKind::InvalidInput, fmt::format("{}: facet {} has more than 3 vertices", file, line_facets));
      tri[corner++] = merge.add(p);
    } else if (word == "endfacet") {
      if (corner != 3)
        fail(ErrorKind::InvalidInput,
             fmt::format("{}: facet {} has {} vertices, expected 3", file, line_facets, corner));
      s.triangles.push_back(tri);
      s.triangle_patch.push_back(std::max<int32_t>(0, int32_t(s.patch_names.size()) - 1));
      corner = 0;
      ++line_facets;
    }
  }
  if (s.triangles.empty())
    fail(ErrorKind::InvalidInput, fmt::format("{}: no facets found (not an STL file?)", file));
  if (s.patch_names.empty()) s.triangle_patch.clear();
  return s;
}

// A binary STL's triangle count (0 for a file too short to have one).
uint32_t binary_count(std::string_view bytes) {
  uint32_t n = 0;
  if (bytes.size() >= 84) std::memcpy(&n, bytes.data() + 80, 4);
  return n;
}

}  // namespace

TriangleSurface read_stl(const std::filesystem::path& path, double max_memory_bytes) {
  // A binary STL holds exactly 84 + 50 n bytes for its n triangles: nothing past that is read.
  const std::string bytes = read_input_file(path, max_memory_bytes, [](std::string_view head) -> size_t {
    const size_t start = head.find_first_not_of(" \t\r\n");
    if (head.size() < 84 || (start != std::string_view::npos && head.compare(start, 5, "solid") == 0)) return SIZE_MAX;
    return 84 + size_t(binary_count(head)) * 50;
  });
  const std::string file = path.string();
  const uint64_t count = binary_count(bytes), expected = 84 + 50 * count;
  if (bytes.size() == expected) {
    if (count == 0) fail(ErrorKind::InvalidInput, fmt::format("{}: binary STL with no triangles", file));
    return read_binary(file, bytes);
  }
  size_t start = bytes.find_first_not_of(" \t\r\n");
  if (start != std::string::npos && bytes.compare(start, 5, "solid") == 0) return read_ascii(file, bytes);
  fail(ErrorKind::InvalidInput,
       fmt::format("{}: neither binary STL (its triangle count {} makes {} bytes, but it holds {}) nor ASCII STL (it "
                   "does not start with 'solid')",
                   file, count, expected, bytes.size() > expected ? "more" : std::to_string(bytes.size())));
}

}  // namespace froth

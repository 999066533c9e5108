// Reads polyhedral VTU files written by any VTK-compatible writer: ascii, inline base64 binary
// and appended (raw or base64) data arrays, UInt32 or UInt64 headers, optionally compressed with
// zlib (vtkZLibDataCompressor). The XML is parsed with pugixml; raw appended bytes are cut off
// first, as they are not XML.
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cstring>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <type_traits>

#include <fmt/format.h>
#include <pugixml.hpp>

#include "common/cell_points.hpp"
#include "froth/error.hpp"
#include "froth/io.hpp"
#include "froth/validate.hpp"
#include "io/quality_fields.hpp"

namespace froth {
namespace {

[[noreturn]] void bad(const std::filesystem::path& path, const std::string& what) {
  fail(ErrorKind::InvalidInput, fmt::format("{}: {}", path.string(), what));
}

std::string base64_decode(std::string_view in) {
  static const auto table = [] {
    std::array<int8_t, 256> t;
    t.fill(-1);
    const char* chars = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    for (int i = 0; i < 64; ++i) t[uint8_t(chars[i])] = int8_t(i);
    return t;
  }();
  std::string out;
  out.reserve(in.size() * 3 / 4);
  uint32_t acc = 0;
  int bits = 0;
  for (char ch : in) {
    const int8_t v = table[uint8_t(ch)];
    if (v < 0) continue;  // whitespace and '=' padding
    acc = (acc << 6) | uint32_t(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(char((acc >> bits) & 0xFF));
    }
  }
  return out;
}

class Reader {
 public:
  explicit Reader(const std::filesystem::path& path) : path_(path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(ErrorKind::Io, fmt::format("cannot open {}", path.string()));
    std::stringstream ss;
    ss << in.rdbuf();
    bytes_ = ss.str();
    // Raw appended data is not XML: parse up to it, and keep the bytes after its '_'.
    std::string xml = bytes_;
    const size_t appended = bytes_.find("<AppendedData");
    if (appended != std::string::npos) {
      const size_t tag_end = bytes_.find('>', appended);
      const size_t underscore = bytes_.find('_', tag_end);
      if (tag_end == std::string::npos || underscore == std::string::npos) bad(path, "AppendedData without its '_'");
      appended_begin_ = underscore + 1;
      std::string tag = bytes_.substr(appended, tag_end - appended + 1);
      appended_base64_ = tag.find("base64") != std::string::npos;
      xml = bytes_.substr(0, appended) + "</VTKFile>";
    }
    const auto res = doc_.load_buffer(xml.data(), xml.size());
    if (!res) bad(path, fmt::format("not valid XML ({} at byte {})", res.description(), res.offset));
    auto file = doc_.child("VTKFile");
    if (!file || std::string(file.attribute("type").as_string()) != "UnstructuredGrid")
      bad(path, "not a VTK UnstructuredGrid (.vtu) file");
    if (std::string(file.attribute("byte_order").as_string("LittleEndian")) != "LittleEndian")
      bad(path, "big-endian data is not supported");
    header64_ = std::string(file.attribute("header_type").as_string("UInt32")) == "UInt64";
    const std::string compressor = file.attribute("compressor").as_string("");
    if (!compressor.empty() && compressor != "vtkZLibDataCompressor")
      bad(path, fmt::format("compressor {} is not supported (only zlib)", compressor));
    compressed_ = !compressor.empty();
    piece_ = file.child("UnstructuredGrid").child("Piece");
    if (!piece_) bad(path, "no Piece in the UnstructuredGrid");
  }

  size_t file_bytes() const { return bytes_.size(); }
  size_t points() const { return piece_.attribute("NumberOfPoints").as_ullong(); }
  size_t cells() const { return piece_.attribute("NumberOfCells").as_ullong(); }

  // A field data array of the grid (froth writes r, weld, random_seed, ...).
  pugi::xml_node field(const char* name) const {
    for (auto a : piece_.parent().child("FieldData").children("DataArray"))
      if (std::string(a.attribute("Name").as_string()) == name) return a;
    return {};
  }

  pugi::xml_node array(const char* section, const char* name, bool required = true) const {
    auto sec = piece_.child(section);
    for (auto a : sec.children("DataArray"))
      if (!name || std::string(a.attribute("Name").as_string()) == name) return a;
    if (required) bad(path_, fmt::format("no {} array {}", section, name ? name : ""));
    return {};
  }

  // The array's values converted to T. `count` is how many the file's counts make it hold: a
  // block that declares another size is refused before it is inflated (a zlib bomb's blocks can
  // inflate honestly to gigabytes for a handful of points).
  template <class T>
  std::vector<T> values(pugi::xml_node a, uint64_t count) const {
    const std::string type = a.attribute("type").as_string(), format = a.attribute("format").as_string("ascii");
    const char* name = a.attribute("Name").as_string("(unnamed)");
    std::vector<T> out;
    if (format == "ascii") {
      std::istringstream in(a.child_value());
      double v;
      while (in >> v) out.push_back(whole_if_needed<T>(v, name));  // (text: the file's own size bounds it)
      return out;
    }
    const uint64_t size = type_size(type, name);
    if (count > std::numeric_limits<uint64_t>::max() / size)
      bad(path_, fmt::format("array {}: {} values cannot be held", name, count));
    const Expected expected{name, count * size, count};
    std::string raw;
    if (format == "binary") raw = decode_block(a.child_value(), expected);
    else if (format == "appended") raw = appended_block(a.attribute("offset").as_ullong(), expected);
    else bad(path_, fmt::format("array {}: unknown format {}", name, format));
    convert(type, raw, out, name);
    return out;
  }

  // A field data array's values: as many as its NumberOfTuples and NumberOfComponents say (a
  // String array's tuples are its strings: froth writes those as text).
  template <class T>
  std::vector<T> field_values(pugi::xml_node a) const {
    return values<T>(a, a.attribute("NumberOfTuples").as_ullong(1) * a.attribute("NumberOfComponents").as_ullong(1));
  }

  // A field data array of one number (froth's r, weld, grading options), if there is one.
  std::optional<double> scalar_field(const char* name) const {
    const pugi::xml_node a = field(name);
    if (!a) return std::nullopt;
    const std::vector<double> v = field_values<double>(a);
    return v.size() == 1 ? std::optional<double>(v[0]) : std::nullopt;
  }

 private:
  // What a data block must hold, from the counts in the XML.
  struct Expected {
    const char* name;
    uint64_t bytes, values;
  };

  [[noreturn]] void wrong_size(const Expected& e, uint64_t declared) const {
    bad(path_, fmt::format("array {}: its data block declares {} bytes, but its {} values take {} (corrupt or hostile)",
                           e.name, declared, e.values, e.bytes));
  }

  uint64_t type_size(const std::string& type, const char* name) const {
    if (type == "Float64" || type == "Int64" || type == "UInt64") return 8;
    if (type == "Float32" || type == "Int32" || type == "UInt32") return 4;
    if (type == "Int16" || type == "UInt16") return 2;
    if (type == "Int8" || type == "UInt8") return 1;
    bad(path_, fmt::format("array {}: unsupported type {}", name, type));
  }

  uint64_t header_word(const std::string& s, size_t i) const {
    if (i >= s.size() / word()) bad(path_, "a data block's header is truncated");
    if (header64_) {
      uint64_t v;
      std::memcpy(&v, s.data() + 8 * i, 8);
      return v;
    }
    uint32_t v;
    std::memcpy(&v, s.data() + 4 * i, 4);
    return v;
  }
  size_t word() const { return header64_ ? 8 : 4; }

  // Uncompresses zlib blocks: header [blocks, block size, last size, compressed sizes...].
  std::string inflate_blocks(const std::string& header, const std::string& data, const Expected& expected) const {
    const uint64_t blocks = header_word(header, 0), block = header_word(header, 1), last = header_word(header, 2);
    // The sizes the blocks declare, checked against the counts before anything is inflated.
    uint64_t declared = 0;
    if (blocks > 0 && (__builtin_mul_overflow(blocks - 1, block, &declared) ||
                       __builtin_add_overflow(declared, last != 0 ? last : block, &declared)))
      declared = std::numeric_limits<uint64_t>::max();
    if (declared > expected.bytes) wrong_size(expected, declared);  // fewer: the counts' checks name it
    std::string out;
    size_t at = 0;
    for (uint64_t b = 0; b < blocks; ++b) {
      const uint64_t csize = header_word(header, 3 + b);
      const uint64_t usize = (b + 1 == blocks && last != 0) ? last : block;
      // zlib inflates at most 1032 to 1 (a count larger than the data can hold is a lie: a
      // "zlib bomb" header would otherwise have froth allocate gigabytes).
      if (csize > data.size() - std::min<size_t>(at, data.size()) || usize > 1032 * csize + 64)
        bad(path_, fmt::format("a compressed data block claims {} bytes from {} (corrupt or hostile)", usize, csize));
      std::string buf(usize, '\0');
      uLongf len = uLongf(usize);
      if (at + csize > data.size() ||
          uncompress(reinterpret_cast<Bytef*>(buf.data()), &len, reinterpret_cast<const Bytef*>(data.data() + at),
                     uLong(csize)) != Z_OK)
        bad(path_, "a compressed data block is corrupt");
      out.append(buf.data(), len);
      at += csize;
    }
    return out;
  }

  // An inline base64 block (binary format).
  std::string decode_block(std::string_view text, const Expected& expected) const {
    // Strip leading whitespace.
    while (!text.empty() && std::isspace(uint8_t(text.front()))) text.remove_prefix(1);
    if (!compressed_) {
      std::string all = base64_decode(text);
      if (all.size() < word()) bad(path_, "a binary data block is truncated");
      const uint64_t n = header_word(all, 0);
      if (n > all.size() - word()) bad(path_, "a binary data block is shorter than its header says");
      if (n > expected.bytes) wrong_size(expected, n);
      return all.substr(word(), n);
    }
    // Compressed: the header is encoded on its own, then the data.
    std::string first = base64_decode(text.substr(0, std::min<size_t>(text.size(), 4 * ((3 * word() + 2) / 3))));
    const uint64_t blocks = header_word(first, 0);
    if (blocks > text.size()) bad(path_, fmt::format("a binary data block declares {} compressed blocks", blocks));
    const size_t header_bytes = (3 + blocks) * word();
    const size_t header_chars = 4 * ((header_bytes + 2) / 3);
    if (header_chars > text.size()) bad(path_, fmt::format("a binary data block's header of {} blocks is truncated", blocks));
    const std::string header = base64_decode(text.substr(0, header_chars));
    return inflate_blocks(header, base64_decode(text.substr(header_chars)), expected);
  }

  std::string appended_block(uint64_t offset, const Expected& expected) const {
    if (appended_begin_ + offset > bytes_.size() || offset > bytes_.size())
      bad(path_, "an appended offset points past the end of the file");
    if (appended_base64_) {
      // Offsets count base64 characters.
      std::string_view rest(bytes_.data() + appended_begin_ + offset, bytes_.size() - appended_begin_ - offset);
      return decode_block(rest.substr(0, rest.find('<')), expected);
    }
    const size_t at = appended_begin_ + offset;
    if (at + word() > bytes_.size()) bad(path_, "an appended offset points past the end of the file");
    if (!compressed_) {
      const uint64_t n = header_word(bytes_.substr(at, word()), 0);
      if (n > bytes_.size() - at - word()) bad(path_, "an appended block runs past the end of the file");
      if (n > expected.bytes) wrong_size(expected, n);
      return bytes_.substr(at + word(), n);
    }
    const uint64_t blocks = header_word(bytes_.substr(at, word()), 0);
    if (blocks > bytes_.size()) bad(path_, fmt::format("an appended block declares {} compressed blocks", blocks));
    const std::string header = bytes_.substr(at, (3 + blocks) * word());
    uint64_t total = 0;
    for (uint64_t b = 0; b < blocks; ++b) {
      total += header_word(header, 3 + b);
      if (total > bytes_.size()) bad(path_, "an appended block's compressed sizes run past the end of the file");
    }
    return inflate_blocks(header, bytes_.substr(at + header.size(), total), expected);
  }

  // A value as T; a floating-point value read for an integer array (offsets, connectivity) must
  // be a number in T's range, or its conversion would be undefined.
  template <class T, class S>
  T whole_if_needed(S v, const char* name) const {
    if constexpr (std::is_integral_v<T> && std::is_floating_point_v<S>) {
      if (!(v >= double(std::numeric_limits<T>::min()) && v < double(std::numeric_limits<T>::max()) + 1.0))
        bad(path_, fmt::format("array {}: {} is not an index or count", name, v));
    }
    return T(v);
  }

  template <class T>
  void convert(const std::string& type, const std::string& raw, std::vector<T>& out, const char* name) const {
    auto take = [&](auto zero) {
      using S = decltype(zero);
      const size_t n = raw.size() / sizeof(S);
      out.resize(n);
      for (size_t i = 0; i < n; ++i) {
        S v;
        std::memcpy(&v, raw.data() + i * sizeof(S), sizeof(S));
        out[i] = whole_if_needed<T>(v, name);
      }
    };
    if (type == "Float64") take(double{});
    else if (type == "Float32") take(float{});
    else if (type == "Int64") take(int64_t{});
    else if (type == "UInt64") take(uint64_t{});
    else if (type == "Int32") take(int32_t{});
    else if (type == "UInt32") take(uint32_t{});
    else if (type == "Int16") take(int16_t{});
    else if (type == "UInt16") take(uint16_t{});
    else if (type == "Int8") take(int8_t{});
    else if (type == "UInt8") take(uint8_t{});
    else bad(path_, fmt::format("array {}: unsupported type {}", name, type));
  }

  std::filesystem::path path_;
  std::string bytes_;
  pugi::xml_document doc_;
  pugi::xml_node piece_;
  size_t appended_begin_ = 0;
  bool appended_base64_ = false, header64_ = false, compressed_ = false;
};

// A string array's names (each name's bytes, then 0), as names_field_data writes them.
std::vector<std::string> string_values(const Reader& rd, pugi::xml_node a) {
  std::vector<std::string> out;
  std::string name;
  for (int64_t ch : rd.field_values<int64_t>(a)) {
    if (ch != 0) name += char(ch);
    else out.push_back(name), name.clear();
  }
  return out;
}

}  // namespace

PolyMesh read_vtu(const std::filesystem::path& path, RunReport* recorded) {
  Reader rd(path);
  const size_t np = rd.points(), nc = rd.cells();
  // Counts the file's bytes cannot hold, even inflated at zlib's best ratio, are refused before
  // anything is sized by them.
  if (np / 1032 > rd.file_bytes() || nc / 1032 > rd.file_bytes())
    bad(path, fmt::format("{} points and {} cells cannot fit in its {} bytes", np, nc, rd.file_bytes()));
  PolyMesh m;
  const std::vector<double> xyz = rd.values<double>(rd.array("Points", nullptr), 3 * uint64_t(np));
  if (xyz.size() != 3 * np) bad(path, fmt::format("{} point coordinates for {} points", xyz.size(), np));
  m.points.resize(np);
  for (size_t i = 0; i < np; ++i) m.points[i] = {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]};
  const std::vector<int64_t> types = rd.values<int64_t>(rd.array("Cells", "types"), nc);
  if (types.size() != nc) bad(path, "the types array does not have one entry per cell");
  for (size_t c = 0; c < nc; ++c)
    if (types[c] != 42)
      bad(path, fmt::format("cell {} has VTK type {}, not a polyhedron (42): froth reads polyhedral meshes", c,
                            types[c]));
  const std::vector<int64_t> faceoffsets = rd.values<int64_t>(rd.array("Cells", "faceoffsets"), nc);
  if (faceoffsets.size() != nc) bad(path, "the faceoffsets array does not have one entry per cell");
  const int64_t face_stream = nc ? faceoffsets.back() : 0;
  if (face_stream < 0) bad(path, fmt::format("cell {}: face offsets out of order", nc - 1));
  const std::vector<int64_t> faces = rd.values<int64_t>(rd.array("Cells", "faces"), uint64_t(face_stream));

  // Face streams: per cell its face count, then per face its size and point ids.
  int64_t at = 0;
  for (size_t c = 0; c < nc; ++c) {
    const int64_t end = faceoffsets[c];
    if (end < at || end > int64_t(faces.size())) bad(path, fmt::format("cell {}: face offsets out of order", c));
    if (at == end) bad(path, fmt::format("cell {}: an empty face stream", c));
    const int64_t nf = faces[at++];
    for (int64_t f = 0; f < nf; ++f) {
      if (at >= end) bad(path, fmt::format("cell {}: face stream shorter than its face count", c));
      const int64_t n = faces[at++];
      if (n < 3 || n > end - at) bad(path, fmt::format("cell {} face {}: {} points", c, f, n));
      for (int64_t k = 0; k < n; ++k) {
        const int64_t v = faces[at++];
        if (v < 0 || v >= int64_t(np)) bad(path, fmt::format("cell {} face {}: point id {} out of range", c, f, v));
        m.face_vertices.push_back(int32_t(v));
      }
      m.face_vertex_begin.push_back(int64_t(m.face_vertices.size()));
      m.face_generator.push_back(0);
    }
    m.cell_face_begin.push_back(int64_t(m.face_vertex_begin.size() - 1));
    at = end;
  }

  // Seeds from the cell data if there, else the mean of each cell's vertices.
  m.seeds.resize(nc);
  if (auto seed = rd.array("CellData", "seed", false)) {
    const std::vector<double> s = rd.values<double>(seed, 3 * uint64_t(nc));
    if (s.size() != 3 * nc) bad(path, "the seed array does not have three values per cell");
    for (size_t c = 0; c < nc; ++c) m.seeds[c] = {s[3 * c], s[3 * c + 1], s[3 * c + 2]};
  } else {
    for (size_t c = 0; c < nc; ++c) {
      Vec3 sum{};
      int64_t count = 0;
      for (int64_t k = m.face_vertex_begin[m.cell_face_begin[c]]; k < m.face_vertex_begin[m.cell_face_begin[c + 1]]; ++k)
        sum = sum + m.points[m.face_vertices[k]], ++count;
      m.seeds[c] = (1.0 / double(std::max<int64_t>(count, 1))) * sum;
    }
  }

  // Interior faces are those two cells share (same point set): their generator is the other
  // cell; the rest are border faces. Faces are grouped by their smallest point id and matched
  // within the group.
  const size_t nf = m.face_count();
  std::vector<int32_t> face_cell(nf);
  for (size_t c = 0; c < nc; ++c)
    for (int64_t f = m.cell_face_begin[c]; f < m.cell_face_begin[c + 1]; ++f) face_cell[f] = int32_t(c);
  std::vector<std::pair<int32_t, int64_t>> by_min(nf);
  for (size_t f = 0; f < nf; ++f)
    by_min[f] = {*std::min_element(m.face_vertices.begin() + m.face_vertex_begin[f],
                                   m.face_vertices.begin() + m.face_vertex_begin[f + 1]),
                 int64_t(f)};
  std::sort(by_min.begin(), by_min.end());
  for (size_t f = 0; f < nf; ++f) m.face_generator[f] = plane_generator(0);
  m.border_planes_known = false;
  auto sorted_points = [&](int64_t f) {
    std::vector<int32_t> k(m.face_vertices.begin() + m.face_vertex_begin[f],
                           m.face_vertices.begin() + m.face_vertex_begin[f + 1]);
    std::sort(k.begin(), k.end());
    return k;
  };
  for (size_t i = 0; i < nf;) {
    size_t j = i;
    while (j < nf && by_min[j].first == by_min[i].first) ++j;
    std::vector<std::vector<int32_t>> keys;
    for (size_t a = i; a < j; ++a) keys.push_back(sorted_points(by_min[a].second));
    for (size_t a = i; a < j; ++a)
      for (size_t b = a + 1; b < j; ++b) {
        const int64_t fa = by_min[a].second, fb = by_min[b].second;
        if (m.face_generator[fa] >= 0 || m.face_generator[fb] >= 0 || keys[a - i] != keys[b - i]) continue;
        m.face_generator[fa] = face_cell[fb];
        m.face_generator[fb] = face_cell[fa];
      }
    i = j;
  }
  if (auto piece = rd.array("CellData", "piece", false)) {
    const std::vector<int64_t> p = rd.values<int64_t>(piece, nc);
    if (p.size() != nc) bad(path, "the piece array does not have one value per cell");
    if (std::any_of(p.begin(), p.end(), [](int64_t v) { return v != 0; }))
      for (int64_t v : p) m.piece.push_back(uint32_t(std::clamp<int64_t>(v, 0, INT32_MAX)));
  }
  // A multi-region mesh's regions and their names.
  if (auto region = rd.array("CellData", "region", false)) {
    const std::vector<int64_t> p = rd.values<int64_t>(region, nc);
    if (p.size() != nc) bad(path, "the region array does not have one value per cell");
    for (int64_t v : p) m.region.push_back(int32_t(std::clamp<int64_t>(v, 0, INT32_MAX)));
    if (auto names = rd.field("region_names")) m.region_names = string_values(rd, names);
  }
  if (auto names = rd.field("crack_names")) m.crack_names = string_values(rd, names);
  // froth's r and graded radii, so that the bounds are judged as in the run (quality.hpp).
  if (const auto r = rd.scalar_field("r"); r && *r > 0) m.r = *r;
  // froth's volumes and centres, as written (a solver's formats carry them on).
  if (auto volume = rd.array("CellData", "volume", false)) {
    std::vector<double> v = rd.values<double>(volume, nc);
    if (v.size() != nc) bad(path, "the volume array does not have one value per cell");
    m.volumes = std::move(v);
  } else {  // another program's VTU: the volumes from the cells themselves, as the writers need them
    m.volumes.resize(nc);
    for (size_t c = 0; c < nc; ++c) m.volumes[c] = cell_volume(m, c);
  }
  if (auto center = rd.array("CellData", "center", false)) {
    const std::vector<double> v = rd.values<double>(center, 3 * uint64_t(nc));
    if (v.size() != 3 * nc) bad(path, "the center array does not have three values per cell");
    m.centers.resize(nc);
    for (size_t c = 0; c < nc; ++c) m.centers[c] = {v[3 * c], v[3 * c + 1], v[3 * c + 2]};
  }
  if (auto seed = rd.field("random_seed")) {  // froth writes it in ascii, exactly
    std::istringstream in(seed.child_value());
    uint64_t v = 0;
    if (in >> v) m.random_seed = v;
  }
  if (auto radius = rd.array("CellData", "radius", false); radius && m.r > 0) {
    std::vector<double> h = rd.values<double>(radius, nc);
    if (h.size() != nc) bad(path, "the radius array does not have one value per cell");
    if (std::any_of(h.begin(), h.end(), [&](double v) { return v < m.r; })) m.radii = std::move(h);
  }
  // --convex's parents, and the quality stage's measures, so that a converted mesh keeps them.
  if (auto parent = rd.array("CellData", "parent", false)) {
    const std::vector<int64_t> p = rd.values<int64_t>(parent, nc);
    if (p.size() != nc) bad(path, "the parent array does not have one value per cell");
    for (int64_t v : p) m.parent.push_back(uint32_t(std::clamp<int64_t>(v, 0, int64_t(nc) - 1)));
  }
  if (std::all_of(std::begin(kQualityFields), std::end(kQualityFields),
                  [&](const auto& field) { return bool(rd.array("CellData", field.first, false)); })) {
    m.quality.resize(nc);
    for (const auto& [name, member] : kQualityFields) {
      const std::vector<double> v = rd.values<double>(rd.array("CellData", name), nc);
      if (v.size() != nc) bad(path, fmt::format("the {} array does not have one value per cell", name));
      for (size_t c = 0; c < nc; ++c) m.quality[c].*member = v[c];
    }
    std::vector<int32_t> pts;
    for (size_t c = 0; c < nc; ++c) {
      cell_points(m, c, pts);
      m.quality[c].faces = uint32_t(m.cell_face_begin[c + 1] - m.cell_face_begin[c]);
      m.quality[c].vertices = uint32_t(pts.size());
    }
  }
  if (recorded) {
    recorded->r = m.r;
    recorded->seed = m.random_seed.value_or(0);
    if (const auto weld = rd.scalar_field("weld"); weld && *weld >= 0) recorded->weld = *weld;
    if (rd.field("grade")) {
      recorded->grade = rd.scalar_field("grade").value_or(0) != 0;
      recorded->sizing.min_r = rd.scalar_field("min_r").value_or(m.r);
      recorded->sizing.graded = recorded->sizing.min_r < m.r;
      recorded->grading = rd.scalar_field("max_grading").value_or(recorded->grading);
    }
  }
  m.kinds.assign(nc, CellKind::Interior);
  if (auto kind = rd.array("CellData", "kind", false)) {
    const std::vector<int64_t> k = rd.values<int64_t>(kind, nc);
    if (k.size() != nc) bad(path, "the kind array does not have one value per cell");
    for (size_t c = 0; c < nc; ++c) m.kinds[c] = CellKind(std::clamp<int64_t>(k[c], 0, kCellKinds - 1));
  } else {
    for (size_t c = 0; c < nc; ++c)
      for (int64_t f = m.cell_face_begin[c]; f < m.cell_face_begin[c + 1]; ++f)
        if (is_border_generator(m.face_generator[f])) m.kinds[c] = CellKind::Fringe;
  }
  return m;
}

}  // namespace froth

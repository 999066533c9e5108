// OFF, OBJ and PLY (ASCII or binary), read by froth itself: CGAL 5.5's readers crash on some
// malformed files (a PLY property before any element, integer PLY coordinates, a COFF line that
// is not a number). Every count is checked against the bytes left before anything is allocated
// for it, every index against the vertices, every number as it is parsed. Polygons are fanned
// into triangles; vertices with bit-equal coordinates are merged, as for STL.
#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string_view>

#include <fmt/format.h>

#include "froth/domain.hpp"
#include "froth/error.hpp"
#include "input/input_file.hpp"
#include "input/vertex_merger.hpp"

namespace froth {
namespace {

struct Soup {
  std::vector<Vec3> points;
  std::vector<int64_t> corners;            // vertex indices of all faces, 0-based
  std::vector<size_t> face_begin{0};       // into corners
  std::vector<int32_t> face_group;         // OBJ: each face's group (g or o), into groups
  std::vector<std::string> groups;
};

[[noreturn]] void bad(const std::string& file, const std::string& what) {
  fail(ErrorKind::InvalidInput, fmt::format("{}: {}", file, what));
}

// Lines of a text file, with their numbers; `#` starts a comment; blank lines are skipped.
class Lines {
 public:
  Lines(const std::string& text, size_t from = 0) : text_(text), at_(from) {}
  bool next(std::string_view& line) {
    while (at_ < text_.size()) {
      const size_t end = std::min(text_.find('\n', at_), text_.size());
      line = std::string_view(text_).substr(at_, end - at_);
      at_ = end + 1;
      ++number_;
      if (const size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
      while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.remove_suffix(1);
      while (!line.empty() && std::isspace(static_cast<unsigned char>(line.front()))) line.remove_prefix(1);
      if (!line.empty()) return true;
    }
    return false;
  }
  size_t number() const { return number_; }
  size_t left() const { return text_.size() > at_ ? text_.size() - at_ : 0; }

 private:
  const std::string& text_;
  size_t at_, number_ = 0;
};

// Whitespace-separated words of one line.
std::vector<std::string_view> words(std::string_view line) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    size_t j = i;
    while (j < line.size() && !std::isspace(static_cast<unsigned char>(line[j]))) ++j;
    if (j > i) out.push_back(line.substr(i, j - i));
    i = j;
  }
  return out;
}

// The whole word as a T: std::errc() if it is one, invalid_argument for other characters, and
// result_out_of_range for a number T cannot hold.
template <class T>
std::errc parse(std::string_view w, T& v) {
  const auto [p, ec] = std::from_chars(w.data(), w.data() + w.size(), v);
  return ec != std::errc() ? ec : p == w.data() + w.size() ? std::errc() : std::errc::invalid_argument;
}

double number(const std::string& file, const Lines& at, std::string_view w) {
  double v;
  if (parse(w, v) != std::errc()) bad(file, fmt::format("line {}: '{}' is not a number", at.number(), quoted_text(w)));
  return v;
}

int64_t whole(const std::string& file, const Lines& at, std::string_view w, const char* what) {
  int64_t v;
  const std::errc ec = parse(w, v);
  if (ec == std::errc::result_out_of_range)
    bad(file, fmt::format("line {}: {} '{}' is out of range (at most {})", at.number(), what, quoted_text(w), INT64_MAX));
  if (ec != std::errc()) bad(file, fmt::format("line {}: {} '{}' is not a whole number", at.number(), what, quoted_text(w)));
  return v;
}

// A declared count, which the bytes left must be able to hold at `min_bytes` each.
size_t count(const std::string& file, int64_t n, size_t left, size_t min_bytes, const char* what) {
  if (n < 0) bad(file, fmt::format("{} {} is negative", what, n));
  if (uint64_t(n) > left / min_bytes)
    bad(file, fmt::format("declares {} {}, more than its {} remaining bytes can hold (truncated or corrupt)", n, what,
                          left));
  return size_t(n);
}

Soup read_off(const std::string& file, const std::string& text) {
  Lines lines(text);
  std::string_view line;
  if (!lines.next(line)) bad(file, "empty");
  std::vector<std::string_view> w = words(line);
  const std::string_view head = w[0];
  if (head.size() < 3 || head.substr(head.size() - 3) != "OFF" ||
      head.substr(0, head.size() - 3).find_first_not_of("STCN") != std::string_view::npos)
    bad(file, fmt::format("line 1: '{}' is not an OFF header (OFF, COFF, NOFF, STOFF...)", quoted_text(head)));
  w.erase(w.begin());
  if (w.empty()) {
    if (!lines.next(line)) bad(file, "no vertex and face counts after the header");
    w = words(line);
  }
  if (w.size() < 2) bad(file, fmt::format("line {}: expected the vertex and face counts", lines.number()));
  Soup s;
  const size_t nv = count(file, whole(file, lines, w[0], "the vertex count"), lines.left(), 6, "vertices");
  const size_t nf = count(file, whole(file, lines, w[1], "the face count"), lines.left(), 8, "faces");
  s.points.reserve(nv);
  for (size_t v = 0; v < nv; ++v) {
    if (!lines.next(line)) bad(file, fmt::format("ends after {} of its {} vertices", v, nv));
    w = words(line);
    if (w.size() < 3) bad(file, fmt::format("line {}: vertex {} has {} coordinates", lines.number(), v, w.size()));
    s.points.push_back({number(file, lines, w[0]), number(file, lines, w[1]), number(file, lines, w[2])});
  }
  for (size_t f = 0; f < nf; ++f) {
    if (!lines.next(line)) bad(file, fmt::format("ends after {} of its {} faces", f, nf));
    w = words(line);
    const int64_t n = whole(file, lines, w[0], "a face's vertex count");
    if (n < 0 || uint64_t(n) + 1 > w.size())
      bad(file, fmt::format("line {}: face {} declares {} vertices and lists {}", lines.number(), f, n, w.size() - 1));
    for (int64_t k = 1; k <= n; ++k) s.corners.push_back(whole(file, lines, w[size_t(k)], "a vertex index"));
    s.face_begin.push_back(s.corners.size());
  }
  return s;
}

Soup read_obj(const std::string& file, const std::string& text) {
  Lines lines(text);
  std::string_view line;
  Soup s;
  int32_t group = -1;
  auto group_index = [&](const std::string& name) {
    const auto it = std::find(s.groups.begin(), s.groups.end(), name);
    if (it != s.groups.end()) return int32_t(it - s.groups.begin());
    s.groups.push_back(name);
    return int32_t(s.groups.size()) - 1;
  };
  while (lines.next(line)) {
    const std::vector<std::string_view> w = words(line);
    if (w[0] == "v") {
      if (w.size() < 4) bad(file, fmt::format("line {}: a vertex with {} coordinates", lines.number(), w.size() - 1));
      s.points.push_back({number(file, lines, w[1]), number(file, lines, w[2]), number(file, lines, w[3])});
    } else if (w[0] == "f") {
      for (size_t k = 1; k < w.size(); ++k) {
        const std::string_view ref = w[k].substr(0, w[k].find('/'));  // v, v/vt, v//vn, v/vt/vn
        const int64_t i = whole(file, lines, ref, "a vertex index");
        // 1-based; negative counts back from the last vertex so far.
        if (i == 0) bad(file, fmt::format("line {}: vertex index 0 (OBJ counts from 1)", lines.number()));
        if (i < 0 && -i > int64_t(s.points.size()))
          bad(file, fmt::format("line {}: vertex index {} counts back past the first vertex ({} are defined so far)",
                                lines.number(), i, s.points.size()));
        s.corners.push_back(i > 0 ? i - 1 : int64_t(s.points.size()) + i);
      }
      s.face_begin.push_back(s.corners.size());
      if (group < 0) group = group_index("default");  // faces before the first group
      s.face_group.push_back(group);
    } else if ((w[0] == "g" || w[0] == "o") && w.size() > 1) {
      std::string name(w[1]);
      for (size_t k = 2; k < w.size(); ++k) name.append(1, '_').append(w[k]);
      group = group_index(name);  // a group named again continues
    }
  }
  return s;
}

// PLY: a text header, then the elements in ASCII or binary (either byte order).
struct PlyProperty {
  std::string name;
  int type = 0, count_type = 0;  // bytes of a scalar type code (see ply_type); count_type > 0: a list
  bool is_float = false, is_signed = false, count_signed = false;
};
struct PlyElement {
  std::string name;
  size_t count = 0;
  std::vector<PlyProperty> props;
};

bool ply_type(std::string_view t, int& bytes, bool& is_float, bool& is_signed) {
  struct Kind { const char* a; const char* b; int bytes; bool f, s; };
  static constexpr Kind kinds[] = {{"char", "int8", 1, false, true},     {"uchar", "uint8", 1, false, false},
                                   {"short", "int16", 2, false, true},   {"ushort", "uint16", 2, false, false},
                                   {"int", "int32", 4, false, true},     {"uint", "uint32", 4, false, false},
                                   {"float", "float32", 4, true, true},  {"double", "float64", 8, true, true}};
  for (const Kind& k : kinds)
    if (t == k.a || t == k.b) return bytes = k.bytes, is_float = k.f, is_signed = k.s, true;
  return false;
}

class BinaryCursor {
 public:
  BinaryCursor(const std::string& file, const std::string& text, size_t at, bool big)
      : file_(file), text_(text), at_(at), big_(big) {}
  double scalar(int bytes, bool is_float, bool is_signed) {
    bytes = std::clamp(bytes, 1, 8);  // (ply_type gives 1, 2, 4 or 8)
    if (at_ > text_.size() || text_.size() - at_ < size_t(bytes)) bad(file_, "binary data ends early (truncated)");
    unsigned char b[8];
    std::memcpy(b, text_.data() + at_, size_t(bytes));
    at_ += size_t(bytes);
    if (big_ != (std::endian::native == std::endian::big))
      for (int i = 0; i < bytes / 2; ++i) std::swap(b[i], b[bytes - 1 - i]);
    if (is_float) {
      if (bytes == 4) return double(std::bit_cast<float>(load<uint32_t>(b)));
      return std::bit_cast<double>(load<uint64_t>(b));
    }
    uint64_t u = 0;
    std::memcpy(&u, b, size_t(bytes));  // little end first, as the bytes now are in host order
    if constexpr (std::endian::native == std::endian::big) u >>= 8 * (8 - bytes);
    if (is_signed && bytes < 8 && (u >> (8 * bytes - 1) & 1)) u |= ~uint64_t(0) << (8 * bytes);
    return is_signed ? double(int64_t(u)) : double(u);
  }
  size_t left() const { return text_.size() - at_; }

 private:
  template <class U>
  static U load(const unsigned char* b) {
    U u;
    std::memcpy(&u, b, sizeof u);
    return u;
  }
  const std::string& file_;
  const std::string& text_;
  size_t at_;
  bool big_;
};

Soup read_ply(const std::string& file, const std::string& text) {
  const size_t end = text.find("end_header");
  if (text.compare(0, 3, "ply") != 0 || end == std::string::npos) bad(file, "not a PLY file (no 'ply' ... 'end_header')");
  size_t data = text.find('\n', end);
  data = data == std::string::npos ? text.size() : data + 1;
  const std::string header = text.substr(0, end);
  Lines lines(header);
  std::string_view line;
  std::string format;
  std::vector<PlyElement> elements;
  while (lines.next(line)) {
    const std::vector<std::string_view> w = words(line);
    if (w[0] == "ply" || w[0] == "comment" || w[0] == "obj_info") continue;
    if (w[0] == "format") {
      if (w.size() < 2) bad(file, fmt::format("line {}: format without a name", lines.number()));
      format = std::string(w[1]);
    } else if (w[0] == "element") {
      if (w.size() != 3) bad(file, fmt::format("line {}: expected 'element NAME COUNT'", lines.number()));
      const int64_t n = whole(file, lines, w[2], "an element count");
      elements.push_back({std::string(w[1]), count(file, n, text.size() - data + 1, 1, std::string(w[1]).c_str()), {}});
    } else if (w[0] == "property") {
      if (elements.empty()) bad(file, fmt::format("line {}: a property before any element", lines.number()));
      PlyProperty p;
      bool ok = false;
      if (w.size() == 5 && w[1] == "list") {
        int item = 0;
        bool f = false;
        ok = ply_type(w[2], p.count_type, f, p.count_signed) && !f && ply_type(w[3], item, p.is_float, p.is_signed);
        p.type = item, p.name = std::string(w[4]);
      } else if (w.size() == 3) {
        ok = ply_type(w[1], p.type, p.is_float, p.is_signed);
        p.name = std::string(w[2]);
      }
      if (!ok) bad(file, fmt::format("line {}: property '{}' is not one froth reads", lines.number(), quoted_text(line)));
      elements.back().props.push_back(p);
    } else {
      bad(file, fmt::format("line {}: '{}' is not a PLY header line", lines.number(), quoted_text(w[0])));
    }
  }
  if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian")
    bad(file, fmt::format("format '{}' (expected ascii, binary_little_endian or binary_big_endian)", quoted_text(format)));

  Soup s;
  Lines body(text, data);
  BinaryCursor bin(file, text, data, format == "binary_big_endian");
  const bool ascii = format == "ascii";
  std::vector<std::string_view> w;
  size_t word = 0;
  auto value = [&](int bytes, bool is_float, bool is_signed) -> double {
    if (!ascii) return bin.scalar(bytes, is_float, is_signed);
    if (word == w.size()) bad(file, fmt::format("line {}: fewer values than the header declares", body.number()));
    return number(file, body, w[word++]);
  };
  for (const PlyElement& e : elements) {
    const bool vertex = e.name == "vertex", face = e.name == "face";
    int xyz[3] = {-1, -1, -1};
    for (size_t k = 0; k < e.props.size(); ++k)
      for (int a = 0; a < 3; ++a)
        if (e.props[k].count_type == 0 && e.props[k].name == std::string(1, char('x' + a))) xyz[a] = int(k);
    if (vertex && (xyz[0] < 0 || xyz[1] < 0 || xyz[2] < 0)) bad(file, "the vertex element has no x, y and z");
    if (vertex) s.points.reserve(e.count);
    for (size_t i = 0; i < e.count; ++i) {
      if (ascii) {
        std::string_view l;
        if (!body.next(l)) bad(file, fmt::format("ends after {} of its {} {} lines", i, e.count, e.name));
        w = words(l), word = 0;
      }
      Vec3 p{};
      for (size_t k = 0; k < e.props.size(); ++k) {
        const PlyProperty& pr = e.props[k];
        if (pr.count_type == 0) {
          const double v = value(pr.type, pr.is_float, pr.is_signed);
          for (int a = 0; a < 3; ++a)
            if (int(k) == xyz[a]) p[a] = v;
          continue;
        }
        const double n = value(pr.count_type, false, pr.count_signed);
        if (!(n >= 0) || n > double(ascii ? w.size() : bin.left())) bad(file, fmt::format("a list of {} items", n));
        const bool indices = face && (pr.name == "vertex_indices" || pr.name == "vertex_index");
        for (int64_t j = 0; j < int64_t(n); ++j) {
          const double v = value(pr.type, pr.is_float, pr.is_signed);
          if (indices) s.corners.push_back(v == std::floor(v) && std::abs(v) < 9e18 ? int64_t(v) : -1);
        }
        if (indices) s.face_begin.push_back(s.corners.size());
      }
      if (vertex) s.points.push_back(p);
    }
  }
  return s;
}

}  // namespace

TriangleSurface read_polygon_file(const std::filesystem::path& path, double max_memory_bytes) {
  const std::string file = path.string();
  std::string ext = path.extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  // Text (a PLY's header is) cannot hold NUL bytes: a zeroed or binary file is refused from its
  // first bytes, not after reading all of it.
  const std::string text = read_input_file(path, max_memory_bytes, [&](std::string_view head) {
    if (ext == ".ply") {
      if (head.substr(0, 3) != "ply") bad(file, fmt::format("not a PLY file: it starts '{}', not 'ply'", quoted_text(head.substr(0, 16))));
      refuse_binary_text(file, head, "PLY header", head.find("end_header"));
    } else {
      refuse_binary_text(file, head, ext == ".off" ? "OFF" : "OBJ");
    }
    return SIZE_MAX;
  });
  const Soup soup = ext == ".off" ? read_off(file, text) : ext == ".obj" ? read_obj(file, text) : read_ply(file, text);
  if (soup.face_begin.size() < 2) bad(file, fmt::format("no faces in this {} file", ext));
  TriangleSurface s;
  VertexMerger merge(s);
  std::vector<int32_t> id(soup.points.size());
  for (size_t i = 0; i < soup.points.size(); ++i) {
    const Vec3 p = soup.points[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      bad(file, fmt::format("vertex {} has a coordinate that is not a finite number ({}, {}, {})", i, p.x, p.y, p.z));
    id[i] = merge.add(p);
  }
  for (size_t f = 0; f + 1 < soup.face_begin.size(); ++f) {
    const size_t b = soup.face_begin[f], e = soup.face_begin[f + 1];
    if (e - b < 3) bad(file, fmt::format("face {} has {} vertices", f, e - b));
    for (size_t k = b; k < e; ++k)
      if (soup.corners[k] < 0 || uint64_t(soup.corners[k]) >= soup.points.size())
        bad(file, fmt::format("face {} uses vertex {}, but the vertices are numbered 0 to {}", f, soup.corners[k],
                              soup.points.size() - 1));
    for (size_t k = b + 1; k + 1 < e; ++k) {
      s.triangles.push_back({id[size_t(soup.corners[b])], id[size_t(soup.corners[k])], id[size_t(soup.corners[k + 1])]});
      if (!soup.face_group.empty()) s.triangle_patch.push_back(soup.face_group[f]);
    }
  }
  s.patch_names = soup.groups;
  return s;
}

}  // namespace froth

// OpenFOAM polyMesh (ASCII): points, faces, owner, neighbour, boundary and cellZones by kind.
// OpenFOAM's rules: each interior face once, owner < neighbour, its normal (right-hand rule)
// out of the owner; interior faces first, in upper-triangular order (by owner, then by
// neighbour); then the border faces, patch by patch, their normals out of the domain.
#include <algorithm>
#include <array>
#include <cctype>
#include <iterator>
#include <numeric>

#include <fmt/format.h>

#include "froth/error.hpp"
#include "froth/io.hpp"
#include "io/atomic_file.hpp"
#include "io/parallel_text.hpp"

namespace froth {
namespace {

constexpr std::array<const char*, kCellKinds> kZoneNames = {"interior", "fringe", "edge", "vertex", "interface_face",
                                                            "interface_edge"};

// Text in memory, handed to the stream a megabyte at a time.
class Chunked {
 public:
  explicit Chunked(std::ostream& out) : out_(out) {}
  ~Chunked() { flush(); }
  template <class... Args>
  void put(fmt::format_string<Args...> f, Args&&... args) {
    fmt::format_to(std::back_inserter(buf_), f, std::forward<Args>(args)...);
    if (buf_.size() > (1 << 20)) flush();
  }
  void flush() {
    out_.write(buf_.data(), std::streamsize(buf_.size()));
    buf_.clear();
  }

 private:
  std::ostream& out_;
  fmt::memory_buffer buf_;
};

void header(Chunked& out, const char* cls, const char* object, const std::string& note = "") {
  out.put("FoamFile\n{{\n    version     2.0;\n    format      ascii;\n    class       {};\n", cls);
  if (!note.empty()) out.put("    note        \"{}\";\n", note);
  out.put("    location    \"constant/polyMesh\";\n    object      {};\n}}\n\n", object);
}

// Patch names as OpenFOAM words: letters, digits and _ (others become _), unique.
std::vector<std::string> foam_patch_names(const PolyMesh& m) {
  std::vector<std::string> out;
  for (const std::string& name : m.patch_names.empty() ? std::vector<std::string>{"walls"} : m.patch_names) {
    std::string w;
    for (char ch : name) w += std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' ? ch : '_';
    if (w.empty() || std::isdigit(static_cast<unsigned char>(w[0]))) w = "patch_" + w;
    while (std::find(out.begin(), out.end(), w) != out.end()) w += "_";
    out.push_back(w);
  }
  return out;
}

// The faces in OpenFOAM's order, each as (a face of the mesh, its owner cell, neighbour or -1).
struct FoamFace {
  int64_t face;
  int32_t owner, neighbour;
};

std::vector<FoamFace> foam_order(const PolyMesh& m, size_t& internal) {
  std::vector<FoamFace> out;
  std::vector<FoamFace> mine;
  for (size_t c = 0; c < m.cell_count(); ++c) {
    mine.clear();
    for (int64_t f = m.cell_face_begin[c]; f < m.cell_face_begin[c + 1]; ++f) {
      const int32_t g = m.face_generator[f];
      if (is_other_piece_generator(g))
        fail(ErrorKind::Usage, "an OpenFOAM mesh needs the whole mesh, not one rank's piece of a partitioned run");
      if (g >= 0 && size_t(g) > c) mine.push_back({f, int32_t(c), g});
    }
    std::sort(mine.begin(), mine.end(), [](const FoamFace& a, const FoamFace& b) {
      return a.neighbour != b.neighbour ? a.neighbour < b.neighbour : a.face < b.face;
    });
    out.insert(out.end(), mine.begin(), mine.end());
  }
  internal = out.size();
  // Border faces patch by patch, in cell order within each.
  for (size_t c = 0; c < m.cell_count(); ++c)
    for (int64_t f = m.cell_face_begin[c]; f < m.cell_face_begin[c + 1]; ++f)
      if (is_border_generator(m.face_generator[f])) out.push_back({f, int32_t(c), -1});
  std::stable_sort(out.begin() + std::ptrdiff_t(internal), out.end(), [&](const FoamFace& a, const FoamFace& b) {
    return m.patch_of(size_t(a.face)) < m.patch_of(size_t(b.face));
  });
  return out;
}

// A case's system/ files, minimal, so that checkMesh and paraFoam run on a new case.
void write_minimal_system(const std::filesystem::path& system) {
  make_output_folder(system);
  const auto dict = [&](const char* object, const char* body) {
    write_atomically(system / object, [&](std::ostream& os) {
      Chunked out(os);
      out.put("FoamFile\n{{\n    version     2.0;\n    format      ascii;\n    class       dictionary;\n"
              "    object      {};\n}}\n\n{}",
              object, body);
    });
  };
  dict("controlDict",
       "application     checkMesh;\nstartFrom       startTime;\nstartTime       0;\nstopAt          endTime;\n"
       "endTime         0;\ndeltaT          1;\nwriteControl    timeStep;\nwriteInterval   1;\n");
  dict("fvSchemes",
       "ddtSchemes {}\ngradSchemes {}\ndivSchemes {}\nlaplacianSchemes {}\ninterpolationSchemes {}\n"
       "snGradSchemes {}\n");
  dict("fvSolution", "");
}

}  // namespace

void write_openfoam(const PolyMesh& m, const std::filesystem::path& dir) {
  if (m.cell_count() > size_t(INT32_MAX))
    fail(ErrorKind::Usage, "OpenFOAM's 32-bit labels cannot number this mesh's cells");
  size_t internal = 0;
  const std::vector<FoamFace> faces = foam_order(m, internal);
  // Points no face uses (none in froth's meshes, but a welded or read mesh may have them) are
  // dropped: checkMesh counts them as an error.
  std::vector<int32_t> new_id(m.points.size(), -1);
  for (const FoamFace& f : faces)
    for (int64_t k = m.face_vertex_begin[f.face]; k < m.face_vertex_begin[f.face + 1]; ++k)
      new_id[size_t(m.face_vertices[k])] = 0;
  int32_t used = 0;
  std::vector<size_t> used_points;
  for (size_t p = 0; p < new_id.size(); ++p)
    if (new_id[p] == 0) new_id[p] = used++, used_points.push_back(p);
  const std::string note = fmt::format("nPoints:{} nCells:{} nFaces:{} nInternalFaces:{}", used, m.cell_count(),
                                       faces.size(), internal);
  // The case's files appear together, or neither they nor the folders made for them.
  OutputGroup files;
  make_output_folder(dir);

  write_atomically(dir / "points", [&](std::ostream& os) {
    Chunked out(os);
    header(out, "vectorField", "points");
    out.put("{}\n(\n", used);
    out.flush();
    write_lines(os, used_points.size(), [&](fmt::memory_buffer& buf, size_t i) {
      const Vec3 p = m.points[used_points[i]];
      fmt::format_to(std::back_inserter(buf), "({:.17g} {:.17g} {:.17g})\n", p.x, p.y, p.z);
    });
    out.put(")\n");
  });
  write_atomically(dir / "faces", [&](std::ostream& os) {
    Chunked out(os);
    header(out, "faceList", "faces");
    out.put("{}\n(\n", faces.size());
    out.flush();
    write_lines(os, faces.size(), [&](fmt::memory_buffer& buf, size_t i) {
      const int64_t b = m.face_vertex_begin[faces[i].face], e = m.face_vertex_begin[faces[i].face + 1];
      auto it = std::back_inserter(buf);
      fmt::format_to(it, "{}({}", e - b, new_id[size_t(m.face_vertices[b])]);
      for (int64_t k = b + 1; k < e; ++k) fmt::format_to(it, " {}", new_id[size_t(m.face_vertices[k])]);
      fmt::format_to(it, ")\n");
    });
    out.put(")\n");
  });
  write_atomically(dir / "owner", [&](std::ostream& os) {
    Chunked out(os);
    header(out, "labelList", "owner", note);
    out.put("{}\n(\n", faces.size());
    out.flush();
    write_lines(os, faces.size(),
                [&](fmt::memory_buffer& buf, size_t i) { fmt::format_to(std::back_inserter(buf), "{}\n", faces[i].owner); });
    out.put(")\n");
  });
  write_atomically(dir / "neighbour", [&](std::ostream& os) {
    Chunked out(os);
    header(out, "labelList", "neighbour", note);
    out.put("{}\n(\n", internal);
    out.flush();
    write_lines(os, internal, [&](fmt::memory_buffer& buf, size_t i) {
      fmt::format_to(std::back_inserter(buf), "{}\n", faces[i].neighbour);
    });
    out.put(")\n");
  });
  write_atomically(dir / "boundary", [&](std::ostream& os) {
    Chunked out(os);
    header(out, "polyBoundaryMesh", "boundary");
    const std::vector<std::string> names = foam_patch_names(m);
    std::vector<size_t> count(names.size(), 0);
    for (size_t k = internal; k < faces.size(); ++k) ++count[size_t(m.patch_of(size_t(faces[k].face)))];
    out.put("{}\n(\n", names.size());
    size_t start = internal;
    for (size_t p = 0; p < names.size(); ++p) {
      out.put("    {}\n    {{\n        type            wall;\n        inGroups        1(wall);\n"
              "        nFaces          {};\n        startFace       {};\n    }}\n",
              names[p], count[p], start);
      start += count[p];
    }
    out.put(")\n");
  });
  // One cellZone per cell kind, so a solver can tell the cells along protected edges apart.
  write_atomically(dir / "cellZones", [&](std::ostream& os) {
    Chunked out(os);
    header(out, "regIOobject", "cellZones");
    // A multi-region mesh: a zone per region after them (chtMultiRegionFoam's splitMeshRegions
    // -cellZones makes the regions' meshes from these).
    out.put("{}\n(\n", kZoneNames.size() + m.region_names.size());
    auto zone = [&](const std::string& name, auto&& in_zone) {
      size_t n = 0;
      for (size_t c = 0; c < m.cell_count(); ++c) n += in_zone(c);
      out.put("{}\n{{\n    type cellZone;\ncellLabels      List<label> {}\n(\n", name, n);
      for (size_t c = 0; c < m.cell_count(); ++c)
        if (in_zone(c)) out.put("{}\n", c);
      out.put(")\n;\n}}\n");
    };
    for (size_t k = 0; k < kZoneNames.size(); ++k) zone(kZoneNames[k], [&](size_t c) { return size_t(m.kinds[c]) == k; });
    for (size_t k = 0; k < m.region_names.size(); ++k)
      zone(m.region_names[k], [&](size_t c) { return m.region_of(c) == int32_t(k); });
    out.put(")\n");
  });
  // DIR = CASE/constant/polyMesh: a case without system/ gets a minimal one.
  const std::filesystem::path constant = std::filesystem::absolute(dir).lexically_normal().parent_path();
  std::error_code ec;
  if (constant.filename() == "constant" && !std::filesystem::exists(constant.parent_path() / "system", ec))
    write_minimal_system(constant.parent_path() / "system");
  files.commit();
}

}  // namespace froth

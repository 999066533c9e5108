// VTK XML UnstructuredGrid (format 1.0, UInt64 headers, appended raw binary) of VTK_POLYHEDRON
// cells in the `faces` / `faceoffsets` layout that VTK 9.1 and ParaView read. Output is a pure
// function of the mesh and the run parameters: no time stamps, no host names.
#include <algorithm>
#include <cstring>
#include <sstream>

#include <fmt/format.h>

#include "froth/io.hpp"
#include "io/atomic_file.hpp"

namespace froth {
namespace {

constexpr uint8_t kVtkPolyhedron = 42;

struct Block {
  const void* data;
  uint64_t bytes;
};

class AppendedWriter {
 public:
  // Registers a block and returns the XML attribute text for its offset.
  std::string add(const void* data, uint64_t bytes) {
    std::string attr = fmt::format("format=\"appended\" offset=\"{}\"", offset_);
    blocks_.push_back({data, bytes});
    offset_ += sizeof(uint64_t) + bytes;
    return attr;
  }
  void write(std::ostream& out) const {
    for (const Block& b : blocks_) {
      out.write(reinterpret_cast<const char*>(&b.bytes), sizeof b.bytes);
      out.write(static_cast<const char*>(b.data), std::streamsize(b.bytes));
    }
  }

 private:
  std::vector<Block> blocks_;
  uint64_t offset_ = 0;
};

template <class Vector>
std::string array(AppendedWriter& w, const Vector& v, const char* type, const char* name, int components = 1) {
  // NumberOfComponents only for vectors: meshio reads a declared single component as a column.
  std::string comps = components > 1 ? fmt::format(" NumberOfComponents=\"{}\"", components) : "";
  return fmt::format("<DataArray type=\"{}\" Name=\"{}\"{} {}/>\n", type, name, comps,
                     w.add(v.data(), v.size() * sizeof(v[0])));
}

std::string version_numbers(std::string v) {
  std::replace(v.begin(), v.end(), '.', ' ');
  return v;
}

}  // namespace

void write_vtu(const PolyMesh& m, const RunReport& run, const std::filesystem::path& path) {
  const size_t n = m.cell_count();
  // Each cell's distinct points (VTK's cell connectivity) and its face stream.
  std::vector<int64_t> connectivity, offsets(n), faces, faceoffsets(n);
  std::vector<uint8_t> types(n, kVtkPolyhedron);
  std::vector<int32_t> kind(n);
  std::vector<int32_t> pts;
  for (size_t c = 0; c < n; ++c) {
    pts.assign(m.face_vertices.begin() + m.face_vertex_begin[m.cell_face_begin[c]],
               m.face_vertices.begin() + m.face_vertex_begin[m.cell_face_begin[c + 1]]);
    std::sort(pts.begin(), pts.end());
    pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
    connectivity.insert(connectivity.end(), pts.begin(), pts.end());
    offsets[c] = int64_t(connectivity.size());
    faces.push_back(m.cell_face_begin[c + 1] - m.cell_face_begin[c]);
    for (int64_t f = m.cell_face_begin[c]; f < m.cell_face_begin[c + 1]; ++f) {
      faces.push_back(m.face_vertex_begin[f + 1] - m.face_vertex_begin[f]);
      for (int64_t k = m.face_vertex_begin[f]; k < m.face_vertex_begin[f + 1]; ++k) faces.push_back(m.face_vertices[k]);
    }
    faceoffsets[c] = int64_t(faces.size());
    kind[c] = int32_t(m.kinds[c]);
  }
  static_assert(sizeof(Vec3) == 3 * sizeof(double));

  AppendedWriter w;
  std::ostringstream xml;
  xml << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      << "<UnstructuredGrid>\n<FieldData>\n"
      << fmt::format("<DataArray type=\"Float64\" Name=\"r\" NumberOfTuples=\"1\" format=\"ascii\">{:.17g}</DataArray>\n", run.r)
      << fmt::format("<DataArray type=\"Float64\" Name=\"weld\" NumberOfTuples=\"1\" format=\"ascii\">{:.17g}</DataArray>\n", run.weld)
      << fmt::format("<DataArray type=\"UInt64\" Name=\"random_seed\" NumberOfTuples=\"1\" format=\"ascii\">{}</DataArray>\n", run.seed)
      // Numeric (major, minor, patch): meshio cannot read VTK string arrays.
      << fmt::format("<DataArray type=\"Int32\" Name=\"version\" NumberOfTuples=\"3\" format=\"ascii\">{}</DataArray>\n",
                     version_numbers(FROTH_VERSION))
      << "</FieldData>\n"
      << fmt::format("<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", m.points.size(), n)
      << "<Points>\n" << array(w, m.points, "Float64", "Points", 3) << "</Points>\n"
      << "<Cells>\n"
      << array(w, connectivity, "Int64", "connectivity") << array(w, offsets, "Int64", "offsets")
      << array(w, types, "UInt8", "types") << array(w, faces, "Int64", "faces")
      << array(w, faceoffsets, "Int64", "faceoffsets") << "</Cells>\n"
      << "<CellData>\n"
      << array(w, m.seeds, "Float64", "seed", 3) << array(w, kind, "Int32", "kind")
      << array(w, m.volumes, "Float64", "volume") << "</CellData>\n"
      << "</Piece>\n</UnstructuredGrid>\n<AppendedData encoding=\"raw\">\n_";
  write_atomically(path, [&](std::ostream& out) {
    out << xml.str();
    w.write(out);
    out << "\n</AppendedData>\n</VTKFile>\n";
  });
}

}  // namespace froth

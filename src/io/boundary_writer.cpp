// The border faces as a VTU surface (VTK_POLYGON cells): VTU has no face data, so the patch of
// each border face, for boundary conditions, is shown here.
#include <fmt/format.h>

#include "froth/io.hpp"
#include "io/atomic_file.hpp"
#include "io/parallel_text.hpp"

namespace froth {

void write_boundary_vtu(const PolyMesh& m, const std::filesystem::path& path) {
  std::vector<int64_t> faces;  // the border faces, in cell order
  std::vector<int64_t> cell_of;
  for (size_t c = 0; c < m.cell_count(); ++c)
    for (int64_t f = m.cell_face_begin[c]; f < m.cell_face_begin[c + 1]; ++f)
      if (is_border_generator(m.face_generator[f])) faces.push_back(f), cell_of.push_back(int64_t(c));
  const std::vector<std::string> names = m.patch_names.empty() ? std::vector<std::string>{"walls"} : m.patch_names;
  write_atomically(path, [&](std::ostream& out) {
    out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
           "header_type=\"UInt64\">\n<UnstructuredGrid>\n<FieldData>\n";
    // Patch names: VTK's ascii String array, each name's bytes then a 0.
    out << fmt::format("<Array type=\"String\" Name=\"patch_names\" NumberOfTuples=\"{}\" format=\"ascii\">\n", names.size());
    for (const std::string& n : names) {
      for (unsigned char ch : n) out << int(ch) << ' ';
      out << "0\n";
    }
    out << "</Array>\n</FieldData>\n";
    out << fmt::format("<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n<Points>\n"
                       "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n",
                       m.points.size(), faces.size());
    write_lines(out, m.points.size(), [&](fmt::memory_buffer& b, size_t p) {
      fmt::format_to(std::back_inserter(b), "{:.17g} {:.17g} {:.17g}\n", m.points[p].x, m.points[p].y, m.points[p].z);
    });
    out << "</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
    write_lines(out, faces.size(), [&](fmt::memory_buffer& b, size_t i) {
      for (int64_t k = m.face_vertex_begin[faces[i]]; k < m.face_vertex_begin[faces[i] + 1]; ++k)
        fmt::format_to(std::back_inserter(b), "{} ", m.face_vertices[k]);
      b.push_back('\n');
    });
    out << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
    int64_t end = 0;
    for (int64_t f : faces) out << (end += m.face_vertex_begin[f + 1] - m.face_vertex_begin[f]) << '\n';
    out << "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
    for (size_t i = 0; i < faces.size(); ++i) out << "7\n";  // VTK_POLYGON
    out << "</DataArray>\n</Cells>\n<CellData>\n<DataArray type=\"Int32\" Name=\"patch\" format=\"ascii\">\n";
    for (int64_t f : faces) out << m.patch_of(size_t(f)) << '\n';
    out << "</DataArray>\n<DataArray type=\"Int64\" Name=\"cell\" format=\"ascii\">\n";
    for (int64_t c : cell_of) out << c << '\n';
    out << "</DataArray>\n</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
  });
}

}  // namespace froth

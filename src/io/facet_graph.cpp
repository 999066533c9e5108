// The facet graph (NumPy .npz) for lattice, particle and finite-volume models, and peridynamic
// nodes (text) for Peridigm and PeriLab: the mesh's cells as points with volumes, and the faces
// between them with their areas, centroids and normals.
#include <cmath>

#include <fmt/format.h>

#include "froth/error.hpp"
#include "froth/io.hpp"
#include "froth/validate.hpp"
#include "io/atomic_file.hpp"
#include "io/npz_writer.hpp"

namespace froth {
namespace {

constexpr int64_t kFacetGraphVersion = 1;

struct FaceGeometry {
  double area = 0;
  Vec3 centroid, normal;  // area-weighted centroid; unit normal by the right-hand rule
};

// Fanned from the vertices' mean: exact for planar faces, and for a face welding left slightly
// non-planar the same triangles as the volume uses.
FaceGeometry face_geometry(const PolyMesh& m, int64_t f) {
  const int64_t b = m.face_vertex_begin[f], e = m.face_vertex_begin[f + 1];
  Vec3 mean{};
  for (int64_t k = b; k < e; ++k) mean = mean + m.points[m.face_vertices[k]];
  mean = (1.0 / double(e - b)) * mean;
  Vec3 twice_area{}, weighted{};
  double sum = 0;
  for (int64_t k = b; k < e; ++k) {
    const Vec3 p = m.points[m.face_vertices[k]], q = m.points[m.face_vertices[k + 1 < e ? k + 1 : b]];
    const Vec3 n = cross(p - mean, q - mean);
    twice_area = twice_area + n;
    const double a = std::sqrt(dot(n, n));
    weighted = weighted + (a / 3) * (mean + p + q);
    sum += a;
  }
  FaceGeometry g;
  g.area = std::sqrt(dot(twice_area, twice_area)) / 2;
  g.centroid = sum > 0 ? (1.0 / sum) * weighted : mean;
  g.normal = g.area > 0 ? (0.5 / g.area) * twice_area : Vec3{};
  return g;
}

// Volume-weighted centroid of cell c: tetrahedra from its `center` (a point it is star-shaped
// from) to each face's fan.
Vec3 cell_centroid(const PolyMesh& m, size_t c) {
  const Vec3 o = m.center_of(c);
  Vec3 weighted{};
  double volume = 0;
  for (int64_t f = m.cell_face_begin[c]; f < m.cell_face_begin[c + 1]; ++f) {
    const int64_t b = m.face_vertex_begin[f], e = m.face_vertex_begin[f + 1];
    Vec3 mean{};
    for (int64_t k = b; k < e; ++k) mean = mean + m.points[m.face_vertices[k]];
    mean = (1.0 / double(e - b)) * mean;
    for (int64_t k = b; k < e; ++k) {
      const Vec3 p = m.points[m.face_vertices[k]], q = m.points[m.face_vertices[k + 1 < e ? k + 1 : b]];
      const double v = dot(mean - o, cross(p - o, q - o)) / 6;
      weighted = weighted + (v / 4) * (o + mean + p + q);
      volume += v;
    }
  }
  return volume != 0 ? (1.0 / volume) * weighted : o;
}

void append(std::vector<double>& v, Vec3 p) { v.insert(v.end(), {p.x, p.y, p.z}); }

// The mesh's volumes, or the cells' own where it has none (a VTU without froth's cell data).
std::vector<double> volumes_of(const PolyMesh& m) {
  if (m.volumes.size() == m.cell_count()) return m.volumes;
  std::vector<double> v(m.cell_count());
  for (size_t c = 0; c < v.size(); ++c) v[c] = cell_volume(m, c);
  return v;
}

}  // namespace

void write_facet_graph(const PolyMesh& m, const std::filesystem::path& path) {
  const size_t n = m.cell_count();
  std::vector<double> seed, centroid, volume = volumes_of(m);
  std::vector<int64_t> kind(n), region(n, 0), piece(n);
  for (size_t c = 0; c < n; ++c) {
    append(seed, m.seeds[c]);
    append(centroid, cell_centroid(m, c));
    kind[c] = int64_t(m.kinds[c]);
    piece[c] = m.piece_of(c);
  }
  std::vector<int64_t> face_cells, border_cell, border_patch, border_plane;
  std::vector<double> face_area, face_centroid, face_normal, face_crossing, border_area, border_centroid, border_normal;
  for (size_t c = 0; c < n; ++c)
    for (int64_t f = m.cell_face_begin[c]; f < m.cell_face_begin[c + 1]; ++f) {
      const int32_t g = m.face_generator[f];
      if (is_other_piece_generator(g))
        fail(ErrorKind::Usage, "a facet graph needs the whole mesh, not one rank's piece of a partitioned run");
      const FaceGeometry geo = face_geometry(m, f);
      if (is_border_generator(g)) {
        border_cell.push_back(int64_t(c));
        border_patch.push_back(0);
        border_plane.push_back(m.border_planes_known ? generator_plane(g) : -1);
        border_area.push_back(geo.area);
        append(border_centroid, geo.centroid);
        append(border_normal, geo.normal);
        continue;
      }
      if (size_t(g) < c) continue;  // each interior face once, from its lower cell
      face_cells.insert(face_cells.end(), {int64_t(c), int64_t(g)});
      face_area.push_back(geo.area);
      append(face_centroid, geo.centroid);
      append(face_normal, geo.normal);
      // Where the segment between the two seeds meets the face's plane (a lattice model's bond
      // point; the two seeds of a seed's pieces coincide, and then there is none: NaN).
      const Vec3 a = m.seeds[c], d = m.seeds[size_t(g)] - m.seeds[c];
      const double t = dot(geo.centroid - a, geo.normal) / dot(d, geo.normal);
      append(face_crossing, std::isfinite(t) ? a + t * d : Vec3{NAN, NAN, NAN});
    }
  write_atomically(path, [&](std::ostream& out) {
    NpzWriter npz(out);
    npz.add("format_version", std::vector<int64_t>{kFacetGraphVersion});
    npz.add("r", std::vector<double>{m.r});
    npz.add("cell_seed", seed, 3);
    npz.add("cell_centroid", centroid, 3);
    npz.add("cell_volume", volume);
    npz.add("cell_kind", kind);
    npz.add("cell_region", region);
    npz.add("cell_piece", piece);
    npz.add("face_cells", face_cells, 2);
    npz.add("face_area", face_area);
    npz.add("face_centroid", face_centroid, 3);
    npz.add("face_normal", face_normal, 3);
    npz.add("face_seed_crossing", face_crossing, 3);
    npz.add("border_cell", border_cell);
    npz.add("border_area", border_area);
    npz.add("border_centroid", border_centroid, 3);
    npz.add("border_normal", border_normal, 3);
    npz.add("border_patch", border_patch);
    npz.add("border_plane", border_plane);
    npz.finish();
  });
}

void write_peridynamic_nodes(const PolyMesh& m, const std::filesystem::path& path) {
  write_atomically(path, [&](std::ostream& out) {
    // Peridigm's text discretization: one node per line, "x y z block_id volume", blocks from 1.
    out << "# x y z block_id volume\n";
    const std::vector<double> volume = volumes_of(m);
    fmt::memory_buffer buf;
    for (size_t c = 0; c < m.cell_count(); ++c) {
      const Vec3 p = cell_centroid(m, c);
      fmt::format_to(std::back_inserter(buf), "{:.17g} {:.17g} {:.17g} 1 {:.17g}\n", p.x, p.y, p.z, volume[c]);
      if (buf.size() > (1 << 20)) out.write(buf.data(), std::streamsize(buf.size())), buf.clear();
    }
    out.write(buf.data(), std::streamsize(buf.size()));
  });
}

}  // namespace froth

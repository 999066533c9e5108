// The facet graph (NumPy .npz) for lattice, particle and finite-volume models, and peridynamic
// nodes (text) for Peridigm and PeriLab: the mesh's cells as points with volumes, and the faces
// between them with their areas, centroids and normals.
#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "froth/error.hpp"
#include "froth/io.hpp"
#include "froth/validate.hpp"
#include "io/atomic_file.hpp"
#include "io/npz_writer.hpp"
#include "io/parallel_text.hpp"

namespace froth {
namespace {

constexpr int64_t kFacetGraphVersion = 2;  // 2: border_across

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

// Volume-weighted centroid of cell c: signed tetrahedra from a point of it to each face's fan.
Vec3 cell_centroid(const PolyMesh& m, size_t c) {
  const Vec3 o = m.fan_origin(c);
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

// The mesh's volumes, or the cells' own where it has none (a VTU without froth's cell data).
std::vector<double> volumes_of(const PolyMesh& m) {
  if (m.volumes.size() == m.cell_count()) return m.volumes;
  std::vector<double> v(m.cell_count());
  for (size_t c = 0; c < v.size(); ++c) v[c] = cell_volume(m, c);
  return v;
}

// Each crack face's face across the crack: the face of the sheet's other side on the same points
// (welding moves the two sides alike), -1 for the other border faces and for a crack face that
// has none. Matched by centroid, which the two orientations of one polygon give within rounding
// (1e-6 r: distinct faces of one side are edges of at least the weld apart).
std::vector<int64_t> faces_across(const PolyMesh& m, const std::vector<int64_t>& patch,
                                  const std::vector<double>& centroid) {
  std::vector<int64_t> across(patch.size(), -1);
  std::map<int64_t, std::pair<size_t, int>> side_of_patch;  // patch -> (crack, side 0 or 1)
  for (size_t k = 0; k < m.crack_names.size(); ++k)
    for (int side = 0; side < 2; ++side) {
      const std::string name = "crack_" + m.crack_names[k] + (side ? "_b" : "_a");
      const auto it = std::find(m.patch_names.begin(), m.patch_names.end(), name);
      if (it != m.patch_names.end()) side_of_patch[it - m.patch_names.begin()] = {k, side};
    }
  if (side_of_patch.empty()) return across;
  std::vector<std::array<std::vector<size_t>, 2>> faces(m.crack_names.size());
  for (size_t b = 0; b < patch.size(); ++b)
    if (const auto it = side_of_patch.find(patch[b]); it != side_of_patch.end())
      faces[it->second.first][size_t(it->second.second)].push_back(b);
  const double tol = 1e-6 * (m.r > 0 ? m.r : 1.0);
  auto at = [&](size_t b) { return Vec3{centroid[3 * b], centroid[3 * b + 1], centroid[3 * b + 2]}; };
  for (auto& sides : faces) {
    std::vector<size_t>& bs = sides[1];
    std::sort(bs.begin(), bs.end(), [&](size_t x, size_t y) { return at(x).x < at(y).x; });
    for (size_t a : sides[0]) {
      const Vec3 p = at(a);
      auto it = std::lower_bound(bs.begin(), bs.end(), p.x - tol, [&](size_t b, double x) { return at(b).x < x; });
      for (; it != bs.end() && at(*it).x <= p.x + tol; ++it)
        if (norm(at(*it) - p) <= tol) across[a] = int64_t(*it), across[*it] = int64_t(a);
    }
  }
  return across;
}

}  // namespace

void write_facet_graph(const PolyMesh& m, const std::filesystem::path& path) {
  const size_t n = m.cell_count();
  std::vector<double> seed(3 * n), centroid(3 * n), volume = volumes_of(m);
  std::vector<int64_t> kind(n), region(n), piece(n), parent(n);
  // Each cell's interior faces (toward a higher cell) and border faces counted, then every face
  // filled in at its place, cells in parallel.
  std::vector<int64_t> interior_at(n + 1, 0), border_at(n + 1, 0);
  for (size_t c = 0; c < n; ++c) {
    for (int64_t f = m.cell_face_begin[c]; f < m.cell_face_begin[c + 1]; ++f) {
      const int32_t g = m.face_generator[f];
      if (is_other_piece_generator(g))
        fail(ErrorKind::Usage, "a facet graph needs the whole mesh, not one rank's piece of a partitioned run");
      interior_at[c + 1] += g >= 0 && size_t(g) > c;
      border_at[c + 1] += is_border_generator(g);
    }
    interior_at[c + 1] += interior_at[c], border_at[c + 1] += border_at[c];
  }
  const size_t ni = size_t(interior_at[n]), nb = size_t(border_at[n]);
  std::vector<int64_t> face_cells(2 * ni), border_cell(nb), border_patch(nb), border_plane(nb);
  std::vector<double> face_area(ni), face_centroid(3 * ni), face_normal(3 * ni), face_crossing(3 * ni),
      border_area(nb), border_centroid(3 * nb), border_normal(3 * nb);
  auto put = [](std::vector<double>& v, size_t i, Vec3 p) { v[3 * i] = p.x, v[3 * i + 1] = p.y, v[3 * i + 2] = p.z; };
#pragma omp parallel for schedule(dynamic, 1024)
  for (size_t c = 0; c < n; ++c) {
    put(seed, c, m.seeds[c]);
    put(centroid, c, cell_centroid(m, c));
    kind[c] = int64_t(m.kinds[c]);
    piece[c] = m.piece_of(c);
    region[c] = m.region_of(c);
    parent[c] = m.parent_of(c);
    size_t i = size_t(interior_at[c]), b = size_t(border_at[c]);
    for (int64_t f = m.cell_face_begin[c]; f < m.cell_face_begin[c + 1]; ++f) {
      const int32_t g = m.face_generator[f];
      if (g >= 0 && size_t(g) < c) continue;  // each interior face once, from its lower cell
      const FaceGeometry geo = face_geometry(m, f);
      if (is_border_generator(g)) {
        border_cell[b] = int64_t(c);
        border_patch[b] = m.patch_of(size_t(f));
        border_plane[b] = m.border_planes_known ? generator_plane(g) : -1;
        border_area[b] = geo.area;
        put(border_centroid, b, geo.centroid);
        put(border_normal, b, geo.normal);
        ++b;
        continue;
      }
      face_cells[2 * i] = int64_t(c), face_cells[2 * i + 1] = g;
      face_area[i] = geo.area;
      put(face_centroid, i, geo.centroid);
      put(face_normal, i, geo.normal);
      // Where the segment between the two seeds meets the face's plane (a lattice model's bond
      // point; the two seeds of a seed's pieces coincide, and then there is none: NaN).
      const Vec3 a = m.seeds[c], d = m.seeds[size_t(g)] - m.seeds[c];
      const double t = dot(geo.centroid - a, geo.normal) / dot(d, geo.normal);
      put(face_crossing, i, std::isfinite(t) ? a + t * d : Vec3{NAN, NAN, NAN});
      ++i;
    }
  }
  const std::vector<int64_t> border_across = faces_across(m, border_patch, border_centroid);
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
    npz.add("cell_parent", parent);
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
    npz.add("border_across", border_across);
    npz.add("patch_names", m.patch_names.empty() ? std::vector<std::string>{"walls"} : m.patch_names);
    npz.finish();
  });
}

void write_peridynamic_nodes(const PolyMesh& m, const std::filesystem::path& path) {
  write_atomically(path, [&](std::ostream& out) {
    // Peridigm's text discretization: one node per line, "x y z block_id volume", blocks from 1.
    out << "# x y z block_id volume\n";
    const std::vector<double> volume = volumes_of(m);
    std::vector<Vec3> at(m.cell_count());
#pragma omp parallel for schedule(dynamic, 1024)
    for (size_t c = 0; c < m.cell_count(); ++c) at[c] = cell_centroid(m, c);
    write_lines(out, m.cell_count(), [&](fmt::memory_buffer& buf, size_t c) {
      fmt::format_to(std::back_inserter(buf), "{:.17g} {:.17g} {:.17g} 1 {:.17g}\n", at[c].x, at[c].y, at[c].z,
                     volume[c]);
    });
  });
}

}  // namespace froth

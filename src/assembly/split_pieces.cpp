#include "common/face_scratch.hpp"
#include "assembly/split_pieces.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include "common/union_find.hpp"

namespace froth {
namespace {

// Signed solid angle of the triangle (a, b, c) seen from the origin (Van Oosterom & Strackee,
// 1983); over a closed surface wound counter-clockwise from outside it sums to 4π at a point
// inside and to 0 outside.
double solid_angle(Vec3 a, Vec3 b, Vec3 c) {
  const double la = norm(a), lb = norm(b), lc = norm(c);
  const double num = dot(a, cross(b, c));
  const double den = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
  return 2 * std::atan2(num, den);
}

// A cell's vertex in one of its regions (a multi-region solid's parts of a cell share the
// interface's vertices, but each part is a piece of its own).
using RegionVertex = std::pair<int32_t, int32_t>;  // (vertex, region)

// One split cell: the piece of each of its faces, in the new order (the anchor's piece first),
// the piece of each of its vertices per region, sorted, for the neighbours' look-ups, and each
// piece's region.
struct Pieces {
  int count = 0;
  std::vector<uint32_t> of_face;
  std::vector<std::pair<RegionVertex, uint32_t>> of_vertex;
  std::vector<int32_t> region;
  uint32_t piece_of_vertex(int32_t v, int32_t in_region) const {
    const RegionVertex key{v, in_region};
    const auto it = std::lower_bound(of_vertex.begin(), of_vertex.end(), std::pair<RegionVertex, uint32_t>{key, 0});
    return it != of_vertex.end() && it->first == key ? it->second : 0;
  }
};

Pieces find_pieces(const PolyMesh& m, const SplitCell& s) {
  Pieces out;
  const int64_t f0 = m.cell_face_begin[s.cell], f1 = m.cell_face_begin[s.cell + 1];
  auto region_of_face = [&](int64_t f) { return scratch_of(m).face_region.empty() ? 0 : scratch_of(m).face_region[size_t(f)]; };
  std::vector<RegionVertex> verts;
  for (int64_t f = f0; f < f1; ++f)
    for (int64_t k = m.face_vertex_begin[f]; k < m.face_vertex_begin[f + 1]; ++k)
      verts.push_back({m.face_vertices[k], region_of_face(f)});
  std::sort(verts.begin(), verts.end());
  verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
  auto local_in = [&](int32_t v, int32_t region) {
    return int32_t(std::lower_bound(verts.begin(), verts.end(), RegionVertex{v, region}) - verts.begin());
  };
  UnionFind parts(verts.size());
  for (int64_t f = f0; f < f1; ++f) {
    const int64_t b = m.face_vertex_begin[f], e = m.face_vertex_begin[f + 1];
    const int32_t rf = region_of_face(f);
    for (int64_t k = b + 1; k < e; ++k) parts.unite(local_in(m.face_vertices[b], rf), local_in(m.face_vertices[k], rf));
  }
  auto local_of_face = [&](int64_t f) { return local_in(m.face_vertices[m.face_vertex_begin[f]], region_of_face(f)); };
  // Components of the cell's boundary numbered in face order.
  std::vector<int32_t> number(verts.size(), -1);
  std::vector<uint32_t> face_piece;
  int components = 0;
  std::vector<int32_t> component_region;
  for (int64_t f = f0; f < f1; ++f) {
    const int32_t root = parts.find(local_of_face(f));
    if (number[root] < 0) number[root] = components++, component_region.push_back(region_of_face(f));
    face_piece.push_back(uint32_t(number[root]));
  }
  // Each component's signed volume and winding number about a point: a component of negative
  // volume is the wall of a void (a cavity smaller than the cell) and belongs to the piece
  // around it, which winds once about any of its points.
  auto winding_about = [&](Vec3 p, std::vector<double>& winding, std::vector<double>* volume) {
    winding.assign(size_t(components), 0.0);
    if (volume) volume->assign(size_t(components), 0.0);
    for (int64_t f = f0; f < f1; ++f) {
      const int64_t b = m.face_vertex_begin[f], e = m.face_vertex_begin[f + 1];
      const size_t c = face_piece[size_t(f - f0)];
      const Vec3 o = m.points[m.face_vertices[b]] - p;
      for (int64_t k = b + 1; k + 1 < e; ++k) {
        const Vec3 u = m.points[m.face_vertices[k]] - p, v = m.points[m.face_vertices[k + 1]] - p;
        winding[c] += solid_angle(o, u, v);
        if (volume) (*volume)[c] += dot(o, cross(u, v)) / 6;
      }
    }
  };
  std::vector<double> winding, volume, around;  // per boundary component
  winding_about(s.anchor, winding, &volume);
  std::vector<int32_t> piece_of(size_t(components), -1);  // component -> piece, in face order
  for (int c = 0; c < components; ++c)
    if (volume[size_t(c)] > 0) piece_of[size_t(c)] = out.count++, out.region.push_back(component_region[size_t(c)]);
  for (int64_t f = f0; f < f1 && out.count > 0; ++f) {
    const size_t c = face_piece[size_t(f - f0)];
    if (piece_of[c] >= 0) continue;
    winding_about(m.points[m.face_vertices[m.face_vertex_begin[f]]], around, nullptr);
    int host = -1;
    for (int h = 0; h < components; ++h)
      if (volume[size_t(h)] > 0 && component_region[size_t(h)] == component_region[c] &&
          (host < 0 || around[size_t(h)] > around[size_t(host)]))
        host = h;
    for (int h = 0; h < components && host < 0; ++h)  // no piece of its region around it: cannot happen
      if (volume[size_t(h)] > 0) host = h;
    piece_of[c] = piece_of[size_t(host)];
  }
  if (out.count == 0)  // cannot happen for a closed cell
    out.count = 1, piece_of.assign(size_t(components), 0), out.region.assign(1, component_region[0]);
  std::vector<double> piece_winding(size_t(out.count), 0.0), piece_volume(size_t(out.count), 0.0);
  for (int c = 0; c < components; ++c) {
    piece_winding[size_t(piece_of[size_t(c)])] += winding[size_t(c)];
    piece_volume[size_t(piece_of[size_t(c)])] += volume[size_t(c)];
  }
  for (uint32_t& p : face_piece) p = uint32_t(piece_of[p]);
  const uint32_t home = uint32_t(std::max_element(piece_winding.begin(), piece_winding.end()) - piece_winding.begin());
  // A piece too small to outlive welding (it would collapse to nothing) stays with the seed's,
  // if it is in the seed's region (a cell never reaches into a region it is not in).
  std::vector<uint32_t> number_of(size_t(out.count));
  std::vector<int32_t> region_of_number{out.region[home]};
  for (int p = 0; p < out.count; ++p) {
    const bool stays = uint32_t(p) == home || (piece_volume[size_t(p)] < s.min_volume && out.region[size_t(p)] == out.region[home]);
    number_of[size_t(p)] = stays ? 0 : uint32_t(region_of_number.size());
    if (!stays) region_of_number.push_back(out.region[size_t(p)]);
  }
  out.count = int(region_of_number.size());
  out.region = std::move(region_of_number);
  auto renumber = [&](uint32_t p) { return number_of[p]; };
  for (uint32_t p : face_piece) out.of_face.push_back(renumber(p));
  for (size_t v = 0; v < verts.size(); ++v)
    out.of_vertex.push_back({verts[v], renumber(uint32_t(piece_of[size_t(number[parts.find(int32_t(v))])]))});
  return out;
}

}  // namespace

void split_pieces(PolyMesh& m, const std::vector<SplitCell>& split, const RegionSet* regions, bool pieces_keep_kind) {
  if (regions) {
    // Every cell's region: its faces' (one region for a cell that is not split).
    m.region.resize(m.cell_count());
    for (size_t c = 0; c < m.cell_count(); ++c)
      m.region[c] = m.cell_face_begin[c] < m.cell_face_begin[c + 1] ? scratch_of(m).face_region[size_t(m.cell_face_begin[c])] : 0;
    m.region_names = regions->names;
  }
  if (split.empty()) {
    scratch_of(m).face_region.clear();
    return;
  }
  const size_t n = m.cell_count();
  std::vector<Pieces> pieces(split.size());
#pragma omp parallel for schedule(dynamic, 1)
  for (size_t k = 0; k < split.size(); ++k) pieces[k] = find_pieces(m, split[k]);

  // first[c]: the new index of old cell c's first piece; which[c]: its entry in `split`, or -1.
  std::vector<int64_t> first(n + 1);
  std::vector<int32_t> which(n, -1);
  for (size_t k = 0; k < split.size(); ++k) which[size_t(split[k].cell)] = int32_t(k);
  first[0] = 0;
  for (size_t c = 0; c < n; ++c) first[c + 1] = first[c] + (which[c] < 0 ? 1 : pieces[size_t(which[c])].count);
  const size_t cells = size_t(first[n]);

  // Each new cell's faces and face vertices, counted, then summed into where each begins.
  const auto piece_count = [&](size_t c) { return which[c] < 0 ? 1 : pieces[size_t(which[c])].count; };
  const auto in_piece = [&](size_t c, int64_t f, int p) {
    return which[c] < 0 || pieces[size_t(which[c])].of_face[size_t(f - m.cell_face_begin[c])] == uint32_t(p);
  };
  PolyMesh out;
  out.r = m.r;
  out.cell_face_begin.assign(cells + 1, 0);
  std::vector<int64_t> cell_fv(cells + 1, 0);
#pragma omp parallel for schedule(dynamic, 1024)
  for (size_t c = 0; c < n; ++c) {
    const int64_t f0 = m.cell_face_begin[c], f1 = m.cell_face_begin[c + 1];
    for (int p = 0; p < piece_count(c); ++p) {
      int64_t faces = 0, vertices = 0;
      for (int64_t f = f0; f < f1; ++f)
        if (in_piece(c, f, p)) ++faces, vertices += m.face_vertex_begin[f + 1] - m.face_vertex_begin[f];
      out.cell_face_begin[size_t(first[c] + p) + 1] = faces, cell_fv[size_t(first[c] + p) + 1] = vertices;
    }
  }
  for (size_t k = 0; k < cells; ++k) out.cell_face_begin[k + 1] += out.cell_face_begin[k], cell_fv[k + 1] += cell_fv[k];
  out.points = std::move(m.points);
  out.seeds.resize(cells), out.kinds.resize(cells), out.piece.assign(cells, 0);
  if (regions) out.region.resize(cells);
  out.face_generator.resize(m.face_count());
  if (regions) scratch_of(out).face_interface_facet.assign(m.face_count(), -1);
  out.face_vertex_begin.resize(m.face_count() + 1);
  out.face_vertices.resize(m.face_vertices.size());
  // Read once here: scratch_of(m) on a mesh without scratch makes one, which threads would race.
  const std::vector<int32_t>& face_region = scratch_of(std::as_const(m)).face_region;
  auto new_generator = [&](int32_t g, int64_t f, size_t c) {
    const int32_t rf = face_region.empty() ? 0 : face_region[size_t(f)];
    if (regions && g < 0 && regions->is_interface(generator_plane(g))) {
      // An interface face: its twin is this cell's part on the other side.
      const int32_t w = which[c];
      const int32_t other = regions->across(generator_plane(m.face_generator[f]), rf);
      return int32_t(first[c] + (w < 0 ? 0 : pieces[size_t(w)].piece_of_vertex(m.face_vertices[m.face_vertex_begin[f]], other)));
    }
    if (g < 0 || is_other_piece_generator(g)) return g;
    const int32_t w = which[size_t(g)];
    // The twin face lies in the piece of the neighbour that has this face's vertices.
    return int32_t(first[size_t(g)] +
                   (w < 0 ? 0 : pieces[size_t(w)].piece_of_vertex(m.face_vertices[m.face_vertex_begin[f]], rf)));
  };
  // Every cell's pieces at their places, in parallel (the copy was most of this stage's time).
#pragma omp parallel for schedule(dynamic, 1024)
  for (size_t c = 0; c < n; ++c) {
    const int64_t f0 = m.cell_face_begin[c], f1 = m.cell_face_begin[c + 1];
    const int32_t w = which[c];
    for (int p = 0; p < piece_count(c); ++p) {
      const size_t cell = size_t(first[c] + p);
      out.seeds[cell] = m.seeds[c];
      out.kinds[cell] = p == 0 || pieces_keep_kind ? m.kinds[c] : CellKind::Fringe;
      out.piece[cell] = uint32_t(p);
      if (regions) out.region[cell] = w < 0 ? m.region[c] : pieces[size_t(w)].region[size_t(p)];
      int64_t face = out.cell_face_begin[cell], fv = cell_fv[cell];
      for (int64_t f = f0; f < f1; ++f) {
        if (!in_piece(c, f, p)) continue;
        const int32_t g = m.face_generator[f];
        if (regions && g < 0 && regions->is_interface(generator_plane(g)))
          scratch_of(out).face_interface_facet[size_t(face)] = generator_plane(g);
        out.face_generator[size_t(face)] = new_generator(g, f, c);
        out.face_vertex_begin[size_t(face)] = fv;
        for (int64_t k = m.face_vertex_begin[f]; k < m.face_vertex_begin[f + 1]; ++k)
          out.face_vertices[size_t(fv++)] = m.face_vertices[k];
        ++face;
      }
    }
  }
  out.face_vertex_begin[size_t(out.cell_face_begin[cells])] = cell_fv[cells];
  out.region_names = std::move(m.region_names);
  m = std::move(out);
}

}  // namespace froth

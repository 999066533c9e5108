// Welding: union-find over short edges, one decision for the whole mesh.
#include "common/face_scratch.hpp"
#include "froth/weld.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "common/closed_edges.hpp"
#include "common/face_plane.hpp"
#include "common/union_find.hpp"

namespace froth {
namespace {

// Face f's vertices mapped through `map`, with consecutive repeats (cyclically) removed.
template <class Map>
void collapsed(const PolyMesh& m, int64_t f, Map&& map, std::vector<int32_t>& out) {
  out.clear();
  for (int64_t k = m.face_vertex_begin[f]; k < m.face_vertex_begin[f + 1]; ++k) {
    const int32_t v = map(m.face_vertices[k]);
    if (out.empty() || out.back() != v) out.push_back(v);
  }
  while (out.size() > 1 && out.back() == out.front()) out.pop_back();
}

// Six times the volume cell c's faces enclose, each fanned from its centroid, with vertex ids
// mapped by `id` (faces left with fewer than three vertices dropped) and placed by `at`.
template <class Id, class At>
double cell_volume6(const PolyMesh& m, size_t c, Id&& id, At&& at, std::vector<int32_t>& face) {
  double v6 = 0;
  const Vec3 o = m.seeds[c];
  for (int64_t f = m.cell_face_begin[c]; f < m.cell_face_begin[c + 1]; ++f) {
    collapsed(m, f, id, face);
    if (face.size() < 3) continue;
    Vec3 centroid{};
    for (int32_t v : face) centroid = centroid + (at(v) - o);
    centroid = (1.0 / double(face.size())) * centroid;
    for (size_t k = 0; k < face.size(); ++k)
      v6 += dot(centroid, cross(at(face[k]) - o, at(face[(k + 1) % face.size()]) - o));
  }
  return v6;
}

// One pass over the mesh as it is, in steps that share the clusters being decided.
class WeldPass {
 public:
  WeldPass(PolyMesh& m, double w, double r) : m(m), w(w), r(r), twins(scratch_of(std::as_const(m)).point_twins) {
    st.tolerance = w;
  }
  WeldStats run(std::vector<std::pair<int32_t, int32_t>>& edges,
                const std::function<void(const std::vector<size_t>&)>& before_change) {
    if (!find_short_edges(edges)) return st;
    find_member_faces();
    // Later passes only change cells with a vertex moved here: these cells (see weld_mesh).
    if (before_change) before_change(cells);
    gather_planes();
    decide_clusters();
    move_points();
    rewrite_faces();
    measure_after(edges);
    m.volumes.clear();
    m.quality.clear();
    return st;
  }

 private:
  bool find_short_edges(std::vector<std::pair<int32_t, int32_t>>& edges);
  void find_member_faces();
  void gather_planes();
  void decide_clusters();
  void mirror_clusters();
  void spread_refusals();
  bool refuse_pinches();
  bool refuse_off_plane();
  bool refuse_for_cells();
  void find_clusters();
  // Where a staying vertex goes: its cluster's target, or its own place if it is alone.
  Vec3 destination(int32_t root) const {
    const auto it = member[root] ? clusters.find(root) : clusters.end();
    return it != clusters.end() && it->second.count > 1 ? it->second.to : m.points[root];
  }
  // A vertex stays (with a new id) unless welding merged it into another, its cluster's root.
  bool stays(size_t v) { return !member[v] || uf.find(int32_t(v)) == int32_t(v); }
  void move_points();
  void rewrite_faces();
  void measure_after(std::vector<std::pair<int32_t, int32_t>>& edges);

  PolyMesh& m;
  const double w, r;
  // A crack point's copies across the sheets it lies on (FaceScratch::point_twins; empty: no
  // cracks), moved alike.
  const PointTwins& twins;
  // f(x) for v and its copies: its twins, and theirs where sheets cross (four copies).
  template <class F>
  void for_copies(int32_t v, F&& f) const {
    int32_t group[8] = {v};
    int n = 1;
    for (int i = 0; i < n && !twins.empty(); ++i)
      for (const auto& [sheet, t] : twins.of(group[i]))
        if (n < 8 && std::find(group, group + n, t) == group + n) group[n++] = t;
    for (int i = 0; i < n; ++i) f(group[i]);
  }
  int32_t twin_across(int32_t v, int32_t sheet) const {
    for (const auto& [s, t] : twins.of(v))
      if (s == sheet) return t;
    return -1;
  }
  // The smallest id among a crack point's copies, which breaks keepers' ties the same way on
  // every copy.
  int32_t canonical(int32_t v) const {
    int32_t least = v;
    for_copies(v, [&](int32_t x) { least = std::min(least, x); });
    return least;
  }
  WeldStats st;
  std::vector<std::pair<int32_t, int32_t>> short_edges;
  std::vector<uint8_t> refused, member;  // per point
  std::vector<int64_t> member_faces;     // faces with a vertex on a short edge
  std::vector<size_t> cells;             // the cells welding can change
  // Border planes of every vertex on a short edge, and a multi-region solid's interface facets
  // (one numbering: both are the regions' facets), which bind a vertex the same way.
  std::map<int32_t, std::vector<int32_t>> planes;
  UnionFind uf{0};
  std::vector<int32_t> cyc, sorted, root;
  // Per cluster root, the vertex on the most border planes (the smallest id on a tie): it
  // keeps its place.
  struct Keeper {
    int32_t vertex = -1;
    const std::vector<int32_t>* planes = nullptr;
  };
  std::map<int32_t, Keeper> keeper;
  // A cluster with a border vertex goes to its keeper, any other to its centroid: worked out
  // before any point moves, as the points are then renumbered in place.
  struct Cluster {
    Vec3 sum{};
    int count = 0;
    int32_t keeper = -1;
    Vec3 to{};
  };
  std::map<int32_t, Cluster> clusters;
  std::vector<int32_t> new_id;  // per old point
  // The faces with a member vertex, renumbered and collapsed: faces [member_begin[i], ...).
  std::vector<int32_t> member_vertices;
  std::vector<size_t> member_begin{0};
};

// One parallel pass: the short edges (in face order, deduplicated: each is seen from several
// faces), the shortest edge and the border's area. `edges`: the short edges if known (later
// passes), else empty and found by a scan of all faces. False if there are none.
bool WeldPass::find_short_edges(std::vector<std::pair<int32_t, int32_t>>& edges) {
  const size_t nf = m.face_count(), chunk = 1 << 14, chunks = (nf + chunk - 1) / chunk;
  std::vector<std::vector<std::pair<int32_t, int32_t>>> found(chunks);
  double shortest2 = INFINITY;
  std::vector<double> chunk_area(chunks, 0.0);  // summed in chunk order: the same for any thread count
  const bool scan = edges.empty();
#pragma omp parallel for schedule(dynamic, 1) reduction(min : shortest2)
  for (size_t ch = 0; ch < (scan ? chunks : 0); ++ch)
    for (size_t f = ch * chunk; f < std::min(nf, (ch + 1) * chunk); ++f) {
      const int64_t b = m.face_vertex_begin[f], e = m.face_vertex_begin[f + 1];
      Vec3 n{};
      for (int64_t k = b; k < e; ++k) {
        const int32_t u = m.face_vertices[k], v = m.face_vertices[k + 1 < e ? k + 1 : b];
        const double l2 = norm2(m.points[u] - m.points[v]);
        shortest2 = std::min(shortest2, l2);
        if (u < v && l2 < w * w) found[ch].push_back({u, v});
        n = n + cross(m.points[u], m.points[v]);
      }
      if (is_border_generator(m.face_generator[f])) chunk_area[ch] += norm(n) / 2;
    }
  for (double a : chunk_area) st.border_area += a;
  st.shortest_edge_before = std::isfinite(shortest2) ? std::sqrt(shortest2) : 0;
  short_edges.clear();
  short_edges.swap(edges);
  for (auto& f : found) short_edges.insert(short_edges.end(), f.begin(), f.end());
  if (short_edges.empty()) {
    st.shortest_edge_after = st.shortest_edge_before;
    return false;
  }
  std::sort(short_edges.begin(), short_edges.end());
  short_edges.erase(std::unique(short_edges.begin(), short_edges.end()), short_edges.end());

  return true;
}

// Faces with a vertex on a short edge: the only ones welding can change; and their cells.
void WeldPass::find_member_faces() {
  const size_t nf = m.face_count(), chunk = 1 << 14, chunks = (nf + chunk - 1) / chunk;
  refused.assign(m.points.size(), 0), member.assign(m.points.size(), 0);
  for (auto [u, v] : short_edges)
    for (int32_t y : {u, v}) for_copies(y, [&](int32_t x) { member[size_t(x)] = 1; });
  std::vector<std::vector<int64_t>> touched(chunks);
#pragma omp parallel for schedule(dynamic, 1)
  for (size_t ch = 0; ch < chunks; ++ch)
    for (size_t f = ch * chunk; f < std::min(nf, (ch + 1) * chunk); ++f)
      for (int64_t k = m.face_vertex_begin[f]; k < m.face_vertex_begin[f + 1]; ++k)
        if (member[m.face_vertices[k]]) {
          touched[ch].push_back(int64_t(f));
          break;
        }
  for (auto& t : touched) member_faces.insert(member_faces.end(), t.begin(), t.end());
  // The cells welding can change.
  for (int64_t f : member_faces)
    cells.push_back(size_t(std::upper_bound(m.cell_face_begin.begin(), m.cell_face_begin.end(), f) -
                           m.cell_face_begin.begin() - 1));
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());

}

void WeldPass::gather_planes() {
  for (auto [u, v] : short_edges)
    for (int32_t y : {u, v}) for_copies(y, [&](int32_t x) { planes[x]; });
  for (int64_t f : member_faces) {
    const int32_t g = m.face_generator[f];
    const int32_t plane = is_border_generator(g)             ? generator_plane(g)
                          : scratch_of(m).face_interface_facet.empty() ? -1
                                                           : scratch_of(m).face_interface_facet[size_t(f)];
    if (plane < 0) continue;
    for (int64_t k = m.face_vertex_begin[f]; k < m.face_vertex_begin[f + 1]; ++k) {
      auto it = planes.find(m.face_vertices[k]);
      if (it == planes.end()) continue;
      auto& p = it->second;
      if (std::find(p.begin(), p.end(), plane) == p.end()) p.push_back(plane);
    }
  }
  for (auto& [v, p] : planes) std::sort(p.begin(), p.end());
}

// Merge, then refuse every cluster that would make a face touch itself or move a vertex off a
// border plane it lies on (a cluster needs one vertex on every plane its members are on: it keeps
// its place, so the domain's features stay where they are), or leave a cell open or flattened,
// and merge again without them, until no cluster is refused.
void WeldPass::decide_clusters() {
  root.assign(m.points.size(), 0);
  for (;;) {
    uf = UnionFind(m.points.size());
    for (auto [u, v] : short_edges)
      if (!refused[u] && !refused[v]) uf.unite(u, v);
    mirror_clusters();
    bool refused_any = refuse_pinches();
    refused_any |= refuse_off_plane();
    if (!refused_any) refused_any = refuse_for_cells();
    if (!refused_any) break;
    spread_refusals();
  }
  {  // refused vertices stay apart in uf: their clusters are counted by their own short edges
    UnionFind refused_clusters(m.points.size());
    for (auto [u, v] : short_edges)
      if (refused[u] && refused[v]) refused_clusters.unite(u, v);
    for (size_t v = 0; v < refused.size(); ++v)
      st.clusters_refused += refused[v] && refused_clusters.find(int32_t(v)) == int32_t(v);
  }
  find_clusters();
}

// A crack's copies weld alike (issue 38): two points of one cluster with twins across one sheet
// put those twins in one cluster too, sheet by sheet, until that holds every way.
void WeldPass::mirror_clusters() {
  if (twins.empty()) return;
  for (bool changed = true; changed;) {
    changed = false;
    std::map<std::pair<int32_t, int32_t>, int32_t> first;  // (cluster root, sheet) -> its first point with a twin across it
    for (const auto& [v, p] : planes) {
      if (refused[v]) continue;
      for (const auto& [sheet, t] : twins.of(v)) {
        if (refused[t]) continue;
        const auto [it, added] = first.try_emplace({uf.find(v), sheet}, v);
        if (!added) changed |= uf.unite(t, twin_across(it->second, sheet));
      }
    }
  }
}

// A refused vertex refuses its cluster (the vertices joined to it by short edges, and by the
// mirror of the clusters above: its twin).
void WeldPass::spread_refusals() {
  for (bool spread = true; spread;) {
    spread = false;
    for (auto [u, v] : short_edges)
      if (refused[u] != refused[v]) refused[u] = refused[v] = 1, spread = true;
    if (twins.empty()) continue;
    for (const auto& [v, p] : planes)
      for (const auto& [sheet, t] : twins.of(v))
        if (refused[v] != refused[t]) refused[v] = refused[t] = 1, spread = true;
  }
}

// A cluster that would make a face touch itself (a vertex twice, not in a row) is refused
// whole: every vertex whose root is the repeated one.
bool WeldPass::refuse_pinches() {
  bool refused_any = false;
  for (int64_t f : member_faces) {
    const int64_t b = m.face_vertex_begin[f], e = m.face_vertex_begin[f + 1];
    collapsed(m, f, [&](int32_t v) { return uf.find(v); }, cyc);
    sorted = cyc;
    std::sort(sorted.begin(), sorted.end());
    for (size_t k = 1; k < sorted.size(); ++k)
      if (sorted[k] == sorted[k - 1]) {
        // Refuse the whole cluster: every vertex whose root is this one.
        for (int64_t j = b; j < e; ++j)
          if (uf.find(m.face_vertices[j]) == sorted[k]) refused[m.face_vertices[j]] = 1;
        refused_any = true;
      }
  }
  return refused_any;
}

// Per cluster root, the vertex on the most border planes keeps its place; a member on a plane
// the keeper is not on would leave it, and is refused.
bool WeldPass::refuse_off_plane() {
  bool refused_any = false;
  keeper.clear();
  for (const auto& [v, p] : planes) {
    if (refused[v]) continue;
    Keeper& k = keeper[uf.find(v)];
    if (!k.planes || p.size() > k.planes->size() ||
        (p.size() == k.planes->size() && canonical(v) < canonical(k.vertex)))
      k = {v, &p};
  }
  for (const auto& [v, p] : planes) {
    if (refused[v]) continue;
    const std::vector<int32_t>& kept = *keeper[uf.find(v)].planes;
    if (!std::includes(kept.begin(), kept.end(), p.begin(), p.end())) refused[v] = 1, refused_any = true;
  }
  return refused_any;
}

// A cell that would no longer close (a cluster spanning a cell thinner than w folds its faces
// onto each other: a domain whose details are below w) keeps all its vertices. In parallel over
// the cells, from the clusters' roots found once (find compresses paths).
bool WeldPass::refuse_for_cells() {
  bool refused_any = false;
  for (const auto& [v, p] : planes) root[v] = uf.find(v);  // every member (twins too)
  std::vector<uint8_t> open_cell(cells.size(), 0);
#pragma omp parallel
  {
    EdgeUses closure;
    std::vector<int32_t> face;
#pragma omp for schedule(dynamic, 64)
    for (size_t i = 0; i < cells.size(); ++i) {
      const size_t c = cells[i];
      closure.clear();
      for (int64_t f = m.cell_face_begin[c]; f < m.cell_face_begin[c + 1]; ++f) {
        collapsed(m, f, [&](int32_t v) { return member[v] ? root[v] : v; }, face);
        for (size_t k = 0; face.size() >= 3 && k < face.size(); ++k)
          closure.add(uint32_t(face[k]), uint32_t(face[(k + 1) % face.size()]));
      }
      open_cell[i] = !closure.each_once_each_way();
    }
  }
  // A cell that would close but lose half its volume or more (a piece of a cell smaller
  // than w, cut off by an interface, flattened onto itself) keeps its vertices too.
  find_clusters();
#pragma omp parallel
  {
    std::vector<int32_t> face;
#pragma omp for schedule(dynamic, 64)
    for (size_t i = 0; i < cells.size(); ++i) {
      if (open_cell[i]) continue;
      const size_t c = cells[i];
      const double before = cell_volume6(m, c, [](int32_t v) { return v; }, [&](int32_t v) { return m.points[v]; }, face);
      const double after = cell_volume6(m, c, [&](int32_t v) { return member[v] ? root[v] : v; }, [&](int32_t v) { return destination(v); }, face);
      open_cell[i] = !(after > 0.5 * before);
    }
  }
  for (size_t i = 0; i < cells.size(); ++i) {
    if (!open_cell[i]) continue;
    const size_t c = cells[i];
    for (int64_t k = m.face_vertex_begin[m.cell_face_begin[c]]; k < m.face_vertex_begin[m.cell_face_begin[c + 1]]; ++k)
      if (const int32_t v = m.face_vertices[k]; member[v] && !refused[v]) refused[v] = 1, refused_any = true;
  }
  return refused_any;
}

void WeldPass::find_clusters() {
  clusters.clear();
  for (const auto& [v, p] : planes) {
    if (refused[v]) continue;
    Cluster& c = clusters[uf.find(v)];
    c.sum = c.sum + m.points[v];
    ++c.count;
    const Keeper& k = keeper.at(uf.find(v));
    if (!k.planes->empty()) c.keeper = k.vertex;
  }
  for (auto& [root, c] : clusters) c.to = c.keeper >= 0 ? m.points[c.keeper] : (1.0 / c.count) * c.sum;
}

// New points: one per root, in id order; every old point's new id.
void WeldPass::move_points() {
    const size_t np = m.points.size();
  new_id.assign(np, -1);
  int32_t kept = 0;
  for (size_t v = 0; v < np; ++v)
    if (stays(v)) new_id[v] = kept++;
  for (size_t v = 0; v < np; ++v) {
    if (!member[v]) continue;
    const int32_t root = uf.find(int32_t(v));
    if (root != int32_t(v)) ++st.edges_collapsed, new_id[v] = new_id[root];
    st.max_displacement = std::max(st.max_displacement, norm(destination(root) - m.points[v]));
  }
  // In place: new_id[v] <= v, and point v is read before any later one is written over it.
  for (size_t v = 0; v < np; ++v)
    if (stays(v)) m.points[new_id[v]] = destination(int32_t(v));
  m.points.resize(size_t(kept));
  if (!twins.empty()) {  // each cluster's twin across a sheet is its twin cluster (mirror_clusters)
    std::vector<std::array<int32_t, 3>> moved;  // (point, sheet, twin)
    for (size_t v = 0; v < np; ++v)
      if (stays(v))
        for (const auto& [sheet, t] : twins.of(int32_t(v)))
          if (const int32_t to = new_id[size_t(t)]; to != new_id[v]) moved.push_back({new_id[v], sheet, to});  // (a merged point's is its root's)
    std::sort(moved.begin(), moved.end());
    moved.erase(std::unique(moved.begin(), moved.end()), moved.end());
    std::vector<std::array<int32_t, 3>> both_ways;  // (only pairs both ways, one per point and sheet, stay twins)
    for (size_t i = 0; i < moved.size(); ++i) {
      const auto& [v, sheet, to] = moved[i];
      const bool alone = (i == 0 || moved[i - 1][0] != v || moved[i - 1][1] != sheet) &&
                         (i + 1 == moved.size() || moved[i + 1][0] != v || moved[i + 1][1] != sheet);
      if (alone && std::binary_search(moved.begin(), moved.end(), std::array<int32_t, 3>{to, sheet, v})) both_ways.push_back(moved[i]);
    }
    scratch_of(m).point_twins = PointTwins::from(std::move(both_ways), size_t(kept));
  }

}

// Faces. Only faces with a member vertex can lose vertices (or vanish, with fewer than three
// left): their new vertex lists are made first; every other face is renumbered where it is. The
// arrays are then rewritten in place from the first face that shrank on, which keeps the peak
// memory of a welded run that of the mesh (a rebuilt copy of the face arrays added half of it at
// 1e6 cells).
void WeldPass::rewrite_faces() {
  const size_t nf = m.face_count();
  member_vertices.clear(), member_begin.assign(1, 0);
  for (int64_t f : member_faces) {
    collapsed(m, f, [&](int32_t v) { return new_id[v]; }, cyc);
    member_vertices.insert(member_vertices.end(), cyc.begin(), cyc.end());
    member_begin.push_back(member_vertices.size());
  }
  const int64_t entries = m.face_vertex_begin[nf];
#pragma omp parallel for schedule(static)
  for (int64_t k = 0; k < entries; ++k) m.face_vertices[k] = new_id[m.face_vertices[k]];
  int64_t first = int64_t(nf);  // the first face that shrinks
  for (size_t i = 0; i < member_faces.size(); ++i) {
    const int64_t f = member_faces[i], n = int64_t(member_begin[i + 1] - member_begin[i]);
    if (n == m.face_vertex_begin[f + 1] - m.face_vertex_begin[f]) {
      std::copy(member_vertices.begin() + member_begin[i], member_vertices.begin() + member_begin[i + 1],
                m.face_vertices.begin() + m.face_vertex_begin[f]);
    } else if (first == int64_t(nf)) {
      first = f;
    }
    if (n < 3) ++st.faces_removed;
  }
  if (first < int64_t(nf)) {
    // Faces before `first` stay; from there each face moves down to the end of the kept ones
    // (never past its own start, as faces only shrink), and each cell's first face follows.
    const size_t nc = m.cell_count();
    size_t cell = size_t(std::upper_bound(m.cell_face_begin.begin(), m.cell_face_begin.begin() + nc, first) -
                         m.cell_face_begin.begin());
    size_t i = size_t(std::lower_bound(member_faces.begin(), member_faces.end(), first) - member_faces.begin());
    int64_t face = first, entry = m.face_vertex_begin[first];
    for (int64_t f = first; f < int64_t(nf); ++f) {
      while (cell < nc && m.cell_face_begin[cell] == f) m.cell_face_begin[cell++] = face;
      const int64_t b = m.face_vertex_begin[f], e = m.face_vertex_begin[f + 1];
      const int32_t generator = m.face_generator[f];
      const int32_t facet = scratch_of(m).face_interface_facet.empty() ? -1 : scratch_of(m).face_interface_facet[size_t(f)];
      if (i < member_faces.size() && member_faces[i] == f) {
        const size_t mb = member_begin[i], me = member_begin[i + 1];
        ++i;
        if (me - mb < 3) continue;
        std::copy(member_vertices.begin() + mb, member_vertices.begin() + me, m.face_vertices.begin() + entry);
        m.face_vertex_begin[face] = entry;
        entry += int64_t(me - mb);
      } else {
        std::copy(m.face_vertices.begin() + b, m.face_vertices.begin() + e, m.face_vertices.begin() + entry);
        m.face_vertex_begin[face] = entry;
        entry += e - b;
      }
      if (!scratch_of(m).face_interface_facet.empty()) scratch_of(m).face_interface_facet[size_t(face)] = facet;
      m.face_generator[face++] = generator;
    }
    while (cell <= nc) m.cell_face_begin[cell++] = face;
    m.face_vertex_begin[face] = entry;
    m.face_generator.resize(size_t(face));
    if (!scratch_of(m).face_interface_facet.empty()) scratch_of(m).face_interface_facet.resize(size_t(face));
    m.face_vertex_begin.resize(size_t(face) + 1);
    m.face_vertices.resize(size_t(entry));
  }

}

// The shortest edge now; and, of the faces that had a merged vertex, the non-planarity (distance
// of each vertex from the best-fit plane) and the edges still shorter than w, which are the only
// places the next pass needs to look.
void WeldPass::measure_after(std::vector<std::pair<int32_t, int32_t>>& edges) {
  const size_t faces_after = m.face_count();
  double shortest_after2 = INFINITY;
#pragma omp parallel for schedule(static) reduction(min : shortest_after2)
  for (size_t f = 0; f < faces_after; ++f) {
    const int64_t b = m.face_vertex_begin[f], e = m.face_vertex_begin[f + 1];
    for (int64_t k = b; k < e; ++k)
      shortest_after2 = std::min(shortest_after2, norm2(m.points[m.face_vertices[k]] - m.points[m.face_vertices[k + 1 < e ? k + 1 : b]]));
  }
  st.shortest_edge_after = std::isfinite(shortest_after2) ? std::sqrt(shortest_after2) : 0;

  const Buffer<Vec3>& points = m.points;
  for (size_t i = 0; i < member_faces.size(); ++i) {
    cyc.assign(member_vertices.begin() + member_begin[i], member_vertices.begin() + member_begin[i + 1]);
    if (cyc.size() < 3) continue;
    for (size_t k = 0; k < cyc.size(); ++k) {
      const int32_t u = cyc[k], v = cyc[(k + 1) % cyc.size()];
      if (u < v && norm2(points[u] - points[v]) < w * w) edges.push_back({u, v});
    }
    if (cyc.size() == 3) continue;
    const FacePlane plane = best_fit_plane(cyc.size(), [&](size_t k) { return points[cyc[k]]; });
    if (norm2(plane.normal) == 0) continue;
    for (int32_t v : cyc)
      st.max_nonplanarity = std::max(st.max_nonplanarity, std::abs(dot(plane.normal, points[v] - plane.centroid)) / r);
  }

}

}  // namespace

WeldStats weld_mesh(PolyMesh& m, double w, double r,
                    const std::function<void(const std::vector<size_t>& cells)>& before_change) {
  // Merged vertices move (to the keeper or the centroid), which can make a neighbouring edge
  // shorter than w: repeat until a pass finds nothing more to merge.
  std::vector<std::pair<int32_t, int32_t>> edges;
  // A later pass's short edges all have a vertex the first pass moved, so the cells it changes
  // were changed by the first pass already: before_change is told once.
  WeldStats total = WeldPass(m, w, r).run(edges, before_change);
  for (int pass = 1; pass < 16 && !edges.empty(); ++pass) {
    const WeldStats more = WeldPass(m, w, r).run(edges, {});
    if (more.edges_collapsed == 0) break;
    total.edges_collapsed += more.edges_collapsed;
    total.faces_removed += more.faces_removed;
    total.clusters_refused = more.clusters_refused;
    total.shortest_edge_after = more.shortest_edge_after;
    total.max_displacement += more.max_displacement;  // a bound on the total movement
    total.max_nonplanarity = std::max(total.max_nonplanarity, more.max_nonplanarity);
  }
  return total;
}

}  // namespace froth

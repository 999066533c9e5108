// Welding: union-find over short edges, one decision for the whole mesh.
#include "froth/weld.hpp"

#include <algorithm>
#include <cmath>
#include <map>

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

// One pass: merges along the edges shorter than w as they are. `edges`: the short edges if known (later passes), else empty and found by a scan of all
// faces; on return, the edges shorter than w among the faces this pass changed.
WeldStats weld_pass(PolyMesh& m, double w, double r, std::vector<std::pair<int32_t, int32_t>>& edges,
                    const std::function<void(const std::vector<size_t>&)>& before_change) {
  WeldStats st;
  st.tolerance = w;
  // One parallel pass: the short edges (in face order, deduplicated below: each is seen from
  // several faces), the shortest edge and the border's area.
  const size_t nf = m.face_count(), chunk = 1 << 14, chunks = (nf + chunk - 1) / chunk;
  std::vector<std::vector<std::pair<int32_t, int32_t>>> found(chunks);
  double shortest2 = INFINITY, area = 0;
  const bool scan = edges.empty();
#pragma omp parallel for schedule(dynamic, 1) reduction(min : shortest2) reduction(+ : area)
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
      if (is_border_generator(m.face_generator[f])) area += norm(n) / 2;
    }
  st.border_area = area;
  st.shortest_edge_before = std::isfinite(shortest2) ? std::sqrt(shortest2) : 0;
  std::vector<std::pair<int32_t, int32_t>> short_edges;
  short_edges.swap(edges);
  for (auto& f : found) short_edges.insert(short_edges.end(), f.begin(), f.end());
  if (short_edges.empty()) {
    st.shortest_edge_after = st.shortest_edge_before;
    return st;
  }
  std::sort(short_edges.begin(), short_edges.end());
  short_edges.erase(std::unique(short_edges.begin(), short_edges.end()), short_edges.end());

  // Faces with a vertex on a short edge: the only ones welding can change.
  std::vector<uint8_t> refused(m.points.size(), 0), member(m.points.size(), 0);
  for (auto [u, v] : short_edges) member[u] = member[v] = 1;
  std::vector<std::vector<int64_t>> touched(chunks);
#pragma omp parallel for schedule(dynamic, 1)
  for (size_t ch = 0; ch < chunks; ++ch)
    for (size_t f = ch * chunk; f < std::min(nf, (ch + 1) * chunk); ++f)
      for (int64_t k = m.face_vertex_begin[f]; k < m.face_vertex_begin[f + 1]; ++k)
        if (member[m.face_vertices[k]]) {
          touched[ch].push_back(int64_t(f));
          break;
        }
  std::vector<int64_t> member_faces;
  for (auto& t : touched) member_faces.insert(member_faces.end(), t.begin(), t.end());
  if (before_change) {
    // Later passes only change cells with a vertex moved here: these cells (see weld_mesh).
    std::vector<size_t> cells;
    for (int64_t f : member_faces)
      cells.push_back(size_t(std::upper_bound(m.cell_face_begin.begin(), m.cell_face_begin.end(), f) -
                             m.cell_face_begin.begin() - 1));
    cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
    before_change(cells);
  }

  // Border planes of every vertex on a short edge.
  std::map<int32_t, std::vector<int32_t>> planes;
  for (auto [u, v] : short_edges) planes[u], planes[v];
  for (int64_t f : member_faces) {
    if (!is_border_generator(m.face_generator[f])) continue;
    for (int64_t k = m.face_vertex_begin[f]; k < m.face_vertex_begin[f + 1]; ++k) {
      auto it = planes.find(m.face_vertices[k]);
      if (it == planes.end()) continue;
      auto& p = it->second;
      if (std::find(p.begin(), p.end(), m.face_generator[f]) == p.end()) p.push_back(m.face_generator[f]);
    }
  }
  for (auto& [v, p] : planes) std::sort(p.begin(), p.end());

  // Merge, then refuse every cluster that would make a face touch itself (a vertex twice, not
  // in a row) or move a vertex off a border plane it lies on (a cluster needs one vertex on every
  // plane its members are on: it keeps its place, so the domain's features stay where they
  // are), and merge again without them, until no cluster is refused.
  UnionFind uf(m.points.size());
  std::vector<int32_t> cyc, sorted;
  // Per cluster root, the vertex on the most border planes (the smallest id on a tie): it
  // keeps its place.
  struct Keeper {
    int32_t vertex = -1;
    const std::vector<int32_t>* planes = nullptr;
  };
  std::map<int32_t, Keeper> keeper;
  for (;;) {
    uf = UnionFind(m.points.size());
    for (auto [u, v] : short_edges)
      if (!refused[u] && !refused[v]) uf.unite(u, v);
    bool pinched = false;
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
          pinched = true;
        }
    }
    keeper.clear();
    for (const auto& [v, p] : planes) {
      if (refused[v]) continue;
      Keeper& k = keeper[uf.find(v)];
      if (!k.planes || p.size() > k.planes->size()) k = {v, &p};
    }
    for (const auto& [v, p] : planes) {
      if (refused[v]) continue;
      const std::vector<int32_t>& kept = *keeper[uf.find(v)].planes;
      if (!std::includes(kept.begin(), kept.end(), p.begin(), p.end())) refused[v] = 1, pinched = true;
    }
    if (!pinched) break;
    for (bool spread = true; spread;) {  // refuse the rest of those clusters too
      spread = false;
      for (auto [u, v] : short_edges)
        if (refused[u] != refused[v]) refused[u] = refused[v] = 1, spread = true;
    }
  }
  for (size_t v = 0; v < refused.size(); ++v) st.clusters_refused += refused[v] && uf.find(int32_t(v)) == int32_t(v);

  // A cluster with a border vertex goes to its keeper, any other to its centroid.
  struct Cluster {
    Vec3 sum{};
    int count = 0;
    int32_t keeper = -1;
  };
  std::map<int32_t, Cluster> clusters;
  for (const auto& [v, p] : planes) {
    if (refused[v]) continue;
    Cluster& c = clusters[uf.find(v)];
    c.sum = c.sum + m.points[v];
    ++c.count;
    const Keeper& k = keeper.at(uf.find(v));
    if (!k.planes->empty()) c.keeper = k.vertex;
  }

  // New points: one per root, in id order; every old point's new id.
  std::vector<int32_t> new_id(m.points.size(), -1);
  Buffer<Vec3> points;
  points.reserve(m.points.size());
  for (size_t v = 0; v < m.points.size(); ++v) {
    if (member[v] && uf.find(int32_t(v)) != int32_t(v)) continue;
    new_id[v] = int32_t(points.size());
    Vec3 p = m.points[v];
    auto it = member[v] ? clusters.find(int32_t(v)) : clusters.end();
    if (it != clusters.end() && it->second.count > 1)
      p = it->second.keeper >= 0 ? m.points[it->second.keeper] : (1.0 / it->second.count) * it->second.sum;
    points.push_back(p);
  }
  for (size_t v = 0; v < m.points.size(); ++v) {
    if (!member[v]) continue;
    const int32_t root = uf.find(int32_t(v));
    if (root != int32_t(v)) ++st.edges_collapsed, new_id[v] = new_id[root];
    st.max_displacement = std::max(st.max_displacement, norm(points[new_id[v]] - m.points[v]));
  }

  // Faces rebuilt through the map, in parallel by blocks of cells (sizes first, then the
  // contents); faces left with fewer than three vertices are gone.
  const size_t nc = m.cell_count(), cell_chunk = 4096, cell_chunks = (nc + cell_chunk - 1) / cell_chunk;
  std::vector<int64_t> chunk_faces(cell_chunks + 1, 0), chunk_entries(cell_chunks + 1, 0);
  auto mapped = [&](int64_t f, std::vector<int32_t>& out) {
    collapsed(m, f, [&](int32_t v) { return new_id[v]; }, out);
  };
  uint64_t removed = 0;
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : removed)
  for (size_t ch = 0; ch < cell_chunks; ++ch) {
    std::vector<int32_t> out;
    int64_t faces = 0, entries = 0;
    for (int64_t f = m.cell_face_begin[ch * cell_chunk]; f < m.cell_face_begin[std::min(nc, (ch + 1) * cell_chunk)]; ++f) {
      mapped(f, out);
      if (out.size() < 3) ++removed;
      else ++faces, entries += int64_t(out.size());
    }
    chunk_faces[ch + 1] = faces, chunk_entries[ch + 1] = entries;
  }
  st.faces_removed = removed;
  for (size_t ch = 0; ch < cell_chunks; ++ch)
    chunk_faces[ch + 1] += chunk_faces[ch], chunk_entries[ch + 1] += chunk_entries[ch];
  std::vector<int64_t> cell_face_begin(nc + 1);
  Buffer<int32_t> face_generator(chunk_faces[cell_chunks]);
  Buffer<int64_t> face_vertex_begin(chunk_faces[cell_chunks] + 1);
  Buffer<int32_t> face_vertices(chunk_entries[cell_chunks]);
  double shortest_after2 = INFINITY;
#pragma omp parallel for schedule(dynamic, 1) reduction(min : shortest_after2)
  for (size_t ch = 0; ch < cell_chunks; ++ch) {
    std::vector<int32_t> out;
    int64_t face = chunk_faces[ch], entry = chunk_entries[ch];
    for (size_t c = ch * cell_chunk; c < std::min(nc, (ch + 1) * cell_chunk); ++c) {
      cell_face_begin[c] = face;
      for (int64_t f = m.cell_face_begin[c]; f < m.cell_face_begin[c + 1]; ++f) {
        mapped(f, out);
        if (out.size() < 3) continue;
        face_generator[face] = m.face_generator[f];
        face_vertex_begin[face++] = entry;
        for (size_t k = 0; k < out.size(); ++k) {
          face_vertices[entry++] = out[k];
          shortest_after2 = std::min(shortest_after2, norm2(points[out[k]] - points[out[(k + 1) % out.size()]]));
        }
      }
    }
  }
  cell_face_begin[nc] = chunk_faces[cell_chunks];
  face_vertex_begin[chunk_faces[cell_chunks]] = chunk_entries[cell_chunks];
  st.shortest_edge_after = std::isfinite(shortest_after2) ? std::sqrt(shortest_after2) : 0;

  // Of the faces that had a merged vertex: the non-planarity (distance of each vertex from the
  // best-fit plane), and the edges still shorter than w, which are the only places the next
  // pass needs to look.
  for (int64_t f : member_faces) {
    mapped(f, cyc);
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

  m.points = std::move(points);
  m.cell_face_begin = std::move(cell_face_begin);
  m.face_generator = std::move(face_generator);
  m.face_vertex_begin = std::move(face_vertex_begin);
  m.face_vertices = std::move(face_vertices);
  m.volumes.clear();
  m.quality.clear();
  return st;
}

}  // namespace

WeldStats weld_mesh(PolyMesh& m, double w, double r,
                    const std::function<void(const std::vector<size_t>& cells)>& before_change) {
  // Merged vertices move (to the keeper or the centroid), which can make a neighbouring edge
  // shorter than w: repeat until a pass finds nothing more to merge.
  std::vector<std::pair<int32_t, int32_t>> edges;
  // A later pass's short edges all have a vertex the first pass moved, so the cells it changes
  // were changed by the first pass already: before_change is told once.
  WeldStats total = weld_pass(m, w, r, edges, before_change);
  for (int pass = 1; pass < 16 && !edges.empty(); ++pass) {
    const WeldStats more = weld_pass(m, w, r, edges, {});
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

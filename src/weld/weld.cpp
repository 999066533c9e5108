// Welding: union-find over short edges, one decision for the whole mesh.
#include "froth/weld.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace froth {
namespace {

struct UnionFind {
  std::vector<int32_t> parent;
  explicit UnionFind(size_t n) : parent(n) {
    for (size_t i = 0; i < n; ++i) parent[i] = int32_t(i);
  }
  int32_t find(int32_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  }
  // The smaller id becomes the root, so the result does not depend on the order of unions.
  bool unite(int32_t a, int32_t b) {
    a = find(a), b = find(b);
    if (a == b) return false;
    if (a > b) std::swap(a, b);
    parent[b] = a;
    return true;
  }
};

// Walks the faces' vertex cycles: f(face, first, end) for each face.
template <class F>
void for_each_face(const PolyMesh& m, F&& f) {
  for (size_t k = 0; k < m.face_count(); ++k) f(k, m.face_vertex_begin[k], m.face_vertex_begin[k + 1]);
}

// A face's vertices mapped through `root`, with consecutive repeats (cyclically) removed.
void collapsed(const PolyMesh& m, int64_t b, int64_t e, UnionFind& uf, std::vector<int32_t>& out) {
  out.clear();
  for (int64_t k = b; k < e; ++k) {
    const int32_t v = uf.find(m.face_vertices[k]);
    if (out.empty() || out.back() != v) out.push_back(v);
  }
  while (out.size() > 1 && out.back() == out.front()) out.pop_back();
}

double shortest_edge(const PolyMesh& m) {
  double best = INFINITY;
  for_each_face(m, [&](size_t, int64_t b, int64_t e) {
    for (int64_t k = b; k < e; ++k)
      best = std::min(best, norm2(m.points[m.face_vertices[k]] - m.points[m.face_vertices[k + 1 < e ? k + 1 : b]]));
  });
  return std::isfinite(best) ? std::sqrt(best) : 0;
}

// One pass: merges along the edges shorter than w as they are.
WeldStats weld_pass(PolyMesh& m, double w, double r) {
  WeldStats st;
  st.tolerance = w;
  // One parallel pass: the short edges (in face order, deduplicated below: each is seen from
  // several faces), the shortest edge and the border's area.
  const size_t nf = m.face_count(), chunk = 1 << 14, chunks = (nf + chunk - 1) / chunk;
  std::vector<std::vector<std::pair<int32_t, int32_t>>> found(chunks);
  double shortest2 = INFINITY, area = 0;
#pragma omp parallel for schedule(dynamic, 1) reduction(min : shortest2) reduction(+ : area)
  for (size_t ch = 0; ch < chunks; ++ch)
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
  for (auto& f : found) short_edges.insert(short_edges.end(), f.begin(), f.end());
  if (short_edges.empty()) {
    st.shortest_edge_after = st.shortest_edge_before;
    return st;
  }
  std::sort(short_edges.begin(), short_edges.end());
  short_edges.erase(std::unique(short_edges.begin(), short_edges.end()), short_edges.end());

  // Merge, then refuse every cluster that would make a face touch itself (a vertex twice, not
  // in a row), and merge again without it, until no face is pinched.
  std::vector<uint8_t> refused(m.points.size(), 0), member(m.points.size(), 0);
  for (auto [u, v] : short_edges) member[u] = member[v] = 1;
  auto touches_member = [&](int64_t b, int64_t e) {
    for (int64_t k = b; k < e; ++k)
      if (member[m.face_vertices[k]]) return true;
    return false;
  };
  UnionFind uf(m.points.size());
  std::vector<int32_t> cyc, sorted;
  for (;;) {
    uf = UnionFind(m.points.size());
    for (auto [u, v] : short_edges)
      if (!refused[u] && !refused[v]) uf.unite(u, v);
    bool pinched = false;
    for_each_face(m, [&](size_t, int64_t b, int64_t e) {
      if (!touches_member(b, e)) return;
      collapsed(m, b, e, uf, cyc);
      sorted = cyc;
      std::sort(sorted.begin(), sorted.end());
      for (size_t k = 1; k < sorted.size(); ++k)
        if (sorted[k] == sorted[k - 1]) {
          // Refuse the whole cluster: every vertex whose root is this one.
          for (int64_t j = b; j < e; ++j)
            if (uf.find(m.face_vertices[j]) == sorted[k]) refused[m.face_vertices[j]] = 1;
          pinched = true;
        }
    });
    if (!pinched) break;
    for (auto [u, v] : short_edges)  // refuse the rest of those clusters too
      if (refused[u] || refused[v]) refused[u] = refused[v] = 1;
  }
  for (size_t v = 0; v < refused.size(); ++v) st.clusters_refused += refused[v] && uf.find(int32_t(v)) == int32_t(v);

  // Border planes of the vertices in clusters: the one on the most planes keeps its place.
  std::map<int32_t, std::vector<int32_t>> planes;
  for (auto [u, v] : short_edges)
    if (uf.find(u) == uf.find(v)) planes[u], planes[v];
  for_each_face(m, [&](size_t f, int64_t b, int64_t e) {
    if (!is_border_generator(m.face_generator[f])) return;
    for (int64_t k = b; k < e; ++k) {
      auto it = planes.find(m.face_vertices[k]);
      if (it == planes.end()) continue;
      auto& p = it->second;
      if (std::find(p.begin(), p.end(), m.face_generator[f]) == p.end()) p.push_back(m.face_generator[f]);
    }
  });
  struct Cluster {
    Vec3 sum{};
    int count = 0;
    int32_t keeper = -1;
    size_t keeper_planes = 0;
  };
  std::map<int32_t, Cluster> clusters;
  for (const auto& [v, p] : planes) {
    Cluster& c = clusters[uf.find(v)];
    c.sum = c.sum + m.points[v];
    ++c.count;
    if (p.size() > c.keeper_planes || (p.size() == c.keeper_planes && p.size() > 0 && v < c.keeper))
      c.keeper = v, c.keeper_planes = p.size();
  }

  // New points: one per root, in id order.
  std::vector<int32_t> new_id(m.points.size(), -1);
  Buffer<Vec3> points;
  for (size_t v = 0; v < m.points.size(); ++v) {
    if (uf.find(int32_t(v)) != int32_t(v)) continue;
    new_id[v] = int32_t(points.size());
    Vec3 p = m.points[v];
    auto it = clusters.find(int32_t(v));
    if (it != clusters.end() && it->second.count > 1)
      p = it->second.keeper >= 0 ? m.points[it->second.keeper] : (1.0 / it->second.count) * it->second.sum;
    points.push_back(p);
  }
  for (size_t v = 0; v < m.points.size(); ++v) {
    const int32_t root = uf.find(int32_t(v));
    if (root != int32_t(v)) ++st.edges_collapsed;
    st.max_displacement = std::max(st.max_displacement, norm(points[new_id[root]] - m.points[v]));
  }

  // Faces rebuilt through the map; faces left with fewer than three vertices are gone.
  std::vector<int64_t> cell_face_begin{0};
  Buffer<int32_t> face_generator;
  Buffer<int64_t> face_vertex_begin;
  Buffer<int32_t> face_vertices;
  face_vertex_begin.push_back(0);
  for (size_t c = 0; c < m.cell_count(); ++c) {
    for (int64_t f = m.cell_face_begin[c]; f < m.cell_face_begin[c + 1]; ++f) {
      collapsed(m, m.face_vertex_begin[f], m.face_vertex_begin[f + 1], uf, cyc);
      if (cyc.size() < 3) {
        ++st.faces_removed;
        continue;
      }
      face_generator.push_back(m.face_generator[f]);
      for (int32_t v : cyc) face_vertices.push_back(new_id[v]);
      face_vertex_begin.push_back(int64_t(face_vertices.size()));
    }
    cell_face_begin.push_back(int64_t(face_generator.size()));
  }
  m.points = std::move(points);
  m.cell_face_begin = std::move(cell_face_begin);
  m.face_generator = std::move(face_generator);
  m.face_vertex_begin = std::move(face_vertex_begin);
  m.face_vertices = std::move(face_vertices);
  m.volumes.clear();
  m.quality.clear();

  // Non-planarity of the faces that have a moved vertex: distance of each vertex from the
  // best-fit plane (Newell normal through the centroid).
  std::vector<uint8_t> moved(m.points.size(), 0);
  for (size_t v = 0; v < new_id.size(); ++v)
    if (member[v]) moved[new_id[uf.find(int32_t(v))]] = 1;
  for_each_face(m, [&](size_t, int64_t b, int64_t e) {
    bool any = false;
    for (int64_t k = b; k < e && !any; ++k) any = moved[m.face_vertices[k]];
    if (!any) return;
    Vec3 n{}, centroid{};
    for (int64_t k = b; k < e; ++k) {
      n = n + cross(m.points[m.face_vertices[k]], m.points[m.face_vertices[k + 1 < e ? k + 1 : b]]);
      centroid = centroid + m.points[m.face_vertices[k]];
    }
    if (e - b <= 3 || norm(n) == 0) return;
    n = (1 / norm(n)) * n;
    centroid = (1.0 / double(e - b)) * centroid;
    for (int64_t k = b; k < e; ++k)
      st.max_nonplanarity = std::max(st.max_nonplanarity, std::abs(dot(n, m.points[m.face_vertices[k]] - centroid)) / r);
  });
  st.shortest_edge_after = shortest_edge(m);
  return st;
}

}  // namespace

WeldStats weld_mesh(PolyMesh& m, double w, double r) {
  // Merged vertices move (to the keeper or the centroid), which can make a neighbouring edge
  // shorter than w: repeat until a pass finds nothing more to merge.
  WeldStats total = weld_pass(m, w, r);
  for (int pass = 1; pass < 16 && total.shortest_edge_after < w; ++pass) {
    const WeldStats more = weld_pass(m, w, r);
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

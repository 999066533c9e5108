#include "clip/face_loops.hpp"

#include <algorithm>
#include <cmath>

namespace froth {
namespace {

using Point2 = std::pair<double, double>;

// In-plane coordinates of p for a plane with unit normal n.
Point2 in_plane(Vec3 p, Vec3 n) {
  const Vec3 u = std::abs(n.x) < 0.6 ? Vec3{0, -n.z, n.y} : Vec3{-n.y, n.x, 0};
  const Vec3 uu = (1 / norm(u)) * u, vv = cross(n, uu);
  return {dot(p, uu), dot(p, vv)};
}

// Chains directed edges at a point where a face's region touches itself (a pinch: the point has
// several edges leaving it), in a plane of unit normal n. The region lies left of its edges, so
// at a pinch the loop that arrived along one of the region's wedges leaves along the other side
// of that wedge: the leaving edge first met turning clockwise from the way back. Loops then
// touch at the pinch instead of crossing there, and the same loops come out for either normal.
bool chain_pinched_loops(const std::vector<DirectedEdge>& edges, const std::vector<Vec3>& pts, Vec3 n, Loops& loops) {
  loops.clear();
  std::vector<size_t> order(edges.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return edges[a].from < edges[b].from; });
  auto leaving = [&](int32_t p) {
    auto lo = std::lower_bound(order.begin(), order.end(), p, [&](size_t e, int32_t q) { return edges[e].from < q; });
    auto hi = lo;
    while (hi != order.end() && edges[*hi].from == p) ++hi;
    return std::pair{lo, hi};
  };
  auto angle = [&](int32_t from, int32_t to) {
    const auto [ax, ay] = in_plane(pts[from], n);
    const auto [bx, by] = in_plane(pts[to], n);
    return std::atan2(by - ay, bx - ax);
  };
  std::vector<uint8_t> used(edges.size(), 0);
  for (size_t start = 0; start < edges.size(); ++start) {
    if (used[start]) continue;
    size_t e = start;
    while (!used[e]) {
      used[e] = 1;
      loops.ids.push_back(edges[e].from);
      const int32_t p = edges[e].to;
      const double back = angle(p, edges[e].from);
      size_t next = edges.size();
      double best = INFINITY;
      const auto [lo, hi] = leaving(p);
      for (auto it = lo; it != hi; ++it) {
        if (used[*it] && *it != start) continue;
        double turn = back - angle(p, edges[*it].to);  // clockwise from the way back, in (0, 2 pi]
        while (turn <= 0) turn += 2 * M_PI;
        while (turn > 2 * M_PI) turn -= 2 * M_PI;
        if (turn < best) best = turn, next = *it;
      }
      if (next == edges.size()) return false;
      if (next == start) break;
      e = next;
    }
    if (edges[e].to != edges[start].from) return false;
    loops.begin.push_back(uint32_t(loops.ids.size()));
  }
  return true;
}

// Is p inside the polygon `loop` (counter-clockwise about n)? Even-odd rule in the plane.
bool encloses(const std::vector<Vec3>& pts, const std::vector<int32_t>& loop, Vec3 p, Vec3 n) {
  const auto [px, py] = in_plane(p, n);
  bool in = false;
  for (size_t k = 0; k < loop.size(); ++k) {
    const auto [ax, ay] = in_plane(pts[loop[k]], n);
    const auto [bx, by] = in_plane(pts[loop[(k + 1) % loop.size()]], n);
    if ((ay > py) != (by > py) && px < ax + (py - ay) / (by - ay) * (bx - ax)) in = !in;
  }
  return in;
}

}  // namespace

Vec3 loop_area(const std::vector<Vec3>& pts, std::span<const int32_t> loop) {
  Vec3 a{};
  for (size_t k = 0; k < loop.size(); ++k) a = a + cross(pts[loop[k]], pts[loop[(k + 1) % loop.size()]]);
  return 0.5 * a;
}

bool chain_loops(const std::vector<DirectedEdge>& edges, size_t points, Loops& loops, std::vector<int32_t>& leaving,
                 std::vector<uint8_t>& used, const std::vector<Vec3>& pts, Vec3 n) {
  loops.clear();
  if (leaving.size() < points) leaving.resize(points, -1);
  bool pinched = false;
  size_t set = 0;
  for (; set < edges.size(); ++set) {
    if (leaving[edges[set].from] >= 0) {
      pinched = true;
      break;
    }
    leaving[edges[set].from] = int32_t(set);
  }
  bool ok = !pinched;
  used.assign(edges.size(), 0);
  for (size_t k = 0; ok && k < edges.size(); ++k) {
    const int32_t start = edges[k].from;
    int32_t i = leaving[start];
    if (used[i]) continue;
    int32_t p = start;
    while (i >= 0 && !used[i]) {
      used[i] = 1;
      loops.ids.push_back(p);
      p = edges[i].to;
      i = leaving[p];
    }
    if (i < 0 || p != start) ok = false;
    else loops.begin.push_back(uint32_t(loops.ids.size()));
  }
  for (size_t k = 0; k < set; ++k) leaving[edges[k].from] = -1;
  return pinched ? chain_pinched_loops(edges, pts, n, loops) : ok;
}

bool add_faces_with_holes(const Loops& plane_loops, Vec3 n, int32_t g, const std::vector<Vec3>& pts,
                          double negligible_area, FaceLoops out) {
  auto add = [&](std::span<const int32_t> loop, uint8_t kind) {
    out.generator.push_back(g);
    out.kind.push_back(kind);
    out.faces.ids.insert(out.faces.ids.end(), loop.begin(), loop.end());
    out.faces.begin.push_back(uint32_t(out.faces.ids.size()));
  };
  // A loop turning clockwise by more than round-off. One of (nearly) no area, its points
  // (nearly) one, where a face passes exactly through a domain vertex, is a face like any
  // other: welding removes it.
  auto is_hole = [&](std::span<const int32_t> loop) {
    double perimeter = 0;
    for (size_t k = 0; k < loop.size(); ++k) perimeter += norm(pts[loop[(k + 1) % loop.size()]] - pts[loop[k]]);
    return dot(loop_area(pts, loop), n) < -1e-12 * perimeter * perimeter;
  };
  bool any_hole = false;
  for (size_t k = 0; k < plane_loops.size(); ++k) any_hole |= is_hole(plane_loops[k]);
  if (!any_hole) {  // the usual case
    for (size_t k = 0; k < plane_loops.size(); ++k) add(plane_loops[k], 0);
    return true;
  }
  std::vector<std::vector<int32_t>> outer, holes;
  for (size_t k = 0; k < plane_loops.size(); ++k) {
    const auto loop = plane_loops[k];
    (is_hole(loop) ? holes : outer).emplace_back(loop.begin(), loop.end());
  }
  // Each hole in the smallest outer loop around it (outer loops of one plane do not cross).
  // Loops may touch at a vertex (pinched faces), so the hole is located by a point just off
  // its longest edge on the face's side (the left, as for every boundary loop), not by a
  // vertex, which may lie on the outer loop itself.
  // A clockwise sliver around no outer loop, far below the cell's size, comes of crossings
  // that nearly coincide at a domain vertex (the hinge at r = diag/2: a 1e-6 triangle): it is
  // kept as a face of its own, which welding removes.
  std::vector<std::vector<size_t>> holes_of(outer.size());
  std::vector<size_t> stray;
  for (size_t h = 0; h < holes.size(); ++h) {
    const std::vector<int32_t>& hole = holes[h];
    size_t longest = 0;
    for (size_t k = 1; k < hole.size(); ++k)
      if (norm2(pts[hole[(k + 1) % hole.size()]] - pts[hole[k]]) >
          norm2(pts[hole[(longest + 1) % hole.size()]] - pts[hole[longest]]))
        longest = k;
    const Vec3 a = pts[hole[longest]], b = pts[hole[(longest + 1) % hole.size()]];
    const Vec3 probe = 0.5 * (a + b) + 1e-6 * cross(n, b - a);
    size_t host = outer.size();
    double host_area = INFINITY;
    for (size_t o = 0; o < outer.size(); ++o) {
      const double area = dot(loop_area(pts, outer[o]), n);
      if (area < host_area && encloses(pts, outer[o], probe, n)) host = o, host_area = area;
    }
    if (host < outer.size()) {
      holes_of[host].push_back(h);
    } else if (std::abs(dot(loop_area(pts, hole), n)) < negligible_area) {
      stray.push_back(h);
    } else {
      return false;
    }
  }
  for (size_t o = 0; o < outer.size(); ++o) {
    add(outer[o], holes_of[o].empty() ? 0 : 1);
    for (size_t h : holes_of[o]) add(holes[h], 2);
  }
  for (size_t h : stray) add(holes[h], 0);
  return true;
}

}  // namespace froth

// A cell's distinct points, sorted: VTK's connectivity of a polyhedron, and the points the
// quality measures use.
#pragma once
#include <algorithm>
#include <bit>
#include <cstdint>
#include <vector>

#include "froth/mesh.hpp"

namespace froth {

// Every point of a cell is on three or more of its faces, so the repeats are dropped first,
// through a small hash set, and only the distinct third is sorted (sorting all of them was a
// third of the writing time).
inline void cell_points(const PolyMesh& m, size_t c, std::vector<int32_t>& pts) {
  const int32_t* begin = m.face_vertices.data() + m.face_vertex_begin[m.cell_face_begin[c]];
  const int32_t* end = m.face_vertices.data() + m.face_vertex_begin[m.cell_face_begin[c + 1]];
  const size_t n = size_t(end - begin);
  thread_local std::vector<int32_t> table;  // -1: empty; emptied again before returning
  if (table.size() < 2 * n) table.assign(std::bit_ceil(2 * n), -1);
  const size_t mask = table.size() - 1;
  auto home = [mask](int32_t p) { return size_t(uint32_t(p) * 0x9E3779B1u) & mask; };
  pts.resize(n);
  size_t distinct = 0;
  for (const int32_t* v = begin; v != end; ++v) {
    size_t s = home(*v);
    while (table[s] != -1 && table[s] != *v) s = (s + 1) & mask;
    // A point's first and later appearances alternate unpredictably: kept without a branch.
    const bool fresh = table[s] == -1;
    table[s] = *v;
    pts[distinct] = *v;
    distinct += fresh;
  }
  pts.resize(distinct);
  for (int32_t p : pts) {
    size_t s = home(p);
    while (table[s] != p) s = (s + 1) & mask;
    table[s] = -1;
  }
  std::sort(pts.begin(), pts.end());
}

}  // namespace froth

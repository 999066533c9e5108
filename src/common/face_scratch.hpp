// Per-face data the stages pass along while a mesh is built, kept out of the public PolyMesh
// (which holds only a pointer to it, null in a finished mesh).
#pragma once
#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "froth/mesh.hpp"

namespace froth {

// Each crack point's twins: per point, (sheet, the point at its place across that sheet), one
// per sheet the point lies on one side of (two where sheets cross), in sheet order; flat.
struct PointTwins {
  std::vector<int32_t> begin;                 // per point, and one past the last; empty: none
  std::vector<std::array<int32_t, 2>> twins;  // (sheet, point)
  bool empty() const { return begin.empty(); }
  void clear() { begin.clear(), twins.clear(); }
  std::span<const std::array<int32_t, 2>> of(int32_t v) const {
    return {twins.data() + begin[size_t(v)], size_t(begin[size_t(v) + 1] - begin[size_t(v)])};
  }
  // From one list of (point, sheet, twin) per pair, sorted here; `points` the mesh's count.
  static PointTwins from(std::vector<std::array<int32_t, 3>> pairs, size_t points) {
    std::sort(pairs.begin(), pairs.end());
    PointTwins t;
    t.begin.assign(points + 1, 0);
    for (const auto& p : pairs) ++t.begin[size_t(p[0]) + 1], t.twins.push_back({p[1], p[2]});
    for (size_t v = 0; v < points; ++v) t.begin[v + 1] += t.begin[v];
    return t;
  }
};

struct FaceScratch {
  // While cells are assembled only: each face's region (a multi-region solid's).
  std::vector<int32_t> face_region;
  // Until welding (which keeps interface vertices on their facets, as border ones on theirs) and
  // --convex's split: each face's interface facet (RegionSet's facet numbering), -1 for other
  // faces; empty: none.
  std::vector<int32_t> face_interface_facet;
  // Until welding (which moves a crack's copies alike): per point, the point at its place on
  // the other side of each sheet it lies on (assembly/glue_extensions.hpp); empty: no cracks.
  PointTwins point_twins;
};

// The mesh's scratch, made on first use.
inline FaceScratch& scratch_of(PolyMesh& m) {
  if (!m.scratch) m.scratch = std::make_shared<FaceScratch>();
  return *m.scratch;
}
inline const FaceScratch& scratch_of(const PolyMesh& m) {
  static const FaceScratch none;
  return m.scratch ? *m.scratch : none;
}

}  // namespace froth

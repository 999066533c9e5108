// Per-face data the stages pass along while a mesh is built, kept out of the public PolyMesh
// (which holds only a pointer to it, null in a finished mesh).
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "froth/mesh.hpp"

namespace froth {

struct FaceScratch {
  // While cells are assembled only: each face's region (a multi-region solid's).
  std::vector<int32_t> face_region;
  // Until welding (which keeps interface vertices on their facets, as border ones on theirs) and
  // --convex's split: each face's interface facet (RegionSet's facet numbering), -1 for other
  // faces; empty: none.
  std::vector<int32_t> face_interface_facet;
  // Until welding (which moves a crack's two copies alike): per point, the point at its place
  // on the crack's other copy (assembly/glue_extensions.hpp), -1 for none; empty: no cracks.
  std::vector<int32_t> point_twin;
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

// Which input patch each border face lies on (froth/mesh.hpp's face_patch), for boundary
// conditions in the solver formats.
#pragma once
#include "froth/domain.hpp"
#include "froth/mesh.hpp"

namespace froth {

// Sets mesh.patch_names from the domain and mesh.face_patch: a border face on a facet plane of
// one patch takes it; on a plane that patches share (coplanar neighbours), the patch of the
// plane's triangle nearest the face's centroid. Interior faces get -1.
void assign_border_patches(const Domain& domain, PolyMesh& mesh);

}  // namespace froth

// Protection of crack sheets (issue 38, the paper's §2.2 for non-manifold facets): the sheets'
// curves (front, lines on the boundary, crossings with other sheets) get a seed at each corner
// and 1D MPS with disks of r/2; the sheets' triangles 2D MPS with disks of r/sqrt(2), uniform by
// area; all clear of `prior` (the boundary's and interfaces' protection seeds). Free seeds are
// then to keep r from these, so that every sheet point is closest to a sheet seed and only sheet
// seeds' cells meet a sheet. The sampling is the interfaces' (sample_facets_and_curves).
#pragma once
#include <cstdint>
#include <vector>

#include "input/cracks.hpp"
#include "sampling/protect_interfaces.hpp"

namespace froth {

// A pure function of (sheets, r, seed, h). Seeds on curves come first (kind InterfaceEdge), then
// seeds on the triangles (InterfaceFace); `inward` is each seed's side a (the sheet's normal).
// With a sizing field h (--grade) the disks are the interfaces' factors times h (interface_factors).
ProtectionSeeds protect_cracks(const std::vector<CrackSheet>& sheets, double r, uint64_t seed,
                               const std::vector<Vec3>& prior, InterfaceProtectionStats* stats = nullptr,
                               const std::function<double(Vec3)>& h = {}, double lipschitz = 0);

}  // namespace froth

// Every seed's Voronoi cell, cut by a convex domain's planes or clipped to any other domain's surface
// (src/clip), assembled into one conforming mesh.
#pragma once
#include <functional>

#include "froth/domain.hpp"
#include "froth/mesh.hpp"
#include "sampling/mps.hpp"

namespace froth {

struct TessellationTimes {
  double cells = 0;     // seconds computing cells
  size_t cells_peak_rss = 0;  // peak resident memory after computing them
  double assembly = 0;  // seconds giving shared vertices one id
  size_t recut_cells = 0;  // cells cut again by seeds beyond 2r (assembly/cell_builder.cpp)
};

// Seeds [begin, end) of a sample; end < 0: all.
struct SeedRange {
  int32_t begin = 0, end = -1;
};

// Builds the cells of the seeds in `built` (default all), cell k for seed built.begin + k; a face
// toward a seed outside `built` gets the generator kOtherPiece (froth/mesh.hpp), and a vertex
// is owned by the smallest built seed of its name.
// Throws Error(Internal) if a cell cannot be closed by its neighbours (the sample is not maximal)
// or two cells disagree on a shared vertex.
// Consumes the sample: its seeds become the mesh's, its look-up structures are freed early.
// A seed's part of the domain in several pieces gives a cell per piece of at least
// `min_piece_volume` (assembly/split_pieces.hpp).
// `progress`, if set, is told from one thread the fraction of the cells built.
PolyMesh build_voronoi_mesh(const Domain& domain, Sample&& sample, double r, TessellationTimes* times,
                            SeedRange built = {}, double min_piece_volume = 0,
                            const std::function<void(double)>& progress = {});

}  // namespace froth

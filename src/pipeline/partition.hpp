// The pieces of a partitioned run (froth/partition.hpp) that are not the serial pipeline's: the
// seed halo the cells need, and the cutting out of a rank's own cells.
#pragma once
#include "froth/partition.hpp"
#include "sampling/mps.hpp"
#include "assembly/tessellation.hpp"

namespace froth {

// The seeds of the layers [owned_begin - kCellHaloLayers, owned_end + kCellHaloLayers): this
// rank's and its neighbours', in global seed order (base cube order), so local index k is global
// index first_global + k and the cells built from it name their vertices as the serial run does.
struct CellWindow {
  Sample sample;
  int64_t first_global = 0;
  SeedRange owned;   // this rank's seeds
  SeedRange built;   // the seeds whose cells are built: owned, and kGhostCellLayers around them
  size_t total_seeds = 0;  // over all ranks
};

// Trades with the neighbours the seeds within kCellHaloLayers of the slab's faces. `sampled` is
// this rank's sample (src/sampling/mps.hpp with a partition).
CellWindow exchange_cell_halo(const Sample& sampled, const Slab& slab, Communicator& comm);

// Cells [begin, end) of `mesh` as a mesh of their own, points renumbered in their order; a face
// toward a cell outside the range gets the generator kOtherPiece or kOtherPieceProtected (by the
// neighbour's kind), counted in `other_piece_faces`.
PolyMesh extract_cells(const PolyMesh& mesh, size_t begin, size_t end, size_t& other_piece_faces);

}  // namespace froth

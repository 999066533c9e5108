// One mesh split over several processes (froth mesh --partition under mpirun): the background
// grid is cut into slabs of z layers, one per rank, and each rank samples, builds and writes the
// cells of the seeds in its slab. The sample and the cells are the serial ones: the sampling
// schedule is defined on the global grid (src/sampling/mps.cpp), and a rank sees every seed within
// the halo its decisions depend on.
#pragma once
#include <cstdint>
#include <vector>

#include "froth/communicator.hpp"
#include "froth/mesh.hpp"

namespace froth {

// The cells' halo widths, in layers of base cubes (side r/sqrt(3)); the sampling halo is
// kSamplingHaloLayers (froth/communicator.hpp). A rank builds its own cells and a ring of
// ghost cells around them so that welding sees every short edge at an owned vertex (the cells
// sharing a vertex of an owned cell have seeds within 2r of an owned seed, Lemma 1: 2 sqrt(3) < 4
// layers, plus one layer for chains of short edges); each of those cells needs the seeds within
// its security radius, 2r mostly, but up to 2 sqrt(3) 1.05 r (the cube it is cut from) where a
// part of it in the domain reaches beyond r (assembly/cell_builder.cpp): 7 more layers.
constexpr int kGhostCellLayers = 5;
constexpr int kCellHaloLayers = kGhostCellLayers + 7;

// The slab of `rank` among `ranks` on a grid of nz layers (equal shares). Throws Error(Usage) when
// a slab would be thinner than kCellHaloLayers, as the halo must come from the neighbours alone.
Slab slab_of(int rank, int ranks, int nz);

struct PartitionReport {
  int rank = 0, ranks = 1;
  Slab slab;
  int64_t first_seed = 0;       // global index of this rank's first cell (cells follow seed order)
  size_t owned_seeds = 0;       // seeds, and cells, of this rank
  size_t ghost_seeds = 0;       // seeds of other ranks this rank holds for its cells (the halo)
  size_t ghost_cells = 0;       // cells built only for welding, then dropped
  size_t partition_faces = 0;   // faces shared with another rank's cells
  size_t exchanges = 0;         // neighbour exchanges during sampling
};

// This rank's piece of the mesh generate_mesh would make: the cells of the seeds in its slab, in
// global seed order, with its own point numbering. Interior faces toward another rank's cell have
// a generator of another piece (froth/mesh.hpp). report: this rank's figures (volume_sum is the
// piece's). Every rank must call it with the same domain and options. Throws Error.
PolyMesh generate_mesh_piece(const Domain& domain, const MeshOptions& options, Communicator& comm,
                             RunReport* report, PartitionReport* partition);

// The whole run from the ranks' reports: counts, volumes and areas summed in rank order, quality
// merged, each stage's time the slowest rank's, peak memory the largest rank's; and each rank's
// partition figures. Welding figures count each rank's ghost ring too, so merges next to a slab
// face are counted by both ranks. Every rank calls it and gets the same result.
struct PartitionSummary {
  RunReport run;
  std::vector<PartitionReport> ranks;
  std::vector<double> rank_seconds;     // each rank's total
  std::vector<size_t> rank_peak_rss;    // each rank's peak resident memory, bytes
};
PartitionSummary combine_rank_reports(Communicator& comm, const RunReport& mine, const PartitionReport& part);

}  // namespace froth

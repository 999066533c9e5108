// A seed's clipped cell V ∩ D can fall in several connected pieces where a wall or gap is thinner
// than the cell (the cell sees the domain on both sides of it). Each piece becomes a cell of its
// own: the pieces share no vertex, every face belongs to exactly one of them, and a neighbour's
// face toward the seed is the twin of exactly one piece's face, so the mesh stays conforming.
#pragma once
#include <cstdint>
#include <vector>

#include "froth/mesh.hpp"

namespace froth {

struct SplitCell {
  int32_t cell;  // index in the mesh before splitting
  Vec3 anchor;   // a point strictly inside the domain in the piece that holds the seed
  double min_volume = 0;  // a smaller piece stays with the anchor's (welding would collapse it)
};

// Splits the listed cells (sorted by cell) of an assembled mesh whose face generators are cell
// indices. The piece holding the anchor stays first (mesh.piece 0, the seed's own kind); the
// others follow in face order, as fringe cells with piece 1, 2, ... and the same seed. Face
// generators are renumbered to the new cells; kOtherPiece generators are kept.
// A multi-region solid's cells (`regions` set, its FaceScratch::face_region each face's region) are split
// by region too: the parts of a cell in two regions share the interface's vertices, and each
// interface face (on a facet between two regions) becomes the twin of the same cell's part on
// the other side. mesh.region is set and face_region cleared.
// `pieces_keep_kind`: every piece keeps the seed's kind (a solid cut along cracks, where a
// sheet seed's cell is cut in two by design), instead of the others becoming fringe cells.
void split_pieces(PolyMesh& mesh, const std::vector<SplitCell>& split, const RegionSet* regions = nullptr,
                  bool pieces_keep_kind = false);

}  // namespace froth

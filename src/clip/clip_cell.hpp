// Clips a seed's convex Voronoi cell by a non-convex domain (paper §2.3 "trimmed by the
// boundary"): the result is V ∩ D, whose faces are the parts of V's faces inside D and the parts
// of the input triangles inside V, merged per facet plane.
//
// Conformity comes from names, as for convex cells: every vertex is named by the generators that
// meet there, and every generator is a seed, a facet plane, an input edge or an input vertex:
//   Voronoi vertex {i,j,k,l}; Voronoi edge through a facet {i,j,k,F}; Voronoi face through an
//   input edge {i,j,E} (not a seam between two triangles of one facet plane: the faces go
//   straight on there, and no cell keeps a point); input vertex inside the cell {i,v}.
// Two cells that share a vertex compute the same name for it, and the same faces on their
// common bisector, because each is the bisector polygon cut by the same cross-section of D.
#pragma once
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "clip/face_loops.hpp"
#include "common/triangle_grid.hpp"
#include "froth/domain.hpp"
#include "voronoi/convex_cell.hpp"

namespace froth {

// Generator numbers of the input surface's elements in vertex names (all negative, so border).
struct SurfaceGenerators {
  int32_t planes = 0, edges = 0;
  std::vector<std::array<int32_t, 3>> triangle_edges;  // edge ids of (t0,t1), (t1,t2), (t2,t0)
  // Edges between two triangles of one facet plane: where one crosses a cell face it makes no
  // corner, only a point in the middle of a straight edge, which no cell keeps.
  std::vector<uint8_t> seam;
  explicit SurfaceGenerators(const Domain& d);
  // A region of a multi-region solid (froth/domain.hpp's RegionSet): edges numbered as in
  // `edges` (all regions' edges, sorted), so that every region names an input edge alike; a
  // seam where both of this region's triangles at the edge lie on one facet.
  SurfaceGenerators(const Domain& region, const std::vector<std::pair<int32_t, int32_t>>& edges);
  int32_t plane(int32_t f) const { return -(f + 1); }
  int32_t edge(int32_t e) const { return -(planes + 1 + e); }
  int32_t vertex(int32_t v) const { return -(planes + edges + 1 + v); }
  bool is_seam(int32_t generator) const {
    const int32_t e = -generator - planes - 1;
    return e >= 0 && e < edges && seam[size_t(e)];
  }
};

// A clipped cell, with the same accessors as ConvexCell for assembly.
class ClippedCell {
 public:
  size_t vertex_count() const { return points_.size(); }
  size_t face_count() const { return face_gen_.size(); }
  Vec3 vertex(size_t v) const { return points_[v]; }
  int32_t face_generator(size_t f) const { return face_gen_[f]; }
  const uint16_t* face_begin(size_t f) const { return face_vert_.data() + face_start_[f]; }
  size_t face_size(size_t f) const { return face_start_[f + 1] - face_start_[f]; }
  // 0: a face; 1: the outer loop of a face with holes, whose holes are the next faces, marked 2.
  uint8_t face_loop(size_t f) const { return face_loop_[f]; }
  const std::vector<ConvexCell::Names>& names() const { return names_; }
  // Connected pieces of V ∩ D (a wall thinner than the cell seen from both sides makes two).
  int pieces() const { return pieces_; }

 protected:  // (RegionCell, a cell's parts in several regions, is built the same way)
  friend class CellClipper;
  std::vector<Vec3> points_;
  std::vector<ConvexCell::Names> names_;
  std::vector<int32_t> face_gen_;
  std::vector<uint32_t> face_start_{0};
  std::vector<uint16_t> face_vert_;
  std::vector<uint8_t> face_loop_;
  int pieces_ = 1;
};

class CellClipper {
 public:
  // One clipper per thread: it keeps its scratch from cell to cell.
  CellClipper(const Domain& domain, const SurfaceGenerators& gens, const TriangleGrid& triangles);
  ~CellClipper();

  // HalfSpace: the surface near the cell is one facet plane, `facet`, and
  // V ∩ D is V cut by it: the caller cuts it as it cuts a convex domain's cells.
  // Outside: V ∩ D is empty (only when the anchor is outside D).
  // ReachesCube: a piece of V ∩ D reaches the cube: V was cut by too few seeds to be the
  // Voronoi cell there (the caller cuts it by more, assembly/cell_builder.cpp).
  enum class Result { Inside, Clipped, HalfSpace, Outside, ReachesCube };
  // Clips `cell` (coordinates relative to seed x; faces from the seeds in `seeds` or from the
  // cube [-half, half]^3) to the domain. `anchor` (relative to x) is a point of the cell strictly
  // inside the domain: the seed itself, or a point just off the surface for a protection seed.
  // Inside: the cell does not meet the surface and is whole. Throws nothing; returns an error
  // text in `error` (then the result is meaningless). `anchor_inside` false: the anchor is a
  // point of the cell outside D (a multi-region solid's cell seen from another region).
  Result clip(int32_t seed, Vec3 x, Vec3 anchor, const ConvexCell& cell, double half, const std::vector<Vec3>& seeds,
              ClippedCell& out, int32_t& facet, std::string& error, bool anchor_inside = true);

 private:
  struct Scratch;
  struct Call;
  // clip()'s steps after the quick cases; each returns a result to stop with, or nothing to go on.
  std::optional<Result> clip_triangles(const Call& c);
  std::optional<Result> find_inside_vertices(const Call& c);
  std::optional<Result> cut_faces(const Call& c);
  std::optional<Result> add_border_faces(const Call& c);
  Result close_cell(const Call& c);
  void drop_seam_points(Loops& loops) const;
  void order_twin_crossings(std::vector<int32_t>& along, Vec3 dir) const;
  void drop_fins(std::vector<DirectedEdge>& segs);
  void drop_two_point_loops(Loops& loops) const;
  const Domain& domain_;
  const SurfaceGenerators& gens_;
  const TriangleGrid& triangles_;
  std::unique_ptr<Scratch> s_;
};

}  // namespace froth

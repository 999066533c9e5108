// Near ties between seeds, decided exactly and the same way in every cell: is seed e in conflict
// with the Voronoi vertex of seeds (a, b, c, d), strictly inside their circumsphere? Exact
// predicates (CGAL's filtered Epick kernel) on the seeds' coordinates, and for five seeds on one
// sphere a symbolic perturbation: each seed is given an infinitesimal power-diagram weight,
// larger for a smaller index (Edelsbrunner and Mücke's simulation of simplicity). The perturbed
// diagram is simple, so no cell sees a vertex of five seeds that its neighbours see as two
// vertices of four: near-cospherical protection seeds (the corners of a rectangular pocket, set
// 1e-7 r off their vertices) made neighbouring cells disagree (issue 37).
#pragma once
#include <cstdint>
#include <vector>

#include "froth/geometry.hpp"
#include "voronoi/convex_cell.hpp"

namespace froth {

class SeedTies final : public ConvexCell::TieBreaker {
 public:
  // `band`: vertices within it of a bisector are decided exactly (1e-8 r: far above the
  // cell's round-off, far below anything a mesh resolves).
  SeedTies(const std::vector<Vec3>& seeds, double band) : seeds_(seeds), band_(band) {}
  double band() const override { return band_; }
  // +1: e is in conflict with the vertex (a, b, c, d); -1: it is not; 0: the four are coplanar
  // (no such vertex: the caller decides as it would without a tie-breaker).
  int conflict(int32_t a, int32_t b, int32_t c, int32_t d, int32_t e) const override;

 private:
  const std::vector<Vec3>& seeds_;
  double band_;
};

}  // namespace froth

// The sizing field h(x) <= r (paper §2.2: "to handle close edges the sampling radius r may be
// reduced"; graded as in VoroCrust, Abdelkader et al. 2020): r wherever the features allow,
// smaller where a wall or gap thinner than 2r needs it, never below a floor, and Lipschitz so
// that cell sizes change smoothly.
//
// From each triangle whose thickness or gap t (features/feature_size.hpp) is below 2r, the value
// a = max(min_r, t / 2), so that a cell (within h of its seed) cannot reach across the wall;
// then h(x) = min(r, min over those triangles' centroids p of a + L |x - p|) at the nodes of a
// grid of spacing r/4 (a shortest-path sweep over the 26 node neighbours, edges weighted L times
// their length), and between nodes the trilinear interpolation of the node values. Interpolation
// keeps every edge of a grid cell within slope L, so |grad h| <= sqrt(3) L: the field's grading.
//
// The default floor is the smallest in [r/4, r] whose estimated cell count, the integral of
// (r/h)^3 over the domain (cells go as h^-3), stays within kDefaultCellBudget times a uniform
// mesh's: a thin feature is resolved as far as that budget allows, never at any price.
#pragma once
#include <cstdint>
#include <vector>

#include "features/feature_size.hpp"
#include "froth/domain.hpp"

namespace froth {

// The default floor's budget: at most this many times the cells of a uniform mesh at r.
inline constexpr double kDefaultCellBudget = 3;

struct SizingOptions {
  double min_r = 0;    // the floor; 0: the default (see above)
  double grading = 0.2;  // L, the slope along grid edges (the field's Lipschitz bound is sqrt(3) L)
};

class SizingField {
 public:
  static SizingField uniform(double r);
  // `regions`: a multi-region solid's regions and their own measures, whose thin places count
  // too (a layer thinner than 2r between two interfaces is no wall of the union).
  using Measured = std::pair<const Domain*, const FeatureSize*>;
  static SizingField from_feature_size(const Domain& domain, const FeatureSize& fs, double r, const SizingOptions& o,
                                       const std::vector<Measured>& regions = {});

  double at(Vec3 x) const;
  bool is_uniform() const { return nodes_.empty(); }
  double r() const { return r_; }
  double min_r() const { return min_r_; }
  double grading() const { return grading_; }
  double lipschitz() const;  // the bound on |grad h|
  double smallest() const { return smallest_; }  // the least node value (r if uniform)
  // Estimated from the nodes inside the domain: the fraction of its volume where h < r, and the
  // cell count relative to a uniform mesh's (the integral of (r/h)^3 over the domain, over its
  // volume). floor_raised: the default floor went above r/4 to keep that ratio within budget.
  double graded_fraction = 0, cell_ratio = 1;
  bool floor_raised = false;

 private:
  friend struct SizingBuilder;  // sizing.cpp: the sweep and the cell estimate
  double r_ = 0, min_r_ = 0, grading_ = 0, smallest_ = 0, spacing_ = 0;
  Vec3 origin_;
  int64_t nx_ = 0, ny_ = 0, nz_ = 0;
  std::vector<float> nodes_;  // h at the grid nodes (x fastest); empty when uniform
};

}  // namespace froth

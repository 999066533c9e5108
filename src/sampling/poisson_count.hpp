// Darts per cube and round as a Poisson count: both samplers' darts are a space-time Poisson
// process over the cubes not yet covered (mps_sampler.hpp, graded_mps.cpp).
#pragma once
#include <cmath>

namespace froth {

// Inverse CDF of the Poisson law with mean `mean`: the CDF tabulated once (it is summed term by
// term, p0 = exp(-mean) first), then read per draw, with no division per term.
class Poisson {
 public:
  explicit Poisson(double mean) {
    double p = std::exp(-mean), cdf = p;
    cdf_[0] = cdf;
    for (int k = 1; k < kMax; ++k) {
      p *= mean / k;
      cdf += p;
      cdf_[k] = cdf;
    }
  }
  // The count whose CDF interval holds u (at most kMax - 1).
  int operator()(double u) const {
    int k = 0;
    while (k < kMax - 1 && u > cdf_[k]) ++k;
    return k;
  }

 private:
  static constexpr int kMax = 65;
  double cdf_[kMax];
};

}  // namespace froth

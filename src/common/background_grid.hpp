// The sampler's background grid: cubes of diagonal r (side r/sqrt(3)) over the domain's bounding
// box, after Ebeida et al. 2012. A cube holds at most one seed, since any two of its points are
// at most r apart. The same grid gives the Voronoi stage its neighbour stencil.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "froth/geometry.hpp"

namespace froth {

struct BackgroundGrid {
  Vec3 origin;
  double side = 0;
  int nx = 0, ny = 0, nz = 0;

  // Empty cubes around the domain's box on every side, as many as the widest stencil reaches
  // (the cells' 2r is four cubes): a stencil around any cube that may hold a seed then stays in
  // the grid, and is read through index offsets without a bounds check per cube (the cells
  // near a face are a large share of a small mesh's).
  static constexpr int kMargin = 4;
  static constexpr double kOriginShift = 0.3819660112501051;

  // Cubes along an axis of length `length` (at least one), with the margins and the cube the
  // shift below takes.
  static double cubes_along(double length, double side) {
    return std::max(1.0, std::ceil(length / side)) + 2 * kMargin + 1;
  }
  static BackgroundGrid covering(const Box& box, double r) {
    BackgroundGrid g;
    g.side = r / std::sqrt(3.0);
    // Shifted by an odd fraction of a cube beyond the margin, so that the planes of the cubes and
    // of their sub-cubes miss the faces a CAD part has at its bounding box: a triangle on a
    // cube's face, or a dart's segment ending on one, sends the samplers' tests there to exact
    // arithmetic or to a ray through the whole surface.
    const double shift = kMargin + kOriginShift;
    g.origin = box.lo - Vec3{shift * g.side, shift * g.side, shift * g.side};
    const Vec3 s = box.size();
    g.nx = static_cast<int>(cubes_along(s.x, g.side));
    g.ny = static_cast<int>(cubes_along(s.y, g.side));
    g.nz = static_cast<int>(cubes_along(s.z, g.side));
    return g;
  }
  size_t cube_count() const { return size_t(nx) * ny * nz; }
  int64_t index(int i, int j, int k) const { return (int64_t(k) * ny + j) * nx + i; }
  // The inverse of index().
  void coords(int64_t c, int& i, int& j, int& k) const {
    i = int(c % nx), j = int((c / nx) % ny), k = int(c / (int64_t(nx) * ny));
  }
  bool inside(int i, int j, int k) const {
    return i >= 0 && j >= 0 && k >= 0 && i < nx && j < ny && k < nz;
  }
  int clamp_axis(double t, int n) const {
    return std::clamp(static_cast<int>(std::floor(t / side)), 0, n - 1);
  }
  void locate(Vec3 p, int& i, int& j, int& k) const {
    i = clamp_axis(p.x - origin.x, nx);
    j = clamp_axis(p.y - origin.y, ny);
    k = clamp_axis(p.z - origin.z, nz);
  }
  // Squared distance from p to cube (i, j, k) along one axis (0 inside its slab).
  static double axis_gap(double t, int i, double side) {
    double lo = i * side, hi = lo + side;
    double d = t < lo ? lo - t : (t > hi ? t - hi : 0.0);
    return d * d;
  }

  // Calls f(cube index) for every existing cube whose distance to p is below `reach`; if f
  // returns bool, true stops the walk.
  template <class F>
  void for_cubes_near(Vec3 p, double reach, F&& f) const {
    int ci, cj, ck;
    locate(p, ci, cj, ck);
    int span = static_cast<int>(std::ceil(reach / side));
    double r2 = reach * reach;
    Vec3 q = p - origin;
    for (int k = std::max(0, ck - span); k <= std::min(nz - 1, ck + span); ++k) {
      double dz = axis_gap(q.z, k, side);
      if (dz >= r2) continue;
      for (int j = std::max(0, cj - span); j <= std::min(ny - 1, cj + span); ++j) {
        double dyz = dz + axis_gap(q.y, j, side);
        if (dyz >= r2) continue;
        int64_t row = (int64_t(k) * ny + j) * nx;
        for (int i = std::max(0, ci - span); i <= std::min(nx - 1, ci + span); ++i) {
          if (dyz + axis_gap(q.x, i, side) >= r2) continue;
          if constexpr (std::is_same_v<decltype(f(row + i)), bool>) {
            if (f(row + i)) return;
          } else {
            f(row + i);
          }
        }
      }
    }
  }
};

}  // namespace froth

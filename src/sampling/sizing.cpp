#include "sampling/sizing.hpp"

#include <algorithm>
#include <cmath>
#include <queue>

namespace froth {

SizingField SizingField::uniform(double r) {
  SizingField f;
  f.r_ = f.min_r_ = f.smallest_ = r;
  return f;
}

double SizingField::lipschitz() const { return std::sqrt(3.0) * grading_; }

SizingField SizingField::from_feature_size(const Domain& d, const FeatureSize& fs, double r, const SizingOptions& o) {
  SizingField f = uniform(r);
  f.min_r_ = o.min_r > 0 ? std::min(o.min_r, r) : r / 4;
  f.grading_ = o.grading;
  // The thin places: (centroid, a) for each triangle whose wall or gap is below 2r.
  const TriangleSurface& S = d.surface;
  std::vector<std::pair<Vec3, double>> thin;
  for (size_t t = 0; t < S.triangles.size(); ++t) {
    const double lfs = std::min(t < fs.thickness.size() ? fs.thickness[t] : INFINITY,
                                t < fs.gap.size() ? fs.gap[t] : INFINITY);
    const double a = std::max(f.min_r_, lfs / 2);
    if (a >= r) continue;
    const auto& tri = S.triangles[t];
    thin.push_back({(1.0 / 3) * (S.vertices[tri[0]] + S.vertices[tri[1]] + S.vertices[tri[2]]), a});
  }
  if (thin.empty()) return f;

  // Nodes over the box grown by the reach of the grading, spacing r/4 (coarser for a huge box).
  const double reach = (r - f.min_r_) / o.grading;
  const Vec3 lo = d.bounds.lo - Vec3{reach, reach, reach}, hi = d.bounds.hi + Vec3{reach, reach, reach};
  const Vec3 size = hi - lo;
  double g = r / 4;
  g = std::max(g, std::cbrt(size.x * size.y * size.z / 3e7));
  f.spacing_ = g, f.origin_ = lo;
  f.nx_ = int64_t(std::ceil(size.x / g)) + 1, f.ny_ = int64_t(std::ceil(size.y / g)) + 1,
  f.nz_ = int64_t(std::ceil(size.z / g)) + 1;
  const size_t n = size_t(f.nx_ * f.ny_ * f.nz_);
  f.nodes_.assign(n, float(r));
  auto index = [&](int64_t i, int64_t j, int64_t k) { return size_t((k * f.ny_ + j) * f.nx_ + i); };
  // Seeds of the sweep: the corners of each thin place's grid cell.
  std::priority_queue<std::pair<double, size_t>, std::vector<std::pair<double, size_t>>, std::greater<>> queue;
  auto offer = [&](size_t at, double v) {
    if (v < f.nodes_[at]) f.nodes_[at] = float(v), queue.push({double(float(v)), at});
  };
  for (const auto& [p, a] : thin) {
    const Vec3 q = (1 / g) * (p - lo);
    const int64_t i = int64_t(q.x), j = int64_t(q.y), k = int64_t(q.z);
    for (int c = 0; c < 8; ++c) {
      const int64_t ii = i + (c & 1), jj = j + (c >> 1 & 1), kk = k + (c >> 2 & 1);
      const Vec3 node = lo + g * Vec3{double(ii), double(jj), double(kk)};
      offer(index(ii, jj, kk), std::max(f.min_r_, a + o.grading * norm(node - p)));
    }
  }
  while (!queue.empty()) {
    const auto [v, at] = queue.top();
    queue.pop();
    if (v > f.nodes_[at]) continue;
    const int64_t i = int64_t(at) % f.nx_, j = int64_t(at) / f.nx_ % f.ny_, k = int64_t(at) / (f.nx_ * f.ny_);
    for (int dk = -1; dk <= 1; ++dk)
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          const int64_t a = i + di, b = j + dj, c = k + dk;
          if ((di | dj | dk) == 0 || a < 0 || b < 0 || c < 0 || a >= f.nx_ || b >= f.ny_ || c >= f.nz_) continue;
          offer(index(a, b, c), v + o.grading * g * std::sqrt(double(di * di + dj * dj + dk * dk)));
        }
  }
  f.smallest_ = *std::min_element(f.nodes_.begin(), f.nodes_.end());
  // Over the domain's box, by node: where h < r, and the extra cells (cells go as h^-3).
  size_t in_box = 0, graded = 0;
  double extra = 0;
  for (int64_t k = 0; k < f.nz_; ++k)
    for (int64_t j = 0; j < f.ny_; ++j)
      for (int64_t i = 0; i < f.nx_; ++i) {
        const Vec3 x = lo + g * Vec3{double(i), double(j), double(k)};
        if (x.x < d.bounds.lo.x || x.y < d.bounds.lo.y || x.z < d.bounds.lo.z || x.x > d.bounds.hi.x || x.y > d.bounds.hi.y || x.z > d.bounds.hi.z) continue;
        ++in_box;
        const double h = f.nodes_[index(i, j, k)];
        if (h < r) ++graded, extra += std::pow(r / h, 3) - 1;
      }
  f.graded_fraction = in_box ? double(graded) / double(in_box) : 0;
  f.extra_cell_fraction = in_box ? extra / double(in_box) : 0;
  return f;
}

double SizingField::at(Vec3 x) const {
  if (nodes_.empty()) return r_;
  const Vec3 q = (1 / spacing_) * (x - origin_);
  const double fx = std::clamp(q.x, 0.0, double(nx_ - 1) - 1e-9), fy = std::clamp(q.y, 0.0, double(ny_ - 1) - 1e-9),
               fz = std::clamp(q.z, 0.0, double(nz_ - 1) - 1e-9);
  const int64_t i = int64_t(fx), j = int64_t(fy), k = int64_t(fz);
  const double u = fx - double(i), v = fy - double(j), w = fz - double(k);
  auto at = [&](int64_t a, int64_t b, int64_t c) { return double(nodes_[size_t((c * ny_ + b) * nx_ + a)]); };
  const double c00 = at(i, j, k) * (1 - u) + at(i + 1, j, k) * u, c10 = at(i, j + 1, k) * (1 - u) + at(i + 1, j + 1, k) * u;
  const double c01 = at(i, j, k + 1) * (1 - u) + at(i + 1, j, k + 1) * u,
               c11 = at(i, j + 1, k + 1) * (1 - u) + at(i + 1, j + 1, k + 1) * u;
  return std::min(r_, (c00 * (1 - v) + c10 * v) * (1 - w) + (c01 * (1 - v) + c11 * v) * w);
}

}  // namespace froth

#include "sampling/sizing.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <queue>

#include "common/surface_locator.hpp"
#include "common/triangle_grid.hpp"

namespace froth {

SizingField SizingField::uniform(double r) {
  SizingField f;
  f.r_ = f.min_r_ = f.smallest_ = r;
  return f;
}

double SizingField::lipschitz() const { return std::sqrt(3.0) * grading_; }

namespace {

// The estimated cell count of a mesh sized by h. A saturated sample packs its seeds' disks of
// radius h/2 at a fixed fraction (0.3841, paper §3.3) of the volume they can reach: the domain
// grown by h/2, so about (V + S h/2) / h^3 seeds up to a constant, which cancels in the ratio to
// a uniform mesh. The surface term matters: in a wall thinner than h the seeds lie in one layer,
// about area / h^2 of them. The volume term is summed over the sizing nodes inside the domain
// where h < r (each stands for g^3), the surface term over the triangles.
struct CellEstimate {
  std::vector<float> nodes;                  // h at the nodes inside the domain where h < r
  std::vector<std::pair<double, float>> facets;  // (area, h at the centroid) where h < r
  double node_volume = 0, volume = 0, area = 0, r = 0;

  double cells(double floor) const {
    double count = 0, graded_area = 0;
    for (float h : nodes) count += node_volume / std::pow(std::max(floor, double(h)), 3);
    for (const auto& [a, h] : facets) count += a / (2 * std::pow(std::max(floor, double(h)), 2)), graded_area += a;
    const double rest_volume = std::max(0.0, volume - node_volume * double(nodes.size()));
    return count + rest_volume / (r * r * r) + (area - graded_area) / (2 * r * r);
  }
  double ratio(double floor) const { return cells(floor) / (volume / (r * r * r) + area / (2 * r * r)); }
};

}  // namespace

struct ThinPlace {
  Vec3 centroid;
  double half_lfs;  // half the wall or gap, below r
};

struct SizingBuilder {
  const Domain& d;
  std::vector<ThinPlace> thin;

  // Node values from the thin places and the floor: a shortest-path sweep over the grid. The
  // grid is the one for the lowest default floor, r/4, whatever the floor: a higher floor then
  // gives values at least as high at the same nodes, which the default floor's choice relies on.
  void sweep(SizingField& f, double floor) const {
    f.min_r_ = floor;
    const double r = f.r_, L = f.grading_;
    // Nodes, spacing r/4 (coarser for a huge box), where h can be below r: within the grading's
    // reach of a thin place, and in the domain's box (a node beyond it is never read: the field
    // is extended by its value at the nearest node). Nodes at the reach are r, so extending the
    // field there gives r beyond it too.
    const double reach = (r - std::min(floor, r / 4)) / L;
    Vec3 lo = thin[0].centroid, hi = lo;
    for (const ThinPlace& p : thin)
      for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], p.centroid[a]), hi[a] = std::max(hi[a], p.centroid[a]);
    for (int a = 0; a < 3; ++a)
      lo[a] = std::max(lo[a] - reach, d.bounds.lo[a] - r / 4), hi[a] = std::min(hi[a] + reach, d.bounds.hi[a] + r / 4);
    const double g = std::max(r / 4, std::cbrt((hi.x - lo.x) * (hi.y - lo.y) * (hi.z - lo.z) / 3e7));
    // Shifted by a fraction of a step: CAD faces often lie on round coordinates, and nodes on
    // them make the estimate's inside tests degenerate (and slow, in exact arithmetic).
    lo = lo - g * Vec3{0.1372, 0.2913, 0.4137};
    const Vec3 size = hi - lo;
    f.spacing_ = g, f.origin_ = lo;
    f.nx_ = int64_t(std::ceil(size.x / g)) + 1, f.ny_ = int64_t(std::ceil(size.y / g)) + 1,
    f.nz_ = int64_t(std::ceil(size.z / g)) + 1;
    const int64_t nx = f.nx_, ny = f.ny_, nz = f.nz_;
    auto& nodes = f.nodes_;
    nodes.assign(size_t(nx * ny * nz), float(r));
    auto index = [&](int64_t i, int64_t j, int64_t k) { return size_t((k * ny + j) * nx + i); };
    // Seeds of the sweep: the corners of each thin place's grid cell.
    std::priority_queue<std::pair<double, size_t>, std::vector<std::pair<double, size_t>>, std::greater<>> queue;
    auto offer = [&](size_t at, double v) {
      if (v < nodes[at]) nodes[at] = float(v), queue.push({double(float(v)), at});
    };
    for (const ThinPlace& p : thin) {
      const double a = std::max(floor, p.half_lfs);
      if (a >= r) continue;
      const Vec3 q = (1 / g) * (p.centroid - lo);
      const int64_t i = int64_t(q.x), j = int64_t(q.y), k = int64_t(q.z);
      for (int c = 0; c < 8; ++c) {
        const int64_t ii = i + (c & 1), jj = j + (c >> 1 & 1), kk = k + (c >> 2 & 1);
        const Vec3 node = lo + g * Vec3{double(ii), double(jj), double(kk)};
        offer(index(ii, jj, kk), std::max(floor, a + L * norm(node - p.centroid)));
      }
    }
    while (!queue.empty()) {
      const auto [v, at] = queue.top();
      queue.pop();
      if (v > nodes[at]) continue;
      const int64_t i = int64_t(at) % nx, j = int64_t(at) / nx % ny, k = int64_t(at) / (nx * ny);
      for (int dk = -1; dk <= 1; ++dk)
        for (int dj = -1; dj <= 1; ++dj)
          for (int di = -1; di <= 1; ++di) {
            const int64_t a = i + di, b = j + dj, c = k + dk;
            if ((di | dj | dk) == 0 || a < 0 || b < 0 || c < 0 || a >= nx || b >= ny || c >= nz) continue;
            offer(index(a, b, c), v + L * g * std::sqrt(double(di * di + dj * dj + dk * dk)));
          }
    }
    f.smallest_ = *std::min_element(nodes.begin(), nodes.end());
  }

  // The estimate's inputs: the nodes with h < r inside the domain and the graded triangles.
  // Row by row along x, the first graded node of a row is located by the exact inside test,
  // each next one by the parity of the triangles crossed on the way (side_from), so that a row
  // costs one ray, not one per node.
  CellEstimate estimate(const SizingField& f) const {
    const int64_t nx = f.nx_, rows = f.ny_ * f.nz_;
    const double graded_below = f.r_ * (1 - 1e-6);  // the nodes hold r as a float
    std::vector<std::vector<float>> found(static_cast<size_t>(rows));
    const double g = f.spacing_;
    std::unique_ptr<TriangleGrid> grid;
    // Buckets of two node steps, but at most 64 along the box's longest side: the grid is built
    // over the whole surface, and a fine one over a large box cost more than the walk it serves.
    const Vec3 extent = d.bounds.size();
    if (d.locator)
      grid = std::make_unique<TriangleGrid>(d.surface, *d.locator, std::max(2 * g, std::max({extent.x, extent.y, extent.z}) / 64));
    auto in_box = [&](Vec3 x) {
      return x.x >= d.bounds.lo.x && x.y >= d.bounds.lo.y && x.z >= d.bounds.lo.z && x.x <= d.bounds.hi.x &&
             x.y <= d.bounds.hi.y && x.z <= d.bounds.hi.z;
    };
#pragma omp parallel
    {
      std::vector<int32_t> near;
#pragma omp for schedule(dynamic, 16)
      for (int64_t row = 0; row < rows; ++row) {
        const int64_t j = row % f.ny_, k = row / f.ny_;
        const float* h = &f.nodes_[size_t(row * nx)];
        auto node = [&](int64_t i) { return f.origin_ + g * Vec3{double(i), double(j), double(k)}; };
        int64_t first = -1, last = -1;
        for (int64_t i = 0; i < nx; ++i)
          if (h[i] < graded_below && in_box(node(i))) last = i, first = first < 0 ? i : first;
        if (first < 0) continue;
        // From a point before the domain's box (outside), so that no row needs a ray.
        const Vec3 start{d.bounds.lo.x - g, node(first).y, node(first).z};
        bool inside = false;
        if (!grid) {
          inside = d.contains(node(first));
        } else {
          grid->triangles_near(start, node(first), near);
          if (!d.locator->side_from(start, false, node(first), near, inside)) inside = d.contains(node(first));
        }
        for (int64_t i = first;; ++i) {
          if (inside && h[i] < graded_below && in_box(node(i))) found[size_t(row)].push_back(h[i]);
          if (i == last) break;
          const Vec3 a = node(i), b = node(i + 1);
          if (!grid) {
            inside = d.contains(b);
            continue;
          }
          grid->triangles_near(a, b, near);
          if (!near.empty() && !d.locator->side_from(a, inside, b, near, inside)) inside = d.contains(b);
        }
      }
    }
    CellEstimate e;
    for (const auto& row : found) e.nodes.insert(e.nodes.end(), row.begin(), row.end());
    const TriangleSurface& S = d.surface;
    for (const auto& t : S.triangles) {
      const Vec3 a = S.vertices[t[0]], b = S.vertices[t[1]], c = S.vertices[t[2]];
      const double h = f.at((1.0 / 3) * (a + b + c)), area = 0.5 * norm(cross(b - a, c - a));
      if (h < graded_below) e.facets.push_back({area, float(h)});
    }
    e.node_volume = g * g * g, e.volume = std::max(d.volume, 1e-300), e.area = d.surface_area, e.r = f.r_;
    return e;
  }
};

SizingField SizingField::from_feature_size(const Domain& d, const FeatureSize& fs, double r, const SizingOptions& o,
                                           const std::vector<Measured>& regions) {
  SizingField f = uniform(r);
  f.grading_ = o.grading;
  // The thin places: the triangles whose wall or gap t is below 2r.
  SizingBuilder build{d, {}};
  auto thin_places = [&](const TriangleSurface& S, const FeatureSize& m) {
    for (size_t t = 0; t < S.triangles.size(); ++t) {
      const double lfs = std::min(t < m.thickness.size() ? m.thickness[t] : INFINITY,
                                  t < m.gap.size() ? m.gap[t] : INFINITY);
      if (!(lfs / 2 < r)) continue;
      const auto& tri = S.triangles[t];
      build.thin.push_back({(1.0 / 3) * (S.vertices[tri[0]] + S.vertices[tri[1]] + S.vertices[tri[2]]), lfs / 2});
    }
  };
  thin_places(d.surface, fs);
  for (const auto& [region, measured] : regions) thin_places(region->surface, *measured);
  const double floor = o.min_r > 0 ? std::min(o.min_r, r) : r / 4;
  if (std::all_of(build.thin.begin(), build.thin.end(), [&](const ThinPlace& p) { return std::max(floor, p.half_lfs) >= r; }))
    return f;
  CellEstimate e = (build.sweep(f, floor), build.estimate(f));
  if (o.min_r <= 0 && e.ratio(floor) > kDefaultCellBudget) {
    // The field with a higher floor m is at least max(m, this one), so the estimate from this
    // one's values bounds the new one's from above: bisect on it, then sweep again.
    double lo = floor, hi = r;
    for (int it = 0; it < 40; ++it) {
      const double mid = (lo + hi) / 2;
      (e.ratio(mid) > kDefaultCellBudget ? lo : hi) = mid;
    }
    if (hi >= r * (1 - 1e-9)) {
      SizingField u = uniform(r);
      u.grading_ = o.grading, u.floor_raised = true;
      return u;
    }
    f.floor_raised = true;
    build.sweep(f, hi);
    e = build.estimate(f);
  }
  f.graded_fraction = std::min(1.0, e.node_volume * double(e.nodes.size()) / e.volume);
  f.cell_ratio = e.ratio(f.min_r_);
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
  // Nodes hold r rounded to a float: where they all do, h is r itself, not r's float.
  const double h = (c00 * (1 - v) + c10 * v) * (1 - w) + (c01 * (1 - v) + c11 * v) * w;
  return h >= double(float(r_)) ? r_ : std::min(r_, h);
}

}  // namespace froth

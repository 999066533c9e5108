#include "quality/inscribed_ball.hpp"

#include <CGAL/Gmpzf.h>
#include <CGAL/QP_functions.h>
#include <CGAL/QP_models.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace froth {

namespace {

// The simplex method in doubles (the header's). A pivot smaller than kPivot is refused: nearly
// parallel face planes (a welded cell's, 1e-15 apart) gave a pivot of 2e-12 that was taken, and
// the answer was 0.156 r outside a plane where the true kernel is empty (LCD-knob.stl, --cells
// 1415 --seed 74376258 --grade). ok is false when no pivot is left (unbounded, or only tiny
// ones) or the pivots run out.
InscribedBall float_simplex(const std::vector<Vec3>& normals, const std::vector<double>& offsets) {
  // Dictionary: x_B[i] = beta[i] - sum_k D[i][k] x_N[k];  z = z0 + sum_k gamma[k] x_N[k].
  // Variables 0..3 are c.x, c.y, c.z, t (free); 4 + f is the slack of face f (>= 0).
  const size_t m = normals.size();
  std::vector<std::array<double, 4>> D(m);
  std::vector<double> beta(m);
  std::vector<int> basic(m);
  std::array<int, 4> nonbasic = {0, 1, 2, 3};
  std::array<double, 4> gamma = {0, 0, 0, 1};
  std::array<bool, 4> negated = {false, false, false, false};
  // Start from c = 0, t = t0 = min(0, min_f d_f), which satisfies every constraint: t - t0
  // takes t's place, so the slacks d_f - t0 start non-negative. The origin (the seed) need not
  // be in the kernel: a non-convex cell's seed may lie beyond a face's plane.
  double t0 = 0;
  for (size_t f = 0; f < m; ++f) t0 = std::min(t0, offsets[f]);
  double z0 = t0;
  double scale = 0;
  for (size_t f = 0; f < m; ++f) {
    D[f] = {normals[f].x, normals[f].y, normals[f].z, 1};
    beta[f] = offsets[f] - t0;
    basic[f] = int(4 + f);
    scale = std::max(scale, std::abs(offsets[f]));
  }
  constexpr double kPivot = 1e-9;
  const double tol = 1e-12, rhs_tol = 1e-14 * std::max(scale, 1e-300);
  auto is_free = [](int v) { return v < 4; };
  bool optimal = false;
  for (int iter = 0; iter < 1000 && !optimal; ++iter) {
    // Entering variable: the smallest index that improves z (Bland).
    int k = -1;
    for (int j = 0; j < 4; ++j) {
      const bool improves = is_free(nonbasic[j]) ? std::abs(gamma[j]) > tol : gamma[j] > tol;
      if (improves && (k < 0 || nonbasic[j] < nonbasic[k])) k = j;
    }
    if (k < 0) {
      optimal = true;
      break;
    }
    if (gamma[k] < 0) {  // a free variable that should decrease: work with its negative
      for (size_t i = 0; i < m; ++i) D[i][k] = -D[i][k];
      gamma[k] = -gamma[k];
      negated[nonbasic[k]] = !negated[nonbasic[k]];
    }
    // Leaving variable: the tightest bounded row (ties to the smallest index).
    int leave = -1;
    double best = 0;
    for (size_t i = 0; i < m; ++i) {
      if (is_free(basic[i]) || D[i][k] <= kPivot) continue;
      const double ratio = std::max(beta[i], 0.0) / D[i][k];
      if (leave < 0 || ratio < best - rhs_tol || (ratio <= best + rhs_tol && basic[i] < basic[leave]))
        leave = int(i), best = ratio;
    }
    if (leave < 0) return {};  // unbounded, or no pivot large enough
    // Pivot: the entering variable takes row i's place.
    const size_t i = size_t(leave);
    const double p = D[i][k];
    beta[i] /= p;
    for (int j = 0; j < 4; ++j) D[i][j] = j == k ? 1 / p : D[i][j] / p;
    for (size_t r = 0; r < m; ++r) {
      const double q = D[r][k];
      if (r == i || q == 0) continue;
      beta[r] -= q * beta[i];
      for (int j = 0; j < 4; ++j) D[r][j] = j == k ? -q * D[i][k] : D[r][j] - q * D[i][j];
    }
    const double g = gamma[k];
    z0 += g * beta[i];
    for (int j = 0; j < 4; ++j) gamma[j] = j == k ? -g * D[i][k] : gamma[j] - g * D[i][j];
    std::swap(basic[i], nonbasic[k]);
  }
  InscribedBall out;
  if (!optimal) return out;
  double x[4] = {0, 0, 0, 0};
  for (size_t i = 0; i < m; ++i)
    if (is_free(basic[i])) x[basic[i]] = negated[basic[i]] ? -beta[i] : beta[i];
  out.center = {x[0], x[1], x[2]};
  out.radius = z0;  // t0 + (t - t0)
  out.ok = true;
  return out;
}

// The same program in CGAL's exact solver (Gmpzf): for the rare cells the float simplex gives
// up on or answers outside a plane.
InscribedBall exact_program(const std::vector<Vec3>& normals, const std::vector<double>& offsets) {
  CGAL::Quadratic_program<double> lp(CGAL::SMALLER, false, 0, false, 0);  // c and t free
  for (size_t f = 0; f < normals.size(); ++f) {
    const int row = int(f);
    lp.set_a(0, row, normals[f].x), lp.set_a(1, row, normals[f].y), lp.set_a(2, row, normals[f].z);
    lp.set_a(3, row, 1), lp.set_b(row, offsets[f]);
  }
  lp.set_c(3, -1);
  const auto sol = CGAL::solve_linear_program(lp, CGAL::Gmpzf());
  InscribedBall out;
  if (!sol.is_optimal()) return out;
  double x[4];
  auto v = sol.variable_values_begin();
  for (int j = 0; j < 4; ++j, ++v) x[j] = CGAL::to_double(*v);
  out.center = {x[0], x[1], x[2]};
  out.radius = x[3];
  out.ok = true;
  return out;
}

}  // namespace

InscribedBall largest_inscribed_ball(const std::vector<Vec3>& normals, const std::vector<double>& offsets) {
  const InscribedBall ball = float_simplex(normals, offsets);
  double scale = 0, beyond = -INFINITY;
  for (size_t f = 0; f < normals.size(); ++f) {
    scale = std::max(scale, std::abs(offsets[f]));
    beyond = std::max(beyond, dot(normals[f], ball.center) + ball.radius - offsets[f]);
  }
  if (ball.ok && beyond <= 1e-9 * scale) return ball;
  return exact_program(normals, offsets);
}

}  // namespace froth

// What a run can be asked to do: options checked, and memory estimated, before any work.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>

#include <fmt/format.h>

#include "common/background_grid.hpp"
#include "froth/error.hpp"
#include "froth/mesh.hpp"
#include "froth/partition.hpp"
#include "froth/weld.hpp"
#include "input/cracked_domain.hpp"
#include "sampling/mps.hpp"
#include "sampling/sizing.hpp"

namespace froth {

namespace {

// Bytes per cell at the run's peak with the quality stage (docs/performance.md measures it), and
// per background cube (the seed index and the sampler's lists).
constexpr double kBytesPerCell = 1024, kBytesPerCube = 8;

constexpr double kMaxBackgroundCubes = 2e9;  // the sampler indexes base cubes with 32 bits

double background_cubes(const Domain& domain, double r) {
  const double side = r / std::sqrt(3.0);
  const Vec3 size = domain.bounds.size();
  return BackgroundGrid::cubes_along(size.x, side) * BackgroundGrid::cubes_along(size.y, side) *
         BackgroundGrid::cubes_along(size.z, side);
}

// Saturated RSA packs disks of radius r/2 at 0.3841 of the volume they reach: the domain grown
// by r/2 (sizing.cpp's estimate, here for h = r).
double saturated_cells(const Domain& domain, double r) {
  return 0.7336 * (domain.volume + domain.surface_area * r / 2) / (r * r * r);
}

}  // namespace

RunEstimate estimate_run(const Domain& domain, const MeshOptions& opt) {
  // Grading can add up to its default budget.
  const double r = opt.r;
  const double cells = saturated_cells(domain, r) * (opt.grade ? kDefaultCellBudget : 1);
  return {cells, kBytesPerCell * cells + kBytesPerCube * background_cubes(domain, r)};
}

namespace {

// The seeds of a maximal sample at r: drawn whole, or by slabs over a partitioned run's ranks
// when each gets the layers the sampler's halo needs (the count is the serial one either way).
size_t sample_size(const Domain& domain, double r, uint64_t seed, Communicator* comm) {
  const BackgroundGrid grid = BackgroundGrid::covering(domain.bounds, r);
  if (!comm || comm->size() == 1 || grid.nz / comm->size() < kCellHaloLayers)
    return sample_maximal_poisson_disk(domain, r, seed).seeds.size();
  SamplingPartition part{slab_of(comm->rank(), comm->size(), grid.nz), comm};
  const Sample s = sample_maximal_poisson_disk(domain, r, seed, &part);
  const int64_t layer = int64_t(grid.nx) * grid.ny;
  size_t own = 0;
  for (int64_t c = layer * part.slab.owned_begin; c < layer * part.slab.owned_end; ++c)
    s.for_seeds_in_cube(c, [&](int32_t) { ++own; });
  return comm->sum(own);
}

}  // namespace

double radius_for_cells(const Domain& domain, double cells, uint64_t seed, bool sample, Communicator* comm) {
  if (!(cells >= 1) || !(cells <= 1e10))
    fail(ErrorKind::Usage, fmt::format("the cell count must be from 1 to 1e10, got {}", cells));
  // The density's estimate (V + S r/2) / r^3 is decreasing in r: bisect on its logarithm.
  auto estimate = [&](double r) { return saturated_cells(domain, r); };
  double lo = domain.bounds.diagonal() * 1e-7, hi = domain.bounds.diagonal() * 10;
  for (int it = 0; it < 200; ++it) {
    const double mid = std::sqrt(lo * hi);
    (estimate(mid) > cells ? lo : hi) = mid;
  }
  double r = hi;
  if (!sample) return r;
  // One sample at that r: the estimate is 3 to 25% high on the shared models (their features
  // and fringes); the count scales as r^-k, with k the estimate's local exponent (3 in bulk, 2
  // where the surface term dominates).
  MeshOptions probe;
  probe.r = r;
  check_mesh_options(domain, probe);
  const double seeds = double(sample_size(domain, r, seed, comm));
  if (seeds > 0) {
    const double k = -std::log(estimate(r * 1.01) / estimate(r)) / std::log(1.01);
    r *= std::pow(seeds / cells, 1 / k);
  }
  return r;
}

MeshOptions resolve_options(const Domain& domain, const MeshOptions& given, bool sample, Communicator* comm) {
  MeshOptions opt = given;
  if (opt.cells != 0) {
    if (opt.r != 0) fail(ErrorKind::Usage, "give r (the sampling radius) or a cell count, not both");
    opt.r = radius_for_cells(domain, opt.cells, opt.seed, sample, comm);
    opt.cells = 0;  // resolved: r stands for the count from here on (RunReport::cells_requested keeps it)
  }
  if (!opt.weld) opt.weld = default_weld_tolerance(opt.r, domain.bounds.diagonal(), opt.convex);
  return opt;
}

void check_mesh_options(const Domain& domain, const MeshOptions& given, double share) {
  const MeshOptions opt = resolve_options(domain, given, false);
  const double weld = *opt.weld;
  if (!(opt.r > 0) || !std::isfinite(opt.r)) fail(ErrorKind::Usage, fmt::format("r must be positive, got {}", opt.r));
  // OpenMP runtimes fail (libgomp crashes) when asked for far more threads than a machine runs.
  if (opt.threads < 0 || opt.threads > kMaxThreads)
    fail(ErrorKind::Usage, fmt::format("threads must be from 0 (all cores) to {}, got {}", kMaxThreads, opt.threads));
  if (!(weld >= 0) || !(weld < opt.r))
    fail(ErrorKind::Usage, fmt::format("the weld tolerance must be in [0, r), got {:.6g}", weld));
  if (opt.convex && weld > 0)
    fail(ErrorKind::Usage, fmt::format("convex cells cannot be combined with welding (weld tolerance {:.6g}): welding bends "
                                       "faces out of their planes, and a convex cell needs planar faces; with convex "
                                       "cells the default weld tolerance is 0",
                                       weld));
  if (opt.convex && domain.cracks)
    for (const CrackSheet& c : domain.cracks->sheets)
      if (!c.on_sheets.empty())
        fail(ErrorKind::Usage, fmt::format("convex cells with crossing cracks (crack {}) are not supported yet: mesh them "
                                           "without --convex",
                                           c.name));
  // Checked here, not where the sizing field is made, so that a bad value is refused whatever
  // the part (a part without thin walls never makes one).
  if (opt.grade) {
    if (!(opt.grading > 0) || !(opt.grading < 0.25))
      fail(ErrorKind::Usage, fmt::format("the maximum grading must be in (0, 0.25), got {} (the field's slope is sqrt(3) times "
                                         "it, below 1/2 for the maximality bound)",
                                         opt.grading));
    if (!(opt.min_r >= 0) || opt.min_r > opt.r)
      fail(ErrorKind::Usage, fmt::format("the smallest graded radius min_r must be in (0, r], got {}", opt.min_r));
  }
  // Squared distances of coordinates and radii must stay far from underflow and overflow.
  const Vec3 size = domain.bounds.size();
  const double extent = std::max({size.x, size.y, size.z});
  if (!(extent >= 1e-100 && extent <= 1e100) || !(opt.r >= 1e-100 && opt.r <= 1e100))
    fail(ErrorKind::Usage, fmt::format("scale out of range: the domain is {:.3g} across and r = {:.3g}; froth "
                                       "computes with both in [1e-100, 1e100] (rescale the input's units)",
                                       extent, opt.r));
  // The cells are computed relative to the part (Domain::origin), but written in the input's
  // coordinates, where each vertex rounds by half the spacing of doubles. Beyond 1e-6 r that
  // rounding would break what the mesh states (a center inside every face plane by 1e-6 r) and
  // bend faces by more than welding does: no mesh with this r is right there.
  const Vec3 lo = domain.bounds.lo + domain.origin, hi = domain.bounds.hi + domain.origin;
  const double far = std::max({std::abs(lo.x), std::abs(lo.y), std::abs(lo.z), std::abs(hi.x), std::abs(hi.y), std::abs(hi.z)});
  const double step = far * 0x1p-52;
  if (step > 1e-6 * opt.r)
    fail(ErrorKind::Usage,
         fmt::format("the part's coordinates reach {:.6g}, where doubles are {:.3g} apart ({:.3g} r): over 1e-6 r, "
                     "the cells cannot be computed or written accurately; translate the part nearer the origin, or "
                     "use r of {:.3g} or more",
                     far, step, step / opt.r, 1e6 * step));
  const int thin = size.x <= std::min(size.y, size.z) ? 0 : (size.y <= size.z ? 1 : 2);
  if (size[thin] < 1e-6 * opt.r)
    fail(ErrorKind::Usage,
         fmt::format("the domain is {:.3g} thick along {} ({:.3g} r): cells a million times wider than thick are no "
                     "mesh, and the sampler would refine without end; use r below {:.3g}",
                     size[thin], "xyz"[thin], size[thin] / opt.r, 1e6 * size[thin]));
  // Memory first: on most machines it is the nearer limit, and its message gives an r that fits.
  const double limit = opt.max_memory_bytes > 0 ? opt.max_memory_bytes : available_memory();
  RunEstimate e = estimate_run(domain, opt);
  e.bytes *= share, e.cells *= share;
  if (limit > 0 && e.bytes > limit) {
    const double fits = opt.r * std::cbrt(e.bytes / limit) * 1.05;
    fail(ErrorKind::Usage,
         fmt::format("r = {} needs about {:.3g} GB ({:.3g} cells) and {:.3g} GB is available{}: use r of {:.3g} or more, "
                     "or a machine with more memory (a partitioned run spreads one mesh over several)",
                     opt.r, e.bytes / 1e9, e.cells, limit / 1e9, opt.max_memory_bytes > 0 ? " (the memory limit given)" : "",
                     fits));
  }
  const double cubes = background_cubes(domain, opt.r);
  if (cubes > kMaxBackgroundCubes) {
    MeshOptions fits = opt;
    fits.r = opt.r * std::cbrt(cubes / kMaxBackgroundCubes) * 1.02;
    fail(ErrorKind::Usage,
         fmt::format("r = {} needs {:.3g} background cubes (side r/sqrt(3), over the domain's bounding box), and the "
                     "sampler numbers them with 32 bits, up to {:.3g}: use r of {:.3g} or more (about {:.3g} cells "
                     "for this part)",
                     opt.r, cubes, kMaxBackgroundCubes, fits.r, estimate_run(domain, fits).cells));
  }
}

}  // namespace froth

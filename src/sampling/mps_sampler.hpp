// Maximal Poisson-disk sampling on a background grid of cubes with diagonal r.
//
// Unbiasedness: the darts are a space-time Poisson process of constant intensity over the domain
// (each round gives every active cube a Poisson number of darts with uniform positions and
// uniform arrival times within the round), and a dart is accepted iff no earlier-accepted seed
// lies within r. That is random sequential addition exactly, run to saturation; Ebeida et al.'s
// refinement only drops sub-cubes that are already covered (where every dart would be rejected)
// or outside the domain, which does not change the law of the accepted set. Within a round the
// candidates are accepted greedily in arrival order, so the result does not depend on how the
// work is split. Cubes cut by the boundary are sampled too (darts outside are rejected), so the
// density does not sag next to the boundary.
#pragma once
#include <functional>
#include "sampling/mps.hpp"

#include <omp.h>
#ifdef __SSE2__
#include <emmintrin.h>
#endif

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <map>
#include <optional>
#include <cstring>
#include <span>

#include "common/random.hpp"
#include "sampling/grandchild_marks.hpp"
#include "sampling/poisson_count.hpp"
#include "common/surface_locator.hpp"
#include "sampling/protect.hpp"
#include "common/tolerances.hpp"

// The sampler (sampling/mps.hpp) as one class over four files by stage: the dart rounds and
// the refinement (mps.cpp), coverage tests (mps_coverage.cpp), boundary cubes
// (mps_boundary.cpp) and arrival-order acceptance (mps_acceptance.cpp). Internal to them.
namespace froth::mps {

// 16 bytes: the active lists are the sampler's largest memory.
struct ActiveCube {
  static constexpr uint32_t kInside = 0x80000000u;  // in sz_flags: entirely inside the domain
  uint32_t base;              // base cube index (the pipeline keeps grids under 2^31 cubes)
  uint32_t sx, sy;            // sub-cube coordinates inside the base cube at the current level
  uint32_t sz_flags;          // sub-cube z coordinate, and kInside
  uint32_t sz() const { return sz_flags & ~kInside; }
  bool inside() const { return sz_flags & kInside; }
};

// The active cubes of a level, in parts that are units of work: a part's children are a part
// of the next level, so the lists are never copied into one. Results depend on neither the parts nor their order: darts are keyed by cube, and
// seeds are numbered in Morton order.
struct ActiveCubes {
  std::vector<std::vector<ActiveCube>> parts;
  size_t size() const {
    size_t n = 0;
    for (const auto& p : parts) n += p.size();
    return n;
  }
  bool empty() const { return size() == 0; }
};

// Concatenates per-chunk results in chunk order, freeing each chunk as it goes.
template <class T>
std::vector<T> concatenate(std::vector<std::vector<T>>& parts) {
  size_t total = 0;
  for (const auto& p : parts) total += p.size();
  std::vector<T> all;
  all.reserve(total);
  for (auto& p : parts) {
    all.insert(all.end(), p.begin(), p.end());
    std::vector<T>().swap(p);
  }
  return all;
}

struct Candidate {
  uint64_t time;
  int64_t base;
  Vec3 p;
};

// Expected darts per active cube per round, and rounds per refinement level. They tune speed
// only: the law of the sample is the same for any choice (each round is a slice of the darts'
// arrival times, and its intensity may differ from the next one's). The first level throws its
// darts in rounds that double: the first round's candidates conflict only with each other, and
// the cost of deciding them in arrival order grows with the square of their density, while a
// later round's darts mostly meet a seed and stop there, so the acceptance falls as the rounds
// grow. Each round walks every base cube, so fewer, doubling rounds beat six equal ones
// (commit 2ffdb9f has the figures).
constexpr std::array<double, 4> kDartsPerCubeLevel0Rounds = {0.0625, 0.125, 0.25, 0.5};
constexpr double kDartsPerCubePerRound = 0.5;
constexpr int kRoundsPerLevel = 1;
// The first refinement level at which a child in no single ball gets the exact two- and
// three-ball test (covered()). Above it, most such children hold a gap or need more balls, and
// the test (half of a level's refinement time) costs more than refining the few it clears: their
// children mostly fit in one ball. Below it, cubes straddling the seam of two balls would double
// at every level; level 7 measured best (commit 7d3a47c). Levels are relative to r, so the
// choice does not depend on scale. Nor does the
// sample: a child's darts depend only on its place and level, and those thrown into covered
// space are all rejected, so keeping a covered child changes the work, not the seeds.
constexpr int kFirstExactCoverageLevel = 7;
// The first refinement level that throws the next level's darts itself, into the children it
// keeps, testing them against the seeds it gathered for them (refine()). Where the marks stand in
// for those seeds (levels 0 and 1 of most domains) it has none; where it has them at those levels
// (a domain that fills little of its grid), throwing there gained nothing measurable (commit
// 4e3c950).
constexpr int kFirstFusedDartLevel = 2;

class Sampler {
 public:
  Sampler(const Domain& domain, double r, uint64_t seed, SamplingPartition* partition)
      : domain_(domain), r_(r), r2_(r * r), seed_(seed), rng_(seed, RandomStream::Sampling),
        partition_(partition) {
    s_.grid = BackgroundGrid::covering(domain.bounds, r);
    const int64_t layer = int64_t(s_.grid.nx) * s_.grid.ny;
    if (partition_) {
      const Slab& sl = partition_->slab;
      owned_begin_ = sl.owned_begin, owned_end_ = sl.owned_end;
      s_.cube_offset = layer * sl.window_begin;
      s_.cube_seed.assign(size_t(layer) * (sl.window_end - sl.window_begin), -1);
    } else {
      owned_begin_ = 0, owned_end_ = s_.grid.nz;
      s_.cube_seed.assign(s_.grid.cube_count(), -1);
    }
    for (const auto& [di, dj, dk] : stencil())
      stencil_offsets_.push_back((int64_t(dk) * s_.grid.ny + dj) * s_.grid.nx + di);
    s_.stats.base_cube_side = s_.grid.side;
    s_.stats.grid = {size_t(s_.grid.nx), size_t(s_.grid.ny), size_t(s_.grid.nz)};
  }

  Sample run();
  // Told after each level the fraction of the domain's cubes covered (from the calling thread).
  void on_level(std::function<void(double)> f) { progress_ = std::move(f); }

 private:
  int layer_of(int64_t b) const { return int(b / (int64_t(s_.grid.nx) * s_.grid.ny)); }
  int32_t& cube_entry(int64_t b) { return s_.cube_seed[b - s_.cube_offset]; }
  int32_t cube_entry(int64_t b) const { return s_.cube_seed[b - s_.cube_offset]; }

  // Is `mine` true on any rank? (Every rank calls it at the same point.)
  bool anywhere(bool mine) const { return partition_ ? partition_->comm->any(mine) : mine; }

  Vec3 base_origin(int64_t b) const {
    const auto& g = s_.grid;
    int i, j, k;
    g.coords(b, i, j, k);
    return g.origin + Vec3{i * g.side, j * g.side, k * g.side};
  }

  // The entries (cube_seed) of base cube b's stencil cubes [first, last) that hold seeds, in
  // stencil order, into `found` (room for kStencilSize); -1 when the stencil leaves the grid or
  // the window, and the caller walks it cube by cube. Most cubes are two or more cubes from the
  // sides: their stencil is read through index offsets without a branch per cube (most are
  // empty, which a branch would mispredict). The first
  // kNearestCubes entries of the stencil are the cubes that share a face, edge or corner with b.
  static constexpr int kStencilSize = 116, kNearestCubes = 26;
  int occupied_stencil(int64_t b, int i0, int j0, int32_t* found, int first = 0, int last = kStencilSize) const {
    const auto& g = s_.grid;
    const int64_t slot = b - s_.cube_offset, span = 2 * (int64_t(g.nx) * g.ny + g.nx + 1);
    if (!(i0 >= 2 && i0 + 2 < g.nx && j0 >= 2 && j0 + 2 < g.ny && slot >= span &&
          slot + span < int64_t(s_.cube_seed.size())))
      return -1;
    return s_.occupied_entries(slot, std::span(stencil_offsets_).subspan(first, last - first), found);
  }
  // Calls f(position) for the seeds of the entries occupied_stencil() found.
  template <class F>
  void for_found_seeds(const int32_t* found, int n, F&& f) const {
    for (int k = 0; k < n; ++k) s_.for_seeds_of_entry(found[k], [&](int32_t id) { f(s_.seeds[id]); });
  }

  // Seeds within r of base cube b (which holds no seed), read from the grid itself through the
  // stencil below.
  void seeds_near_base_cube(int64_t b, std::vector<Vec3>& near) const {
    near.clear();
    const auto& g = s_.grid;
    int i0, j0, k0;
    g.coords(b, i0, j0, k0);
    const Vec3 lo = base_origin(b), hi = lo + Vec3{g.side, g.side, g.side};
    auto add_if_near = [&](Vec3 p) {
      double d2 = 0;
      for (int a = 0; a < 3; ++a) {
        const double t = std::max({lo[a] - p[a], p[a] - hi[a], 0.0});
        d2 += t * t;
      }
      if (d2 < r2_) near.push_back(p);
    };
    int32_t found[kStencilSize];
    const int n = occupied_stencil(b, i0, j0, found);
    if (n >= 0) return for_found_seeds(found, n, add_if_near);
    for (const auto& [di, dj, dk] : stencil()) {
      if (!g.inside(i0 + di, j0 + dj, k0 + dk)) continue;
      s_.for_seeds_in_cube(g.index(i0 + di, j0 + dj, k0 + dk), [&](int32_t id) { add_if_near(s_.seeds[id]); });
    }
  }

  // The base cubes within r of a base cube, as offsets, nearest first: all within two steps along
  // each axis but the cube itself and the eight two steps away along all three (their distance
  // is exactly r).
  static const std::vector<std::array<int, 3>>& stencil() {
    static const std::vector<std::array<int, 3>> offsets = [] {
      std::vector<std::array<int, 3>> o;
      for (int k = -2; k <= 2; ++k)
        for (int j = -2; j <= 2; ++j)
          for (int i = -2; i <= 2; ++i)
            if ((i || j || k) && !(std::abs(i) == 2 && std::abs(j) == 2 && std::abs(k) == 2)) o.push_back({i, j, k});
      auto steps = [](const std::array<int, 3>& d) {
        int s = 0;
        for (int a : d) s += std::max(std::abs(a) - 1, 0) * 4 + std::abs(a);
        return s;
      };
      std::stable_sort(o.begin(), o.end(), [&](const auto& a, const auto& b) { return steps(a) < steps(b); });
      return o;
    }();
    return offsets;
  }

  // Is one of `seeds` closer than r to p? Without a branch per seed: there are few, and one of
  // them mostly is.
  bool any_within_r(std::span<const Vec3> seeds, Vec3 p) const {
    bool hit = false;
    for (const Vec3& s : seeds) hit |= norm2(s - p) < r2_;
    return hit;
  }

  // Is a seed closer than r to p, a point of base cube b (which holds no seed), when b's stencil
  // leaves the grid or the window (occupied_stencil() gives -1): its cubes one by one, nearest
  // first, skipping those beyond r and outside the grid.
  bool seed_within_r_near_edge(Vec3 p, int64_t b) const {
    const auto& g = s_.grid;
    int i0, j0, k0;
    g.coords(b, i0, j0, k0);
    const Vec3 q = p - g.origin;
    double gap[3][5];  // squared distance from p to the slab of cube c0 + d along each axis
    for (int d = -2; d <= 2; ++d) {
      gap[0][d + 2] = BackgroundGrid::axis_gap(q.x, i0 + d, g.side);
      gap[1][d + 2] = BackgroundGrid::axis_gap(q.y, j0 + d, g.side);
      gap[2][d + 2] = BackgroundGrid::axis_gap(q.z, k0 + d, g.side);
    }
    for (const auto& [di, dj, dk] : stencil()) {
      if (gap[0][di + 2] + gap[1][dj + 2] + gap[2][dk + 2] >= r2_) continue;
      if (!g.inside(i0 + di, j0 + dj, k0 + dk)) continue;
      bool hit = false;
      s_.for_seeds_in_cube(g.index(i0 + di, j0 + dj, k0 + dk), [&](int32_t id) { hit |= norm2(s_.seeds[id] - p) < r2_; });
      if (hit) return true;
    }
    return false;
  }

  // The seeds of a base cube's stencil, gathered by the first dart into one of its sub-cubes
  // and read by the next ones (a base cube's sub-cubes are adjacent in the active lists): the
  // nearest kNearestCubes cubes' at once, the rest at the first dart they do not reject.
  struct StencilSeeds {
    int64_t base = -1;
    int i0 = 0, j0 = 0;
    bool interior = false;  // the stencil lies inside the grid and the window
    bool outer_known = false;
    std::vector<Vec3> nearest, outer;
  };
  // Is a seed closer than r to p, a point of base cube b (which holds no seed)? For darts into
  // b's sub-cubes, through `cache`.
  bool seed_within_r(Vec3 p, int64_t b, StencilSeeds& cache) const {
    int32_t found[kStencilSize];
    if (cache.base != b) {
      int k0;
      s_.grid.coords(b, cache.i0, cache.j0, k0);
      const int n = occupied_stencil(b, cache.i0, cache.j0, found, 0, kNearestCubes);
      cache.base = b, cache.interior = n >= 0, cache.outer_known = false;
      cache.nearest.clear();
      if (cache.interior) for_found_seeds(found, n, [&](Vec3 s) { cache.nearest.push_back(s); });
    }
    if (!cache.interior) return seed_within_r_near_edge(p, b);
    // Most darts after the first level meet a seed, most often in a cube next to theirs: those
    // cubes first.
    if (any_within_r(cache.nearest, p)) return true;
    if (!cache.outer_known) {
      cache.outer.clear();
      for_found_seeds(found, occupied_stencil(b, cache.i0, cache.j0, found, kNearestCubes),
                      [&](Vec3 s) { cache.outer.push_back(s); });
      cache.outer_known = true;
    }
    return any_within_r(cache.outer, p);
  }

  // The children of the parent [lo, lo + 2h]^3 inside one seed's ball, as bits (child dx + 2 dy +
  // 4 dz). A child is in seed q's ball iff its farthest corner is: iff the squared distances from
  // q to the child's farther face along each axis sum to at most r^2. Eight children in ten are
  // covered so; testing all eight per seed at once avoids a mispredicted branch per child and seed.
  uint32_t children_in_one_ball(Vec3 lo, double h, const std::vector<Vec3>& near) const;

  // Which of the 64 grandchildren of every cube of the window (bit x + 4y + 16z, in steps of a
  // quarter side) lie in one seed's ball, for the seeds from `first` on: the one-ball tests of
  // the first two refinements, done from the seeds' side. A tenth of the cubes hold a seed, so
  // marking the cubes around each seed reads far less than gathering the seeds around each cube,
  // and the marks of a level's seeds serve the next level too.
  void mark_grandchildren_in_one_ball(size_t first);

  // The marks of seed q on the cubes of layers [k_begin, k_end) around it.
  void mark_around(Vec3 q, int k_begin, int k_end);

  // The children of sub-cube (sx, sy, sz) of base cube b at level 0 or 1 that the marks show to be
  // covered (bits as children_in_one_ball): at level 1, those in one ball; at level 0, those
  // whose eight children each are.
  uint32_t marked_children(int64_t b, int level, uint32_t sx, uint32_t sy, uint32_t sz) const {
    int i, j, k;
    s_.grid.coords(b, i, j, k);
    const uint64_t m = grandchild_marks_.get(i, j, k);
    uint32_t covered = 0;
    for (uint32_t ch = 0; ch < 8; ++ch) {
      const uint32_t x = ch & 1, y = ch >> 1 & 1, z = ch >> 2;
      if (level == 1) {
        covered |= uint32_t(m >> ((2 * sx + x) + 4 * (2 * sy + y) + 16 * (2 * sz + z)) & 1) << ch;
      } else {
        const uint64_t quad = uint64_t(0x33) << (2 * x + 8 * y + 32 * z);  // its 2x2x2 quarters
        const uint64_t all = quad | quad << 16;
        covered |= uint32_t((m & all) == all) << ch;
      }
    }
    return covered;
  }

  // The nearest near seed of each point of the parent's 3x3x3 lattice (its children's corners),
  // found when a child first needs it: neighbouring children share corners.
  struct CornerCache {
    Vec3 lo;
    double h;
    uint32_t known = 0;  // bit p: point p's entry is filled in
    int nearest[27];
    double dist2[27];
    void reset(Vec3 parent_lo, double child_side) { lo = parent_lo, h = child_side, known = 0; }
    Vec3 point(int p) const { return lo + Vec3{(p % 3) * h, (p / 3 % 3) * h, (p / 9) * h}; }
    // The lattice point of corner k of child (dx, dy, dz); corner k is at the child's low corner
    // plus (k & 1, k >> 1 & 1, k >> 2) sides.
    static int child_corner(int dx, int dy, int dz, int k) {
      return ((dz + (k >> 2)) * 3 + dy + ((k >> 1) & 1)) * 3 + dx + (k & 1);
    }
  };

  // The distinct nearest seeds of a piece's vertices (indices into the near seeds), up to three.
  struct Sites {
    int id[3];
    int n = 0;
    // False if `s` would be a fourth: the exact tests give up there.
    bool add(int s) {
      if (std::find(id, id + n, s) != id + n) return true;
      if (n == 3) return false;
      id[n++] = s;
      return true;
    }
  };
  // The index in `near` of the seed nearest x (the first of ties; -1 if none), and its squared
  // distance.
  static int nearest_seed(Vec3 x, const std::vector<Vec3>& near, double& dist2) {
    dist2 = INFINITY;
    int arg = -1;
    for (size_t i = 0; i < near.size(); ++i) {
      const double d = norm2(near[i] - x);
      if (d < dist2) dist2 = d, arg = int(i);
    }
    return arg;
  }
  int nearest_to_corner(int p, const std::vector<Vec3>& near, CornerCache& cc) const {
    if (!(cc.known >> p & 1)) {
      cc.nearest[p] = nearest_seed(cc.point(p), near, cc.dist2[p]);
      cc.known |= 1u << p;
    }
    return cc.nearest[p];
  }

  // A cube's edges as pairs of corners; corner k is lo + h * (k & 1, k >> 1 & 1, k >> 2).
  static constexpr int kCubeEdges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                            {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};

  // The last steps of the exact coverage tests below, on a convex piece P of a cube whose
  // vertices are each within r of their nearest seed in `near`, these being the two or three
  // `s`: P is covered by their balls iff every crossing of one of P's edges with the bisector
  // of two sites, not nearer the third, is within r, and, for three sites, so are the ends of the
  // equidistant line's part in P. P is the box [lo, hi], cut by `cut` if given.
  bool sites_cover(const std::vector<Vec3>& near, const Sites& s, const Vec3 (*edges)[2], int count, Vec3 lo, Vec3 hi,
                   const Plane* cut) const;

  // Is child (dx, dy, dz) of the parent described by `cc`, in no single ball (see
  // children_in_one_ball), inside the union of the r-balls around `near`? When the corners'
  // nearest seeds are two or three seeds S, exact for the balls of S: the cube is cut into
  // convex pieces by S's Voronoi diagram, and a piece is inside its seed's ball iff its
  // vertices are. They are the cube's corners (each within r of its nearest seed, checked
  // first), the crossings of the cube's edges with a bisector of two seeds of S that are not
  // nearer the third, and, for three seeds, the crossings of the cube's faces with the line
  // equidistant from all three. Nearly half the cubes a two-ball test keeps are covered by three.
  bool covered(const std::vector<Vec3>& near, CornerCache& cc, int dx, int dy, int dz) const;

  // A band around facet plane `pl` wider than the round-off of its signed distances at points
  // of the box [lo, lo + h]^3 (the plane is fitted to its triangles' corners, which lie on it
  // exactly).
  static double round_off_band(const Plane& pl, Vec3 lo, double h) {
    return 1e-9 * (std::abs(pl.offset) + h + std::max({std::abs(lo.x), std::abs(lo.y), std::abs(lo.z)}));
  }

  // Is the part of child (dx, dy, dz) on the inner side of `pl` inside the union of the r-balls
  // around `near`? The same exact test as covered() on the convex piece P = child ∩ {pl <= 0}
  // (made a round-off margin larger, so that it holds the domain's part): P's vertices are the
  // child's corners inside and the crossings of its edges with the plane; its edges, the inside
  // parts of the child's edges and the plane's section of each face; the three-seed line is
  // clipped to P. A cube cut by the boundary is often covered where it is inside the domain while
  // its part outside is not, and covered() alone keeps refining it (half of the cut sub-cubes
  // of the tube: measured with 256 random points each).
  bool covered_below_plane(const std::vector<Vec3>& near, CornerCache& cc, int dx, int dy, int dz,
                           const Plane& pl) const;

  // -1 outside, 0 cut by the boundary, 1 inside, with respect to the given planes; `cut`
  // (optional) receives the planes that cut the box, `first_cut` (optional) the first of them.
  // A box within `band` of a plane counts as cut by it.
  template <class PlaneIds>
  int classify_box(Vec3 lo, double h, const PlaneIds& ids, std::vector<int32_t>* cut = nullptr,
                   int32_t* first_cut = nullptr, double band = 0) const {
    bool inside = true;
    for (int32_t id : ids) {
      const Plane& pl = domain_.planes[id];
      // Extreme corners of the box along the plane normal.
      double dmin = pl.signed_distance(lo), dmax = dmin;
      for (int a = 0; a < 3; ++a) (pl.normal[a] > 0 ? dmax : dmin) += h * pl.normal[a];
      if (dmin > band) return -1;
      if (dmax > -band) {
        if (inside && first_cut) *first_cut = id;
        inside = false;
        if (cut) cut->push_back(id);
      }
    }
    return inside ? 1 : 0;
  }

  // A boundary base cube's place in the boundary lists (a bisection: callers look it up once
  // per cube, not per dart or per child).
  size_t boundary_slot(uint32_t b) const {
    return size_t(std::lower_bound(boundary_base_.begin(), boundary_base_.end(), b) - boundary_base_.begin());
  }

  // What cuts the boundary cube in `slot`: facet planes of a convex domain, triangles of any
  // other.
  std::span<const int32_t> cutting_planes(size_t slot) const {
    return {boundary_planes_.data() + boundary_begin_[slot], boundary_begin_[slot + 1] - boundary_begin_[slot]};
  }

  // Is p, a point of the boundary cube in `slot`, inside the domain?
  bool inside_domain(Vec3 p, size_t slot) const {
    if (!domain_.convex) {
      if (const int32_t facet = boundary_facet_[slot]; facet >= 0) {  // the plane decides, away from it
        const Plane& P = domain_.planes[facet];
        const double s = P.signed_distance(p);
        if (std::abs(s) > round_off_band(P, p, s_.grid.side)) return s < 0;
      }
      // Parity of crossings from the cube's reference point; only the cube's triangles can
      // cross the segment, which stays in the cube.
      const Reference& ref = boundary_ref_[slot];
      bool in;
      if (domain_.locator->side_from(ref.p, ref.inside, p, cutting_planes(slot), in)) return in;
      return domain_.locator->inside(p);  // a degenerate crossing: ask the whole surface
    }
    for (int32_t id : cutting_planes(slot))
      if (domain_.planes[id].signed_distance(p) > 0) return false;
    return true;
  }

  // classify_box for a sub-cube of the boundary cube in `slot`. When it is cut (0), `plane`
  // receives a facet plane whose inner side holds the domain's part of the sub-cube, or -1: for
  // a convex domain any plane that cuts it; otherwise the plane of the triangles that meet it, if
  // they all lie in one (then they span the plane's section of the sub-cube:
  // common/facet_planes.hpp).
  int classify_sub_box(Vec3 lo, double h, size_t slot, int32_t& plane) const;

  // Non-convex domains: -1, 0 or 1 as classify_box, by which of `candidates` meet the box
  // (`cut` receives them). None means the box is on one side of the surface: that of its centre,
  // by parity from `ref` (a point of known side whose segment to the centre only candidates can
  // cross), or by the whole surface.
  struct Reference { Vec3 p; bool inside; };
  int classify_box_by_surface(Vec3 lo, double h, std::span<const int32_t> candidates, std::vector<int32_t>* cut,
                              const Reference* ref) const;

  // A point near `p` off the surface, and its side.
  Reference reference_near(Vec3 p, double h) const;

  // The base cubes of the box of n^3 cubes from (i0, j0, k0) (n a power of two), which `cut`
  // meets and of which `ref` is a point of known side, for a non-convex domain: each octant is
  // tested against the triangles that meet the box, then either taken whole (inside), dropped
  // (outside) or split again, down to single cubes, which get their triangles and a reference
  // point for inside tests (their centre).
  void classify_cut_octants(int i0, int j0, int k0, int n, const std::vector<int32_t>& cut, const Reference& ref,
                            std::vector<ActiveCube>& cubes, std::vector<std::pair<uint32_t, int32_t>>& cuts,
                            std::vector<std::pair<uint32_t, Reference>>& refs) const;

  // Base cubes not outside the domain, and for those cut by the boundary the planes (convex
  // domain) or triangles that cut them. Blocks of 8^3 cubes are classified first (and a cut
  // block's octants in turn, for triangles), so a cube is tested only against the few that cut
  // its block.
  ActiveCubes initial_cubes();

  // A round's candidates, per part of the active cubes: the darts no seed rejects.
  struct Darts {
    std::vector<std::vector<Candidate>> parts;
    size_t thrown = 0;
  };

  // Throws round `round`'s darts into active cube c of `level` (low corner lo, side h; slot_of()
  // gives its boundary slot) and appends to `out` those inside the domain that `near_seed(p)`
  // does not reject; returns how many it threw. A cube's darts depend only on its place, level
  // and round, so whoever throws them throws the same ones.
  template <class Slot, class NearSeed>
  int throw_darts(const ActiveCube& c, int level, int round, Vec3 lo, double h, Slot slot_of, const Poisson& poisson,
                  NearSeed near_seed, std::vector<Candidate>& out) const {
    const uint64_t c1 = (uint64_t(c.sx) << 32) | c.sy;
    const uint64_t tag = (uint64_t(c.sz()) << 32) | (uint64_t(level) << 24) | (uint64_t(round) << 12);
    const int n = poisson(CounterRng::unit(rng_.words(uint64_t(c.base), c1, tag, 0)[0]));
    if (n == 0) return 0;
    const size_t slot = c.inside() ? 0 : slot_of();
    for (int k = 0; k < n; ++k) {
      auto w = rng_.words(uint64_t(c.base), c1, tag | uint64_t(k + 1), 0);
      Vec3 p = lo + Vec3{CounterRng::unit(w[0]) * h, CounterRng::unit(w[1]) * h, CounterRng::unit(w[2]) * h};
      if (!c.inside() && !inside_domain(p, slot)) continue;
      if (near_seed(p)) continue;
      out.push_back({w[3], c.base, p});
    }
    return n;
  }

  static Poisson darts_per_cube(int level, int round) {
    return Poisson(level == 0 ? kDartsPerCubeLevel0Rounds[size_t(round)] : kDartsPerCubePerRound);
  }

  Darts throw_round(const ActiveCubes& active, int level, int round) const;

  // Accepts a round's candidates that no earlier one of the round rules out, as new seeds.
  void accept_round(Darts& round);

  static bool by_arrival(const Candidate& a, const Candidate& b) {
    return a.time != b.time ? a.time < b.time : a.base < b.base;
  }

  // One round's candidates. In a partitioned run they are in arrival order and include the
  // neighbours' candidates within r of this slab (`source`: 0 own, 1 from the rank below, 2 from
  // above), with the positions of the candidates whose decisions the ranks trade.
  struct Round {
    std::vector<Candidate> all;
    std::vector<uint8_t> source;
    std::vector<uint32_t> send_lower, send_upper, from_lower, from_upper;
  };

  // Candidates within r of the slab's faces go to the neighbour on that side: a candidate
  // conflicts only with others within r, and r spans fewer than kSamplingHaloLayers layers.
  void add_neighbours_candidates(Round& rs);

  // Interleaved bits of a base cube's coordinates (i in bits 0, 3, 6, ..., j in 1, 4, ..., k in
  // 2, 5, ...; 21 bits each), spread by masks instead of a loop over the bits (the loop was half
  // of the serial numbering of a round's new seeds).
  static uint64_t spread_bits(uint64_t x) {
    x &= 0x1FFFFF;
    x = (x | x << 32) & 0x1F00000000FFFFull;
    x = (x | x << 16) & 0x1F0000FF0000FFull;
    x = (x | x << 8) & 0x100F00F00F00F00Full;
    x = (x | x << 4) & 0x10C30C30C30C30C3ull;
    x = (x | x << 2) & 0x1249249249249249ull;
    return x;
  }
  uint64_t morton(int64_t b) const {
    int i, j, k;
    s_.grid.coords(b, i, j, k);
    return spread_bits(uint64_t(i)) | spread_bits(uint64_t(j)) << 1 | spread_bits(uint64_t(k)) << 2;
  }

  // Greedy in arrival order, computed in parallel: a candidate is accepted iff no earlier
  // candidate of the round that conflicts with it (within r, or in the same base cube) is
  // accepted. Each pass decides every candidate whose earlier conflicting candidates are all
  // decided; decisions are final, so the result is the sequential greedy one whatever the
  // threads or their timing, and whatever the order of `all`. In a partitioned run a rank
  // decides its own candidates only; after it can go no further the ranks trade the decisions
  // near their shared faces, until no rank has an undecided candidate. The earliest undecided
  // candidate anywhere is always decidable, so this ends, with the serial decisions.
  std::vector<uint8_t> accept_in_arrival_order(const Round& rs);

  // Splits every active cube into 8 and keeps the children that are neither covered (by one
  // ball, or from kFirstExactCoverageLevel on provably by two or three) nor outside the domain.
  // From kFirstFusedDartLevel on it also throws the next level's first round into them, into
  // `next_darts`.
  ActiveCubes refine(const ActiveCubes& active, int level, std::optional<Darts>& next_darts);

  // Protection seeds first (paper §2.2); the free seeds then keep r from them like from each other.
  void protect();

  void order_seeds_by_cube();

  const Domain& domain_;
  // Boundary base cubes (sorted) and, for each, the domain planes that cut it.
  std::vector<uint32_t> boundary_base_, boundary_begin_;
  std::vector<int32_t> boundary_planes_;
  std::vector<Reference> boundary_ref_;  // non-convex domains: per boundary cube
  // Non-convex domains, per boundary cube: the facet plane of all the triangles that meet it,
  // or -1; the plane alone then tells a sub-cube's or a dart's side (common/facet_planes.hpp).
  std::vector<int32_t> boundary_facet_;
  // Per window cube, its grandchildren in one seed's ball, from the first marked_seeds_ seeds
  // (levels 0 and 1; mark_grandchildren_in_one_ball).
  GrandchildMarks grandchild_marks_;
  bool use_marks_ = false;  // the marks' blocks hold at most 5 times the initial active cubes
  size_t marked_seeds_ = 0;
  size_t initial_active_ = 0;  // base cubes not outside the domain (in this sampler's slab)
  std::function<void(double)> progress_;
  double r_, r2_;
  uint64_t seed_;
  CounterRng rng_;
  Sample s_;
  std::vector<int64_t> stencil_offsets_;  // stencil() as offsets of base cube indices
  SamplingPartition* partition_;    // null: the whole grid on this process
  int owned_begin_, owned_end_;     // the z layers whose cubes this sampler throws darts into
};

}  // namespace froth::mps

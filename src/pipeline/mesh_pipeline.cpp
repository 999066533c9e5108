// The pipeline of one mesh: sample, cut cells, assemble, check. Each stage reports its time
// and counts into the RunReport.
#include <malloc.h>
#include <omp.h>

#include <chrono>
#include <cmath>
#include <unordered_map>
#include <fstream>
#include <map>
#include <string>

#include <fmt/format.h>

#include "common/face_scratch.hpp"
#include "froth/error.hpp"
#include "froth/mesh.hpp"
#include "froth/quality.hpp"
#include "froth/validate.hpp"
#include "froth/weld.hpp"
#include "convex/convex_split.hpp"
#include "features/feature_size.hpp"
#include "sampling/graded_mps.hpp"
#include "sampling/sizing.hpp"
#include "pipeline/border_patches.hpp"
#include "pipeline/partition.hpp"
#include "input/cracked_domain.hpp"
#include "sampling/mps.hpp"
#include "assembly/tessellation.hpp"

namespace froth {

namespace {

// MeshOptions::interrupted asked, and the run stopped if it says so.
void stop_if_interrupted(const MeshOptions& opt) {
  if (opt.interrupted && opt.interrupted()) fail(ErrorKind::Interrupted, "interrupted");
}

// A stage begins: told to the caller, who may stop the run there.
void stage_starts(const MeshOptions& opt, const char* stage) {
  if (opt.progress) opt.progress(stage, 0);
  stop_if_interrupted(opt);
}

// A stage's progress as the samplers and the tessellation report it (a fraction done), or none;
// the run may be stopped there too (the tessellation carries the error out of its threads).
std::function<void(double)> progress_of(const MeshOptions& opt, const char* stage) {
  if (!opt.progress && !opt.interrupted) return {};
  return [&opt, stage](double fraction) {
    if (opt.progress) opt.progress(stage, fraction);
    stop_if_interrupted(opt);
  };
}

// Hands memory the allocator holds free back to the system (glibc keeps large freed work lists
// mapped otherwise). Not under AddressSanitizer: its allocator does not use glibc's arenas, and
// malloc_trim from a rank running as a thread (the partition tests) breaks glibc's arena
// bookkeeping there ("malloc assertion failure in __malloc_arena_thread_freeres" at thread exit).
void release_freed_memory() {
#ifndef __SANITIZE_ADDRESS__
  malloc_trim(0);
#endif
}

class Stopwatch {
 public:
  double lap() {
    auto now = std::chrono::steady_clock::now();
    double s = std::chrono::duration<double>(now - t_).count();
    t_ = now;
    return s;
  }

 private:
  std::chrono::steady_clock::time_point t_ = std::chrono::steady_clock::now();
};

// Checks the options and fills the report's description of the run.
// `share`: the part of the mesh this process holds (a partitioned run's rank: 1 / ranks).
void start_run(const Domain& domain, const MeshOptions& opt, RunReport& run, double share = 1) {
  check_mesh_options(domain, opt, share);
  if (opt.threads > 0) omp_set_num_threads(opt.threads);
  run.domain = domain.description;
  run.r = opt.r;
  run.seed = opt.seed;
  run.weld = *opt.weld;
  run.grade = opt.grade, run.min_r = opt.min_r, run.grading = opt.grading;
  run.threads = omp_get_max_threads();
  run.domain_volume = domain.volume;
  run.input = {domain.convex, domain.surface.triangles.size(), domain.shells, domain.cavities,
               domain.reoriented_triangles};
  run.surface_area = domain.surface_area;
  run.features = domain.features;
}

// The first cell of the k-th seed of a mesh (cell_count() for k = the number of seeds).
size_t first_cell_of_seed(const PolyMesh& mesh, size_t k) {
  if (mesh.piece.empty()) return k;
  for (size_t c = 0; c < mesh.cell_count(); ++c)
    if (mesh.piece[c] == 0 && k-- == 0) return c;
  return mesh.cell_count();
}

// Thin walls and narrow gaps of the input, up to r: reported (what r the part's features ask for).
// With grading, up to 2r: walls below 2r shrink h (sampling/sizing.hpp).
FeatureSize measure_features(const Domain& domain, const MeshOptions& opt, RunReport& run, Stopwatch& watch) {
  if (domain.cracks) return measure_features(domain.cracks->solid, opt, run, watch);  // (a sheet is no wall)
  if (domain.surface.triangles.empty()) return {};
  stage_starts(opt, "feature size");
  FeatureSize fs = measure_feature_size(domain, opt.grade ? 2 * opt.r : opt.r);
  run.feature_size = fs.report;
  for (auto* m : {&run.feature_size.thickness, &run.feature_size.gap}) m->where = m->where + domain.origin;
  run.stages.push_back({"feature size", watch.lap(), peak_rss_bytes()});
  return fs;
}

// The sizing field: uniform unless grading is asked for and a wall or gap needs it.
SizingField sizing_field(const Domain& domain, const FeatureSize& fs, const MeshOptions& opt, RunReport& run,
                         Stopwatch& watch) {
  if (!opt.grade || fs.thickness.empty()) return SizingField::uniform(opt.r);
  // A cut solid's walls are the solid's (measure_features): the field is fitted to it too. A
  // multi-region solid's regions are measured too: a layer thinner than 2r between two
  // interfaces needs h below it as a wall does, or its cells would reach across it.
  const Domain& measured = domain.cracks ? domain.cracks->solid : domain;
  std::vector<FeatureSize> region_fs;
  std::vector<SizingField::Measured> regions;
  if (measured.regions) {
    region_fs.reserve(measured.regions->size());
    for (const Domain& solid : measured.regions->solids) region_fs.push_back(measure_feature_size(solid, 2 * opt.r));
    for (size_t k = 0; k < region_fs.size(); ++k) regions.push_back({&measured.regions->solids[k], &region_fs[k]});
  }
  SizingField h = SizingField::from_feature_size(measured, fs, opt.r, {opt.min_r, opt.grading}, regions);
  run.sizing = {!h.is_uniform(), h.min_r(), h.grading(), h.lipschitz(), h.smallest(), h.graded_fraction,
                h.cell_ratio,         h.floor_raised};
  run.stages.push_back({"sizing", watch.lap(), peak_rss_bytes()});
  return h;
}

// Cell data radius: h at each seed (left empty, r for all, when nothing is graded); and which
// cells have h < r at themselves or a neighbour, fixed before welding removes any face. Then the
// radius a protection seed states is what holds: reflex corners and the ends of short reflex
// curves can lie closer than r_e = h / sqrt(2) (tessellation noise makes such curves), so a
// protection seed's radius is min(h, sqrt(2) d) for d its distance to the nearest other one
// (2 d where either is an interface curve's, sampled at r/2; free seeds keep h from every seed).
// Returns how many of the seeds of cells [begin, end) were so reduced, and the smallest reduced
// radius over h in `smallest`.
size_t set_radii(PolyMesh& mesh, const SizingField& sizing, double r, size_t begin, size_t end, double& smallest) {
  if (!sizing.is_uniform()) {
    mesh.radii.resize(mesh.cell_count());
    for (size_t c = 0; c < mesh.cell_count(); ++c) mesh.radii[c] = sizing.at(mesh.seeds[c]);
    std::vector<uint8_t> near(mesh.cell_count());
    for (size_t c = 0; c < mesh.cell_count(); ++c) near[c] = graded_near(mesh, c);
    mesh.near_graded = std::move(near);
  }
  auto protection = [&](size_t c) {
    const CellKind k = mesh.kinds[c];
    return mesh.piece_of(c) == 0 && (k == CellKind::Edge || k == CellKind::Vertex || k == CellKind::InterfaceFace ||
                                     k == CellKind::InterfaceEdge);
  };
  // Protection seeds in cubes of side r / sqrt(2): a nearer one that matters is in the 27 around.
  const double side = r / std::sqrt(2.0);
  std::unordered_map<uint64_t, std::vector<uint32_t>> cubes;
  auto key = [&](int64_t i, int64_t j, int64_t k) { return (uint64_t(i) * 73856093u) ^ (uint64_t(j) * 19349663u) ^ (uint64_t(k) * 83492791u); };
  auto cube_of = [&](Vec3 p, int64_t& i, int64_t& j, int64_t& k) {
    i = int64_t(std::floor(p.x / side)), j = int64_t(std::floor(p.y / side)), k = int64_t(std::floor(p.z / side));
  };
  std::vector<uint32_t> cells;
  for (size_t c = 0; c < mesh.cell_count(); ++c)
    if (protection(c)) {
      int64_t i, j, k;
      cube_of(mesh.seeds[c] - mesh.seeds[0], i, j, k);
      cubes[key(i, j, k)].push_back(uint32_t(c));
      cells.push_back(uint32_t(c));
    }
  std::vector<std::pair<uint32_t, double>> reduced;
  for (uint32_t c : cells) {
    const Vec3 x = mesh.seeds[c];
    int64_t i, j, k;
    cube_of(x - mesh.seeds[0], i, j, k);
    double d2 = INFINITY;
    for (int64_t a = -1; a <= 1; ++a)
      for (int64_t b = -1; b <= 1; ++b)
        for (int64_t e = -1; e <= 1; ++e) {
          const auto it = cubes.find(key(i + a, j + b, k + e));
          if (it == cubes.end()) continue;
          for (uint32_t o : it->second) {
            // Interface curves are sampled at r/2 (sampling/protect_interfaces.hpp), the rest at r_e.
            const bool curve = mesh.kinds[c] == CellKind::InterfaceEdge || mesh.kinds[o] == CellKind::InterfaceEdge;
            if (o != c) d2 = std::min(d2, (curve ? 4 : 2) * norm2(mesh.seeds[o] - x));
          }
        }
    const double h = mesh.radius_of(c, r), held = std::sqrt(d2);
    if (held < h) reduced.push_back({c, held});
  }
  size_t count = 0;
  smallest = 1;
  if (reduced.empty()) return 0;
  if (mesh.radii.empty()) {
    mesh.radii.assign(mesh.cell_count(), r);
    mesh.near_graded.assign(mesh.cell_count(), 0);  // the bounds are judged as without the reduction
  }
  for (auto [c, held] : reduced) {
    if (c >= begin && c < end) ++count, smallest = std::min(smallest, held / mesh.radii[c]);
    for (size_t q = c; q < mesh.cell_count() && mesh.seeds[q] == mesh.seeds[c]; ++q) mesh.radii[q] = held;
  }
  return count;
}

// A piece of a cell smaller than a cube of 4 weld tolerances could collapse under welding: it
// stays with its seed's piece instead of becoming a cell.
double min_piece_volume(const MeshOptions& opt) { return std::pow(4 * *opt.weld, 3); }

void check_sample(size_t seeds, size_t uncovered_cubes, double r) {
  if (seeds == 0) fail(ErrorKind::Usage, fmt::format("r = {} leaves no seed in the domain", r));
  if (uncovered_cubes > 0)
    fail(ErrorKind::Internal, fmt::format("sampling stopped at the finest level with {} uncovered cubes", uncovered_cubes));
}

// Star-shapedness of cells [begin, end) before welding (non-convex domains).
void measure_star_shape(const Domain& domain, const PolyMesh& mesh, const MeshOptions& opt, RunReport& run,
                        size_t begin, size_t end) {
  if (domain.convex && !domain.regions) return;  // (a convex union of regions splits cells at interfaces)
  // Protected reflex edges keep cells star-shaped; a concave curved surface's flat reflex
  // edges do not (README, "Non-convex domains"): measured here, before welding.
  const StarShape star = star_shape(mesh, 1e-6 * opt.r, begin, end);
  run.not_star_shaped = star.cells_not;
  run.without_kernel = star.cells_without_kernel;
  run.star_violation = star.worst / opt.r;
}

// What welding changed, for the quality report's figures before welding: the cells it
// changed and their verdicts before.
struct WeldedCells {
  std::vector<size_t> cells;
  std::vector<CellVerdict> before;
};

WeldedCells weld_stage(PolyMesh& mesh, const MeshOptions& opt, RunReport& run, Stopwatch& watch) {
  WeldedCells welded;
  if (!(*opt.weld > 0)) {
    // (--convex cuts by interface planes too, and splits a crack face's twin with it)
    if (!opt.convex) scratch_of(mesh).face_interface_facet.clear(), scratch_of(mesh).point_twins.clear();
    return welded;
  }
  stage_starts(opt, "welding");
  // The paper's bounds speak of the mesh before welding. Welding changes few cells: their
  // metrics are taken before it, and the other cells' are the same before and after.
  auto measure_before = [&](const std::vector<size_t>& cells) {
    if (!opt.quality) return;
    welded.cells = cells;
    welded.before.resize(cells.size());
#pragma omp parallel for schedule(dynamic, 64)
    for (size_t i = 0; i < cells.size(); ++i) welded.before[i] = cell_verdict(mesh, cells[i]);
  };
  run.welding = std::make_shared<const WeldStats>(weld_mesh(mesh, *opt.weld, opt.r, measure_before));
  scratch_of(mesh).face_interface_facet.clear();  // their one reader was welding
  scratch_of(mesh).point_twins.clear();
  run.stages.push_back({"welding", watch.lap(), peak_rss_bytes()});
  return welded;
}

// A multi-region mesh's figures per region and interface (sums in cell order: the same for any
// thread count).
void measure_regions(const RegionSet& set, const PolyMesh& mesh, RunReport& run) {
  run.regions.assign(set.size(), {});
  for (size_t k = 0; k < set.size(); ++k) run.regions[k].name = set.names[k], run.regions[k].enclosed = set.solids[k].volume;
  for (size_t c = 0; c < mesh.cell_count(); ++c) {
    RunReport::Region& r = run.regions[size_t(mesh.region_of(c))];
    ++r.cells, r.volume += mesh.volumes[c];
  }
  run.interfaces.clear();
  std::map<std::pair<int32_t, int32_t>, size_t> index;
  for (const RegionSet::Interface& i : set.interfaces) {
    index[{i.a, i.b}] = run.interfaces.size();
    run.interfaces.push_back({i.a, i.b, i.area, 0, 0});
  }
  for (size_t c = 0; c < mesh.cell_count(); ++c)
    for (int64_t f = mesh.cell_face_begin[c]; f < mesh.cell_face_begin[c + 1]; ++f) {
      const int32_t g = mesh.face_generator[f];
      if (g < 0 || is_other_piece_generator(g)) continue;
      const int32_t a = mesh.region_of(c), b = mesh.region_of(size_t(g));
      if (a == b) continue;
      const auto it = index.find({std::min(a, b), std::max(a, b)});
      if (it == index.end()) continue;  // (regions that touch only where no interface was found: checked by tests)
      RunReport::Interface& i = run.interfaces[it->second];
      (a == i.a ? i.from_a : i.from_b) += face_area(mesh, f);
    }
}

// A cut solid's crack faces per sheet and side (sums in face order: the same for any thread count).
void measure_cracks(const CrackSet& set, const PolyMesh& mesh, RunReport& run) {
  run.cracks.clear();
  std::vector<std::pair<size_t, int>> of_patch(mesh.patch_names.size(), {0, -1});  // patch -> (sheet, side)
  for (size_t k = 0; k < set.sheets.size(); ++k) {
    const CrackSheet& c = set.sheets[k];
    run.cracks.push_back({c.name, c.input_area, c.area, c.front_length, 0, 0, 0, 0, !std::isnan(c.clipped_at.x)});
    for (int side = 0; side < 2; ++side) of_patch[size_t(set.patches[k][size_t(side)])] = {k, side};
  }
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    if (!is_border_generator(mesh.face_generator[f])) continue;
    const auto [k, side] = of_patch[size_t(mesh.patch_of(f))];
    if (side < 0) continue;
    RunReport::Crack& c = run.cracks[k];
    (side == 0 ? c.from_a : c.from_b) += face_area(mesh, f);
    ++(side == 0 ? c.faces_a : c.faces_b);
  }
  // The points of side b's faces, by sheet: a side-a face on them only lies on the front.
  std::vector<int32_t> on_side_b(mesh.points.size(), -1);
  for (int pass = 0; pass < 2; ++pass)
    for (size_t f = 0; f < mesh.face_count(); ++f) {
      if (!is_border_generator(mesh.face_generator[f])) continue;
      const auto [k, side] = of_patch[size_t(mesh.patch_of(f))];
      if (side != 1 - pass) continue;
      bool all = true;
      for (int64_t v = mesh.face_vertex_begin[f]; v < mesh.face_vertex_begin[f + 1]; ++v) {
        int32_t& mark = on_side_b[size_t(mesh.face_vertices[size_t(v)])];
        if (pass == 0) mark = int32_t(k);
        all = all && mark == int32_t(k);
      }
      if (pass == 1) run.cracks[k].faces_on_front += all;
    }
}

// Volumes, structural checks, quality and counts of the finished mesh (or piece).
void finish_mesh(const Domain& domain, PolyMesh& mesh, const MeshOptions& opt, RunReport& run, const WeldedCells& welded, Stopwatch& watch) {
  stage_starts(opt, "validation");
  mesh.volumes.resize(mesh.cell_count());
#pragma omp parallel for schedule(static)
  for (size_t c = 0; c < mesh.cell_count(); ++c) mesh.volumes[c] = cell_volume(mesh, c);
  // Where cells may not hold their seed in their kernel (non-convex domains, and the parts of a
  // seed's cell in other regions than its seed's, even where the regions' union is convex), the
  // point to fan each from.
  if (!domain.convex || domain.regions) mesh.centers = fan_centers(mesh, 1e-6 * opt.r);
  run.without_center = 0;
  for (size_t c = 0; c < mesh.centers.size(); ++c) run.without_center += !mesh.has_kernel(c);
  assign_border_patches(domain.regions ? domain.regions->boundary : domain, mesh);
  MeshCheck check = check_mesh(mesh);
  run.stages.push_back({"validation", watch.lap(), peak_rss_bytes()});
  if (!check.ok())
    fail(ErrorKind::Internal, fmt::format("the mesh failed its checks ({} unmatched faces, {} open cells, {} "
                                          "non-positive cells); first: {}",
                                          check.unmatched_faces, check.open_cells, check.nonpositive_cells,
                                          check.first_problem));

  if (opt.quality) {
    stage_starts(opt, "quality");
    run.quality = std::make_shared<const QualityReport>(assess_quality(mesh, &mesh.quality));
    if (run.welding) {
      // Bounds before welding: the counts after, with the welded cells' verdicts swapped back;
      // and how far welding moved those cells' figures.
      QualityReport before = *run.quality;
      for (size_t i = 0; i < welded.cells.size(); ++i) {
        const CellVerdict after = cell_verdict(mesh, welded.cells[i]);
        const CellVerdict& was = welded.before[i];
        // (The radii do not change with welding, so neither does a cell's gradedness.)
        uint64_t* counts[3] = {&before.theorem1_violations, &before.lemma6_interior_violations,
                               &before.lemma6_border_violations};
        if (was.graded)
          counts[0] = &before.graded_outside.theorem1, counts[1] = &before.graded_outside.lemma6_interior,
          counts[2] = &before.graded_outside.lemma6_border;
        *counts[0] += uint64_t(was.theorem1) - uint64_t(after.theorem1);
        *counts[1] += uint64_t(was.lemma6_interior) - uint64_t(after.lemma6_interior);
        *counts[2] += uint64_t(was.lemma6_border) - uint64_t(after.lemma6_border);
        run.weld_aspect_shift = std::max(run.weld_aspect_shift, std::abs(after.q.aspect - was.q.aspect));
        run.weld_dihedral_shift =
            std::max({run.weld_dihedral_shift, std::abs(after.q.min_dihedral - was.q.min_dihedral),
                      std::abs(after.q.max_dihedral - was.q.max_dihedral)});
      }
      run.bounds_before_weld = std::make_shared<const QualityReport>(before);
    }
    run.stages.push_back({"quality", watch.lap(), peak_rss_bytes()});
  }

  run.cells = mesh.cell_count();
  run.faces = mesh.face_count();
  run.points = mesh.points.size();
  size_t* count_of[] = {&run.interior_cells, &run.fringe_cells,    &run.edge_cells,
                        &run.vertex_cells,   &run.interface_cells, &run.interface_cells};
  for (size_t* c : count_of) *c = 0;
  for (CellKind k : mesh.kinds) ++*count_of[size_t(k)];
  run.split_seeds = run.extra_pieces = 0;
  if (mesh.region.empty()) {
    for (size_t c = 0; c < mesh.cell_count(); ++c) {
      run.extra_pieces += mesh.piece_of(c) > 0;
      run.split_seeds += mesh.piece_of(c) == 1;
    }
  } else {
    // A seed's cell cut by an interface is one cell per region by design; only pieces within
    // one region are a wall or gap thinner than r.
    std::map<std::pair<std::array<double, 3>, int32_t>, uint32_t> pieces;
    for (size_t c = 0; c < mesh.cell_count(); ++c) {
      const uint32_t n = ++pieces[{{mesh.seeds[c].x, mesh.seeds[c].y, mesh.seeds[c].z}, mesh.region[c]}];
      run.extra_pieces += n > 1;
      run.split_seeds += n == 2;
    }
  }
  run.border_area = border_area(mesh);
  if (domain.regions) measure_regions(*domain.regions, mesh, run);
  if (domain.cracks) {
    measure_cracks(*domain.cracks, mesh, run);
    mesh.crack_names.clear();
    for (const CrackSheet& c : domain.cracks->sheets) mesh.crack_names.push_back(c.name);
  }
  // Summed in cell order so the figure is the same for any thread count.
  run.volume_sum = 0;
  for (double v : mesh.volumes) run.volume_sum += v;
  // Back into the input's coordinates, from the part's own (Domain::origin).
  if (const Vec3 o = domain.origin; o.x != 0 || o.y != 0 || o.z != 0) {
    for (Vec3& p : mesh.points) p = p + o;
    for (Vec3& p : mesh.seeds) p = p + o;
    for (Vec3& p : mesh.centers) p = p + o;  // NaN stays NaN
  }
}

// --convex: the quality of the pieces of split cells (cells whose parent became several).
void measure_pieces(const PolyMesh& mesh, RunReport::ConvexSplit& split) {
  if (mesh.quality.size() != mesh.cell_count() || mesh.parent.empty()) return;
  std::vector<uint32_t> count(mesh.cell_count(), 0);
  for (uint32_t p : mesh.parent) ++count[p];
  double sum = 0;
  size_t n = 0;
  split.piece_min_dihedral = 180;
  for (size_t c = 0; c < mesh.cell_count(); ++c) {
    if (count[mesh.parent[c]] < 2) continue;
    const CellQuality& q = mesh.quality[c];
    if (!std::isfinite(q.aspect)) {  // the inscribed ball's linear program found none
      ++split.pieces_without_ball;
      continue;
    }
    sum += q.aspect, ++n;
    split.piece_aspect_max = std::max(split.piece_aspect_max, q.aspect);
    split.piece_min_dihedral = std::min(split.piece_min_dihedral, q.min_dihedral);
  }
  split.piece_aspect_mean = n ? sum / double(n) : 0;
  if (n == 0) split.piece_min_dihedral = 0;
}

// The seeds whose cells this process builds: all of them, or a partitioned run's slab (its owned
// seeds and the ghost layers around them). Ranges index `sample.seeds`.
struct SeedWindow {
  Sample sample;
  SeedRange built, owned;
};

SeedWindow sample_seeds(const Domain& domain, const SizingField& sizing, const MeshOptions& opt, RunReport& run,
                        Communicator* comm, PartitionReport& part) {
  stage_starts(opt, "sampling");
  // The whole sample, or with a partition this rank's window of it.
  const auto sample = [&](SamplingPartition* sp) {
    return sizing.is_uniform() ? sample_maximal_poisson_disk(domain, opt.r, opt.seed, sp, progress_of(opt, "sampling"))
                               : sample_graded_poisson_disk(domain, sizing, opt.seed, sp, progress_of(opt, "sampling"));
  };
  if (!comm) {
    SeedWindow w{sample(nullptr), {}, {}};
    run.sampling = w.sample.stats;
    w.built = w.owned = {0, int32_t(w.sample.seeds.size())};
    return w;
  }
  SamplingPartition sp{part.slab, comm};
  const Sample sampled = sample(&sp);
  part.exchanges = sp.exchanges;
  CellWindow w = exchange_cell_halo(sampled, part.slab, *comm);
  run.sampling = w.sample.stats;
  run.sampling.darts = comm->sum(run.sampling.darts);
  run.sampling.uncovered_cubes = comm->sum(run.sampling.uncovered_cubes);
  // Counts over all ranks (protection seeds are computed whole on every rank).
  run.sampling.seeds = w.total_seeds;
  part.first_seed = w.first_global + w.owned.begin;
  part.owned_seeds = size_t(w.owned.end - w.owned.begin);
  part.ghost_seeds = w.sample.seeds.size() - part.owned_seeds;
  part.ghost_cells = size_t(w.built.end - w.built.begin) - part.owned_seeds;
  return {std::move(w.sample), w.built, w.owned};
}

// A partitioned run's cells welded with their ghost ring: every cell at a point within
// (kGhostCellLayers side - r) of the slab is built (Lemma 1: a point's cells have seeds within r
// of it), so every edge there is seen. Owned vertices lie within r of the slab; a weld cluster
// moves its vertices to one point, so its diameter is at most twice the largest displacement,
// and a cluster at an owned vertex stays in that zone while it is below the slack. Every rank
// decides on the largest displacement of all, so they stop together. Then the ghosts go.
PolyMesh owned_cells(PolyMesh& ring, size_t own_begin, size_t own_end, const MeshOptions& opt, const RunReport& run,
                     Communicator& comm, PartitionReport& part, WeldedCells& welded) {
  const double slack = kGhostCellLayers * opt.r / std::sqrt(3.0) - 2 * opt.r;
  const double moved = comm.max(run.welding ? run.welding->max_displacement : 0);
  if (2 * moved >= slack)
    fail(ErrorKind::Usage, fmt::format("a partitioned run: welding moved a vertex by {:.3g} = {:.3g} r, more than the ghost "
                                       "cells around a slab can vouch for ({:.3g} r): use a smaller weld tolerance",
                                       moved, moved / opt.r, slack / 2 / opt.r));
  PolyMesh mesh = extract_cells(ring, own_begin, own_end, part.partition_faces);
  ring = PolyMesh();
  WeldedCells owned;
  for (size_t k = 0; k < welded.cells.size(); ++k)
    if (welded.cells[k] >= own_begin && welded.cells[k] < own_end) {
      owned.cells.push_back(welded.cells[k] - own_begin);
      owned.before.push_back(welded.before[k]);
    }
  welded = std::move(owned);
  return mesh;
}

// The one recipe of a mesh, whole (comm null) or a partitioned run's piece.
PolyMesh run_pipeline(const Domain& domain, const MeshOptions& given, RunReport& run, Communicator* comm,
                      PartitionReport& part) {
  run.cells_requested = given.cells;
  // `cells` is turned into r through one sample: part of the run the user waits for.
  Stopwatch choosing;
  const MeshOptions opt = resolve_options(domain, given, true, comm);
  const double choosing_seconds = given.cells != 0 ? choosing.lap() : 0;
  auto count_choosing = [&] {
    if (choosing_seconds == 0) return;
    run.stages.insert(run.stages.begin(), {"choosing r", choosing_seconds, peak_rss_bytes()});
    run.total_seconds += choosing_seconds;
  };
  // A crack front inside the solid: the sheets are cut in again with their skirts, whose width
  // follows r (input/cracked_domain.hpp); the r chosen for `cells` is kept.
  if (const CrackSet* cracks = domain.cracks.get(); cracks && cracks->fronts && cracks->skirt_r != opt.r) {
    MeshOptions at_r = given;
    at_r.r = opt.r, at_r.cells = 0;
    const Domain cut = cut_along_cracks(cracks->solid, cracks->sheets, opt.r);
    PolyMesh mesh = run_pipeline(cut, at_r, run, comm, part);
    run.cells_requested = given.cells;
    count_choosing();
    return mesh;
  }
  if (comm && opt.convex)
    fail(ErrorKind::Usage, "convex cells are not available in a partitioned run: a cut carries into cells on other ranks");
  start_run(domain, opt, run, comm ? 1.0 / comm->size() : 1.0);
  Stopwatch total, watch;
  const FeatureSize fs = measure_features(domain, opt, run, watch);
  const SizingField sizing = sizing_field(domain, fs, opt, run, watch);
  if (comm) {
    part.rank = comm->rank();
    part.ranks = comm->size();
    part.slab = slab_of(part.rank, part.ranks, BackgroundGrid::covering(domain.bounds, opt.r).nz);
  }
  SeedWindow seeds = sample_seeds(domain, sizing, opt, run, comm, part);
  run.stages.push_back({"sampling", watch.lap(), peak_rss_bytes()});
  release_freed_memory();  // the sampler's freed work lists, before the cells' peak
  check_sample(run.sampling.seeds, run.sampling.uncovered_cubes, opt.r);

  // A partitioned run builds its cells and the ring of ghost cells around them, welded together
  // so that every short edge at an owned vertex is seen; the ghost cells are dropped after.
  stage_starts(opt, "cells");
  TessellationTimes tt;
  PolyMesh mesh = build_voronoi_mesh(domain, std::move(seeds.sample), opt.r, &tt, seeds.built, min_piece_volume(opt),
                                     progress_of(opt, "cells"));
  mesh.random_seed = opt.seed;
  // The owned seeds' cells, pieces included (a seed's pieces follow it).
  const size_t own_begin = first_cell_of_seed(mesh, size_t(seeds.owned.begin - seeds.built.begin)),
               own_end = first_cell_of_seed(mesh, size_t(seeds.owned.end - seeds.built.begin));
  SoloCommunicator solo;
  Communicator& all = comm ? *comm : solo;
  double smallest = 1;
  run.sampling.protection_radius_reduced = all.sum(set_radii(mesh, sizing, opt.r, own_begin, own_end, smallest));
  run.sampling.smallest_protection_radius = -all.max(-smallest);
  run.stages.push_back({"cells", tt.cells, tt.cells_peak_rss});
  run.stages.push_back({"assembly", tt.assembly, peak_rss_bytes()});
  run.recut_cells = all.sum(tt.recut_cells);  // with each rank's ghost ring, as welding counts
  measure_star_shape(domain, mesh, opt, run, own_begin, own_end);
  watch.lap();

  WeldedCells welded = weld_stage(mesh, opt, run, watch);
  if (comm) mesh = owned_cells(mesh, own_begin, own_end, opt, run, *comm, part, welded);
  if (opt.convex) {
    stage_starts(opt, "convex");
    run.convex_split = split_nonconvex_cells(mesh, domain.regions ? domain.regions->boundary.planes : domain.planes, opt.r);
    run.stages.push_back({"convex", watch.lap(), peak_rss_bytes()});
  }
  mesh.scratch.reset();
  finish_mesh(domain, mesh, opt, run, welded, watch);
  if (opt.convex) measure_pieces(mesh, run.convex_split);
  run.total_seconds = total.lap();
  count_choosing();
  run.peak_rss_bytes = peak_rss_bytes();
  return mesh;
}

}  // namespace

PolyMesh generate_mesh(const Domain& domain, const MeshOptions& given, RunReport* report) {
  RunReport local;
  PartitionReport unused;
  return run_pipeline(domain, given, report ? *report : local, nullptr, unused);
}

PolyMesh generate_mesh_piece(const Domain& domain, const MeshOptions& given, Communicator& comm, RunReport* report,
                             PartitionReport* partition) {
  RunReport local_run;
  PartitionReport local_part;
  return run_pipeline(domain, given, report ? *report : local_run, &comm, partition ? *partition : local_part);
}

}  // namespace froth

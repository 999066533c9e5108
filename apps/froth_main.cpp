// froth command line. Exit codes: 0 success, 2 usage, 3 invalid input, 4 I/O failure,
// 5 internal error.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>

#include <omp.h>
#ifdef FROTH_MPI
#include <mpi.h>
#endif

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "cli_guards.hpp"
#include "communicators.hpp"
#include "froth/froth.hpp"

namespace {

struct MeshArgs {
  std::string input;
  double r = -INFINITY;  // -INFINITY: not given
  std::string seed_text = "0";
  uint64_t seed = 0;  // parsed from seed_text (cli_guards)
  std::string output;
  double weld = -1;  // default: froth::default_weld_tolerance
  int threads = 0;
  std::string report;
  bool no_quality = false;
  double feature_angle = froth::kDefaultFeatureAngle;
  bool repair = false;
  bool partition = false;
  bool grade = false;
  double min_r = 0, max_grading = 0.2;
  double max_memory_gb = 0;  // 0: the machine's available memory
  double cells = 0;           // --cells: choose r for about this many (0: -r given)
  bool dry_run = false;
};

std::string default_output(const std::string& input) {
  if (input.rfind("box:", 0) == 0) return "box.vtu";
  return std::filesystem::path(input).stem().string() + ".vtu";
}

// --weld: negative (unset) means the default, 1e-4 min(r, the domain's diagonal).
double weld_tolerance(double weld, double r, const froth::Domain& domain) {
  return weld < 0 ? froth::default_weld_tolerance(r, domain.bounds.diagonal()) : weld;
}

// "interior aspect ratio A to B (mean M)", or what stands for it when there is no interior cell
// (a domain thinner than r).
std::string interior_aspect_text(const froth::QualityReport& q) {
  const auto& in = q.aspect[0];
  if (q.cells[0] == 0) return "no interior cells";
  return fmt::format("interior aspect ratio {:.3f} to {:.3f} (mean {:.3f})", in.min, in.max, in.mean());
}

// The summary's sentences on features, welding and quality.
std::string details_sentence(const froth::RunReport& run) {
  const froth::FeatureSummary& f = run.features;
  const auto& input = run.input;
  std::string out = fmt::format(
      " Input: {} triangles, {} shell{} ({} cavit{}), {}{}.", input.triangles, input.shells, input.shells == 1 ? "" : "s",
      input.cavities, input.cavities == 1 ? "y" : "ies", input.convex ? "convex" : "non-convex: cells clipped to the surface",
      input.reoriented_triangles ? fmt::format("; --repair reoriented {} triangles", input.reoriented_triangles) : "");
  if (run.not_star_shaped > 0)
    out += fmt::format(" {} cells are not star-shaped from their seed (a face plane up to {:.3g} r beyond it): such cells "
                       "lie along concave curved surfaces, whose flat reflex edges are not protected, or where "
                       "features are closer than r.",
                       run.not_star_shaped, run.star_violation);
  if (run.without_kernel > 0)
    out += fmt::format(" {} of them are star-shaped from no point (empty kernel): they wrap around a feature thinner "
                       "than r; a smaller r avoids them.",
                       run.without_kernel);
  for (const auto& [what, m] : {std::pair{"walls", run.feature_size.thickness}, std::pair{"gaps", run.feature_size.gap}})
    if (std::isfinite(m.min))
      out += fmt::format(" {} narrower than {}r on {:.3g}% of the surface (narrowest {:.3g} = {:.3g} r, at ({:.4g}, "
                         "{:.4g}, {:.4g})).",
                         what, run.feature_size.cap > run.r ? "2" : "", 100 * m.area_below_cap, m.min, m.min / run.r,
                         m.where.x, m.where.y, m.where.z);
  if (run.sizing.graded)
    out += fmt::format(" Sizing graded to the walls and gaps: h from {:.3g} (= {:.3g} r, floor --min-r {:.3g}{}) to r, "
                       "slope at most {:.2g}; h < r on {:.3g}% of the volume, about {:.3g} times a uniform mesh's cells.",
                       run.sizing.smallest, run.sizing.smallest / run.r, run.sizing.min_r,
                       run.sizing.floor_raised ? ", raised from r/4 to keep the cells within budget" : "",
                       run.sizing.lipschitz, 100 * run.sizing.graded_fraction, run.sizing.cell_ratio);
  else if (run.sizing.floor_raised)
    out += " Sizing not graded: resolving the walls and gaps would cost more than the default budget of cells; give "
           "--min-r to grade anyway.";
  if (run.split_seeds > 0)
    out += fmt::format(" {} seeds saw the domain in several pieces (a wall or gap thinner than r): their pieces became "
                       "{} more cells (cell data piece > 0).",
                       run.split_seeds, run.extra_pieces);
  if (run.sampling.edge_seeds + run.sampling.vertex_seeds > 0)
    out += fmt::format(" Protection: {} vertex and {} edge seeds on the reflex edges (r_e = r/sqrt(2)).",
                       run.sampling.vertex_seeds, run.sampling.edge_seeds);
  out += fmt::format(
      " Features (over {} degrees): {} convex and {} reflex edges in {} curves, {} corners; {} flat edges ({} of them "
      "concave).",
      f.angle_degrees, f.convex_edges, f.reflex_edges, f.curves, f.corners, f.flat_edges, f.flat_reflex_edges);
  if (run.welding) {
    const froth::WeldStats& w = *run.welding;
    out += fmt::format(
        " Welding (w = {:.3g}): {} edges collapsed, {} faces removed, shortest edge {:.3g} -> {:.3g}, vertices moved "
        "at most {:.3g}, faces non-planar by at most {:.2g} r.",
        w.tolerance, w.edges_collapsed, w.faces_removed, w.shortest_edge_before, w.shortest_edge_after,
        w.max_displacement, w.max_nonplanarity);
  }
  if (!run.quality) return out;
  const froth::QualityReport& q = *run.quality;
  // The paper's bounds hold before welding.
  const froth::QualityReport& b = run.bounds_before_weld ? *run.bounds_before_weld : q;
  const auto& ii = q.dihedral[0];
  out += fmt::format(
      " Quality: {}, interior dihedrals {:.1f} to {:.1f} degrees, "
      "shortest edge {:.3g}; cells beyond the paper's bounds{}: {} (Theorem 1), {} and {} (Lemma 6).",
      interior_aspect_text(q), ii.min, ii.max, q.shortest_edge, run.bounds_before_weld ? " before welding" : "",
      b.theorem1_violations, b.lemma6_interior_violations, b.lemma6_border_violations);
  if (b.graded_cells > 0)
    out += fmt::format(" The bounds are judged where h = r; the {} cells with h < r at them or a neighbour are counted "
                       "apart: {}, {} and {} beyond them.",
                       b.graded_cells, b.graded_outside.theorem1, b.graded_outside.lemma6_interior,
                       b.graded_outside.lemma6_border);
  if (run.bounds_before_weld)
    out += fmt::format(" Welding moved aspect ratios by at most {:.2g} and dihedrals by at most {:.2g} degrees.",
                       run.weld_aspect_shift, run.weld_dihedral_shift);
  return out;
}

void print_summary(const froth::RunReport& run, const std::string& output, double write_seconds) {
  std::string times;
  for (const auto& st : run.stages) times += fmt::format("{} {:.3f} s, ", st.stage, st.seconds);
  fmt::print(
      "froth: meshed {} with r = {}{} and seed {}: {} cells ({} interior, {} fringe, {} edge, {} vertex) from {} seeds, "
      "{} faces, {} points; every interior face matched, every cell closed. Volume: cells sum {:.12g}, domain "
      "{:.12g} (relative error {:.2e}). Sampling: {} darts, {} refinement levels, maximal.{} Time: {}writing {:.3f} "
      "s; total {:.3f} s on {} threads; peak memory {:.1f} MiB. Wrote {}.\n",
      run.domain, run.r,
      run.cells_requested > 0 ? fmt::format(" (chosen for about {:.6g} cells)", run.cells_requested) : "", run.seed,
      run.cells, run.interior_cells, run.fringe_cells, run.edge_cells, run.vertex_cells,
      run.sampling.seeds, run.faces,
      run.points, run.volume_sum, run.domain_volume, run.volume_relative_error(), run.sampling.darts,
      run.sampling.levels, details_sentence(run), times, write_seconds, run.total_seconds + write_seconds,
      run.threads, run.peak_rss_bytes / 1048576.0, output);
}

// The options `froth mesh` runs with; progress on stderr if `tell` and it is a terminal.
froth::MeshOptions mesh_options(const MeshArgs& a, const froth::Domain& domain, bool tell) {
  froth::MeshOptions opt;
  opt.r = a.r;
  opt.seed = a.seed;
  opt.weld = weld_tolerance(a.weld, a.r, domain);
  opt.threads = a.threads;
  opt.quality = !a.no_quality;
  opt.grade = a.grade, opt.min_r = a.min_r, opt.grading = a.max_grading;
  opt.max_memory_bytes = a.max_memory_gb * 1e9;
  if (tell && isatty(STDERR_FILENO))
    opt.progress = [](const std::string& stage) { fmt::print(stderr, "froth: {}...\n", stage); };
  return opt;
}

// -r as given, or chosen for --cells (the summary says which).
MeshArgs with_radius(const MeshArgs& given, const froth::Domain& domain) {
  MeshArgs a = given;
  if (a.cells > 0) a.r = froth::radius_for_cells(domain, a.cells, a.seed, !a.dry_run);
  else if (a.r == -INFINITY) froth::fail(froth::ErrorKind::Usage, "give -r R (the sampling radius) or --cells N");
  return a;
}

// --dry-run: what the run would take, from the saturated density (froth::estimate_run) and the
// pipeline's time per cell on 2 threads (docs/performance.md: about 11 us for a box without the
// quality stage, twice that with it; non-convex parts up to twice again).
int dry_run(const MeshArgs& a, const froth::Domain& domain, const froth::MeshOptions& opt) {
  const froth::RunEstimate e = froth::estimate_run(domain, opt);
  const int threads = opt.threads > 0 ? opt.threads : omp_get_max_threads();
  const double seconds = e.cells * (opt.quality ? 22e-6 : 11e-6) * 2.0 / threads * (domain.convex ? 1 : 1.5);
  fmt::print("froth: dry run for {} with r = {:.6g}{}: about {:.3g} cells, {:.3g} GB at the peak, {:.2g} s on {} thread{} "
             "(rough: the density's estimate runs 3 to 25% above the cells sampling gives; --cells corrects r by a sample)\n",
             a.input, opt.r, a.cells > 0 ? fmt::format(" (chosen for --cells {:.6g})", a.cells) : "", e.cells,
             e.bytes / 1e9, seconds, threads, threads == 1 ? "" : "s");
  froth::check_mesh_options(domain, opt);
  return 0;
}

int run_mesh(const MeshArgs& given) {
  const std::string output = given.output.empty() ? default_output(given.input) : given.output;
  froth_cli::refuse_same_files({{"the input", given.input}, {"-o", output}, {"--report", given.report}});
  froth::Domain domain = froth::load_domain(given.input, {given.feature_angle, given.repair});
  const MeshArgs a = with_radius(given, domain);
  const froth::MeshOptions opt = mesh_options(a, domain, true);
  if (a.dry_run) return dry_run(a, domain, opt);
  froth::RunReport run;
  run.cells_requested = a.cells;
  froth::PolyMesh mesh = froth::generate_mesh(domain, opt, &run);
  auto t0 = std::chrono::steady_clock::now();
  if (opt.progress) opt.progress("writing");
  froth::OutputGroup outputs;  // the mesh and its report appear together, or neither
  froth::write_vtu(mesh, run, output);
  double write_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  run.stages.push_back({"writing", write_seconds, froth::peak_rss_bytes()});
  if (!a.report.empty()) froth::write_report_json(run, a.report);
  outputs.commit();
  run.stages.pop_back();
  print_summary(run, output, write_seconds);
  return 0;
}

// One mesh over all ranks (froth/partition.hpp): each rank writes its piece,
// OUT/OUT_<rank>.vtu beside OUT.pvtu, and rank 0 the .pvtu, the report and the summary once every
// piece is written. A rank that fails while the others wait for it aborts the run.
int run_mesh_partitioned(const MeshArgs& given, froth::Communicator& comm) {
  std::filesystem::path output = given.output.empty() ? default_output(given.input) : given.output;
  if (output.extension() == ".vtu") output.replace_extension(".pvtu");
  if (output.extension() != ".pvtu")
    froth::fail(froth::ErrorKind::Usage, fmt::format("--partition writes a .pvtu file, not {}", output.string()));
  froth::Domain domain = froth::load_domain(given.input, {given.feature_angle, given.repair});
  const MeshArgs a = with_radius(given, domain);
  const froth::MeshOptions opt = mesh_options(a, domain, comm.rank() == 0);
  froth::RunReport run;
  run.cells_requested = a.cells;
  froth::PartitionReport part;
  froth::PolyMesh piece = froth::generate_mesh_piece(domain, opt, comm, &run, &part);

  const std::string stem = output.stem().string();
  const std::filesystem::path dir = output.parent_path() / stem;
  const std::string relative = fmt::format("{}/{}_{}.vtu", stem, stem, comm.rank());
  auto t0 = std::chrono::steady_clock::now();
  if (opt.progress) opt.progress("writing");
  int code = 0;
  try {
    std::filesystem::create_directories(dir);
    froth::write_vtu(piece, run, output.parent_path() / relative);
  } catch (const froth::Error& e) {
    fmt::print(stderr, "froth: error (rank {}): {}\n", comm.rank(), e.what());
    code = e.exit_code();
  } catch (const std::filesystem::filesystem_error& e) {
    fmt::print(stderr, "froth: error (rank {}): cannot create {}: {}\n", comm.rank(), dir.string(), e.what());
    code = 4;
  }
  // Every piece is written (or every rank removes its own) before the .pvtu names them.
  code = int(comm.max(code));
  if (code != 0) {
    std::filesystem::remove(output.parent_path() / relative);
    return code;
  }
  const double write_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  run.stages.push_back({"writing", write_seconds, froth::peak_rss_bytes()});
  froth::PartitionSummary all = froth::combine_rank_reports(comm, run, part);
  if (comm.rank() != 0) return 0;
  std::vector<std::string> pieces;
  for (int k = 0; k < comm.size(); ++k) pieces.push_back(fmt::format("{}/{}_{}.vtu", stem, stem, k));
  try {
    froth::write_pvtu(pieces, opt.quality, output);
  } catch (const froth::Error&) {
    for (const std::string& p : pieces) std::filesystem::remove(output.parent_path() / p);  // no .pvtu, no pieces
    throw;
  }
  if (!a.report.empty()) froth::write_report_json(all.run, a.report, &all);
  all.run.stages.pop_back();
  print_summary(all.run, output.string(), write_seconds);
  size_t owned = 0, ghosts = 0, shared = 0, fewest = SIZE_MAX, most = 0;
  for (const auto& p : all.ranks) {
    owned += p.owned_seeds, ghosts += p.ghost_seeds, shared += p.partition_faces;
    fewest = std::min(fewest, p.owned_seeds), most = std::max(most, p.owned_seeds);
  }
  fmt::print("froth: partitioned over {} rank{} in slabs of z layers: {} to {} cells per rank, halo {} ghost seeds "
             "({:.3f} per owned seed), {} cell faces shared between ranks (each counted from both sides).\n",
             comm.size(), comm.size() == 1 ? "" : "s", fewest, most, ghosts, owned ? double(ghosts) / double(owned) : 0.0,
             shared);
  return 0;
}

// The MPI world when froth is built with -DFROTH_MPI=ON (one process otherwise).
struct World {
  int rank = 0, size = 1;
  // The largest of every rank's value (all ranks call it).
  int max(int v) const {
#ifdef FROTH_MPI
    int out = v;
    MPI_Allreduce(&v, &out, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    return out;
#else
    return v;
#endif
  }
  unsigned long long sum(unsigned long long v) const {
#ifdef FROTH_MPI
    unsigned long long out = v;
    MPI_Allreduce(&v, &out, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
    return out;
#else
    return v;
#endif
  }
};

struct EnsembleArgs {
  std::string input, dir;
  double r = 0, weld = -1;
  std::string seed_text = "0";
  uint64_t seed = 0;  // parsed from seed_text (cli_guards)
  size_t members = 0;
  int threads = 0;
  bool no_quality = false;
  double feature_angle = froth::kDefaultFeatureAngle;
  bool repair = false;
  bool grade = false;
  double min_r = 0, max_grading = 0.2;
  double max_memory_gb = 0;
};

// Members are spread over the ranks (member k on rank k % ranks); rank 0 writes the summary
// once every rank is done. A rank that fails makes every rank exit with its code.
int run_ensemble(const EnsembleArgs& a, const std::string& command, const World& world) {
  froth::EnsembleOptions opt;
  opt.input = a.input;
  opt.r = a.r;
  opt.seed = a.seed;
  opt.members = a.members;
  opt.quality = !a.no_quality;
  opt.grade = a.grade, opt.min_r = a.min_r, opt.grading = a.max_grading;
  opt.max_memory_bytes = a.max_memory_gb * 1e9;
  opt.threads = a.threads;
  opt.dir = a.dir;
  opt.command = command;
  opt.rank = world.rank;
  opt.ranks = world.size;
  if (isatty(STDERR_FILENO)) opt.progress = [](const std::string& s) { fmt::print(stderr, "froth: {}...\n", s); };
  const auto t0 = std::chrono::steady_clock::now();
  froth::EnsembleProgress done;
  int code = 0;
  try {
    froth::Domain domain = froth::load_domain(a.input, {a.feature_angle, a.repair});
    opt.weld = weld_tolerance(a.weld, a.r, domain);
    done = froth::build_members(domain, opt);
  } catch (const froth::Error& e) {
    fmt::print(stderr, "froth: error{}: {}\n", world.size > 1 ? fmt::format(" (rank {})", world.rank) : "", e.what());
    code = e.exit_code();
  }
  code = world.max(code);
  if (code != 0) return code;
  done.built = world.sum(done.built);
  done.resumed = world.sum(done.resumed);
  done.failed = world.sum(done.failed);
  if (world.rank != 0) return 0;
  const std::vector<int> failed = froth::write_ensemble_summary(opt, done);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  fmt::print("froth: ensemble of {} members of {} with r = {} and seed {} in {}: {} built, {} already complete{}; "
             "{:.3f} s ({:.2f} members per minute). Wrote {}/ensemble.pvd and {}/ensemble.json.\n",
             a.members, a.input, a.r, a.seed, a.dir, done.built, done.resumed,
             world.size > 1 ? fmt::format(" on {} ranks", world.size) : "", seconds,
             done.built > 0 ? 60.0 * double(done.built) / seconds : 0.0, a.dir, a.dir);
  if (failed.empty()) return 0;
  // The other members are complete; the run fails with the first failed member's code.
  fmt::print(stderr, "froth: error: {} of {} members could not be meshed (ensemble.json lists them under "
                     "failed_members, each DIR/member_K.failed.json says why); running the command again retries "
                     "them\n",
             failed.size(), a.members);
  return failed.front();
}

struct QualityArgs {
  std::string input, json, plots;
  int threads = 0;
};

// Histograms as PNG, drawn by scripts/quality_plots.py with Debian's python3-matplotlib.
void draw_plots(const std::string& json, const std::string& dir) {
  std::filesystem::create_directories(dir);
  const std::string script = std::string(FROTH_SCRIPTS_DIR) + "/quality_plots.py";
  const pid_t pid = fork();
  if (pid == 0) {
    execl("/usr/bin/python3", "python3", script.c_str(), json.c_str(), dir.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  if (pid < 0 || waitpid(pid, &status, 0) < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
    froth::fail(froth::ErrorKind::Io,
                fmt::format("could not draw the plots in {} ({} with /usr/bin/python3 and python3-matplotlib)", dir,
                            script));
}

int run_quality(const QualityArgs& a) {
  froth_cli::refuse_same_files({{"the mesh", a.input}, {"--json", a.json}, {"--plots", a.plots}});
  if (a.threads > 0) omp_set_num_threads(a.threads);
  froth::PolyMesh mesh = froth::read_vtu(a.input);
  const froth::MeshCheck check = froth::check_mesh(mesh);
  const froth::QualityReport q = froth::assess_quality(mesh);
  std::string json = a.json;
  if (json.empty() && !a.plots.empty()) json = (std::filesystem::path(a.plots) / "quality.json").string();
  if (!a.plots.empty()) std::filesystem::create_directories(a.plots);
  if (!json.empty()) froth::write_quality_json(q, a.input, json);
  if (!a.plots.empty()) draw_plots(json, a.plots);
  size_t cells = 0;
  for (auto n : q.cells) cells += n;
  std::string aspect = interior_aspect_text(q);
  aspect[0] = char(std::toupper(aspect[0]));
  fmt::print(
      "froth: {}: {} polyhedral cells ({} interior, {} fringe, {} edge, {} vertex); {}. {}, interior dihedrals {:.1f} "
      "to {:.1f} degrees, shortest edge {:.3g}; interior cells beyond Theorem 1: "
      "{}, beyond Lemma 6: {} interior, {} border-interior.{}{}\n",
      a.input, cells, q.cells[0], q.cells[1], q.cells[2], q.cells[3],
      check.ok() ? "every cell closed, every shared face matched"
                 : fmt::format("NOT VALID: {} open cells, {} unmatched faces, {} cells of non-positive volume (first: {})",
                               check.open_cells, check.unmatched_faces, check.nonpositive_cells, check.first_problem),
      aspect, q.dihedral[0].min, q.dihedral[0].max, q.shortest_edge, q.theorem1_violations,
      q.lemma6_interior_violations, q.lemma6_border_violations, json.empty() ? "" : " Wrote " + json + ".",
      a.plots.empty() ? "" : " Plots in " + a.plots + ".");
  return 0;
}

}  // namespace

// --partition: errors on one rank while the others wait in an exchange abort the whole run.
static int run_partitioned(const MeshArgs& a, const World& world) {
#ifdef FROTH_MPI
  froth_cli::MpiCommunicator comm;
#else
  froth_cli::SoloCommunicator comm;
#endif
  bool threw = true;
  const int code = froth_cli::run_with_exit_codes(
      [&] {
        const int c = run_mesh_partitioned(a, comm);
        threw = false;
        return c;
      },
      world.size > 1 ? fmt::format(" (rank {})", world.rank) : "");
  if (!threw) return code;
#ifdef FROTH_MPI
  if (world.size > 1) MPI_Abort(MPI_COMM_WORLD, code);
#endif
  return code;
}

int froth_main(int argc, char** argv, const World& world) {
  CLI::App app{"froth: uniform random Voronoi meshes by maximal Poisson-disk sampling"};
  app.set_version_flag("--version", FROTH_VERSION);
  app.require_subcommand(1);
  MeshArgs a;
  CLI::App* mesh = app.add_subcommand("mesh", "mesh a box or the solid a closed surface encloses with clipped Voronoi cells");
  mesh->add_option("input", a.input, "box:X0,Y0,Z0,X1,Y1,Z1 or a closed surface (STL, OBJ, OFF, PLY)")->required();
  CLI::Option* radius =
      mesh->add_option("-r,--radius", a.r, "sampling radius r: seeds are at least r apart, every point within r of one");
  CLI::Option* cells = mesh->add_option("--cells", a.cells, "instead of -r: choose r for about this many cells (reported)");
  radius->excludes(cells);
  mesh->add_flag("--dry-run", a.dry_run, "print the estimated cells, memory and time, and stop");
  mesh->add_option("--seed", a.seed_text, "random seed, 0 to 2^64-1 (the mesh is a pure function of input, r and seed)");
  mesh->add_option("-o,--output", a.output, "output VTU file (default: <input stem>.vtu)");
  mesh->add_option("--weld", a.weld, "weld tolerance w: vertices joined by an edge shorter than w merge (default 1e-4 min(r, the domain's diagonal); 0 = off)")
      ->check(CLI::NonNegativeNumber);
  mesh->add_option("--threads", a.threads, "threads (default 0: all cores); never changes the result")
      ->check(CLI::Range(0, 4096));
  mesh->add_option("--report", a.report, "write a JSON run report here");
  mesh->add_option("--max-memory", a.max_memory_gb,
                   "refuse a run estimated to need more than this many GB (default: the memory available)")
      ->check(CLI::PositiveNumber);
  mesh->add_flag("--no-quality", a.no_quality, "skip the per-cell quality metrics (VTU cell data and report)");
  mesh->add_option("--feature-angle", a.feature_angle,
                   "input edges turning by more than this many degrees are features (default 30)");
  mesh->add_flag("--repair", a.repair, "reorient shells whose triangles are inconsistently wound (reported)");
  mesh->add_flag("--grade", a.grade,
                 "grade the radius to the input's thin walls and gaps: h(x) <= r, at least --min-r (experimental)");
  mesh->add_option("--min-r", a.min_r, "with --grade: the smallest radius h may take (default: from r/4 up, the lowest that keeps the estimated cells within 3 times a uniform mesh's)")
      ->check(CLI::PositiveNumber);
  mesh->add_option("--max-grading", a.max_grading,
                   "with --grade: the slope of h along its grid, in (0, 0.25) (default 0.2; |grad h| <= sqrt(3) times it)");
  mesh->add_flag("--partition", a.partition,
                 "split the mesh over the MPI ranks (slabs of the sampling grid along z); writes a .pvtu with one "
                 "piece per rank, the same cells as one process makes");
  EnsembleArgs ea;
  CLI::App* ensemble = app.add_subcommand("ensemble", "make N independent meshes of one domain (resumable)");
  ensemble->add_option("input", ea.input, "box:X0,Y0,Z0,X1,Y1,Z1 or a closed surface (STL, OBJ, OFF, PLY)")->required();
  ensemble->add_option("-r,--radius", ea.r, "sampling radius r")->required();
  ensemble->add_option("-n,--members", ea.members, "number of members")->required()->check(CLI::Range(1, 1000000));
  ensemble->add_option("--seed", ea.seed_text, "ensemble seed S; member k has seed froth::member_seed(S, k)");
  ensemble->add_option("-o,--output", ea.dir, "output directory")->required();
  ensemble->add_option("--weld", ea.weld, "weld tolerance (default 1e-4 min(r, the domain's diagonal); 0 = off)")->check(CLI::NonNegativeNumber);
  ensemble->add_option("--threads", ea.threads, "threads per member (default 0: all cores)")->check(CLI::Range(0, 4096));
  ensemble->add_flag("--no-quality", ea.no_quality, "skip the per-cell quality metrics");
  ensemble->add_option("--max-memory", ea.max_memory_gb, "refuse members estimated to need more GB (default: available)")
      ->check(CLI::PositiveNumber);
  ensemble->add_option("--feature-angle", ea.feature_angle, "feature angle in degrees (default 30)");
  ensemble->add_flag("--repair", ea.repair, "reorient inconsistently wound shells (reported)");
  ensemble->add_flag("--grade", ea.grade, "grade the radius to thin walls and gaps, as for froth mesh (experimental)");
  ensemble->add_option("--min-r", ea.min_r, "with --grade: the smallest radius (default: from r/4 up, within a budget of 3 times the uniform cells)")->check(CLI::PositiveNumber);
  ensemble->add_option("--max-grading", ea.max_grading, "with --grade: the slope of h, in (0, 0.25) (default 0.2)");
  QualityArgs qa;
  CLI::App* quality = app.add_subcommand("quality", "measure the cells of a polyhedral VTU: aspect ratios, dihedrals, edges");
  quality->add_option("mesh", qa.input, "a VTU of VTK_POLYHEDRON cells (froth's or any other writer's)")->required();
  quality->add_option("--json", qa.json, "write the quality report (JSON) here");
  quality->add_option("--plots", qa.plots, "write PNG histograms (aspect ratio by cell kind, dihedrals by class) here");
  quality->add_option("--threads", qa.threads, "threads (default 0: all cores); never changes the result")
      ->check(CLI::Range(0, 4096));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  if (ensemble->parsed()) {
    std::string command;
    for (int i = 0; i < argc; ++i) command += (i ? " " : "") + std::string(argv[i]);
    return froth_cli::run_with_exit_codes([&] {
      ea.seed = froth_cli::parse_seed(ea.seed_text);
      return run_ensemble(ea, command, world);
    });
  }
  if (mesh->parsed()) {
    if (const int code = froth_cli::run_with_exit_codes([&] { return a.seed = froth_cli::parse_seed(a.seed_text), 0; }))
      return code;
    if (a.partition) return run_partitioned(a, world);
  }
  // Otherwise one mesh is made by one process.
  if (world.rank != 0) return 0;
  return froth_cli::run_with_exit_codes([&] {
    if (mesh->parsed()) return run_mesh(a);
    if (quality->parsed()) return run_quality(qa);
    return 2;
  });
}

int main(int argc, char** argv) {
  froth::remove_temporaries_on_signal();
  World world;
#ifdef FROTH_MPI
  MPI_Init(&argc, &argv);
  MPI_Comm_rank(MPI_COMM_WORLD, &world.rank);
  MPI_Comm_size(MPI_COMM_WORLD, &world.size);
  const int code = froth_main(argc, argv, world);
  MPI_Finalize();
  return code;
#else
  return froth_main(argc, argv, world);
#endif
}

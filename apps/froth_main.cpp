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
#include <optional>

#include <omp.h>
#ifdef FROTH_MPI
#include <mpi.h>
#endif

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "cli_guards.hpp"
#include "cli_options.hpp"
#include "progress_bar.hpp"
#include "python_scripts.hpp"
#include "summary.hpp"
#include "communicators.hpp"
#include "froth/froth.hpp"

namespace {

using froth_cli::CommonArgs;
using froth_cli::Verbosity;

struct MeshArgs : CommonArgs {
  std::string output;
  std::string report;
  std::string boundary;  // --boundary: the border faces with their patches
  bool compress = false;
  bool partition = false;
  double cells = 0;  // --cells: choose r for about this many (0: -r given)
  bool dry_run = false;
};

std::string default_output(const std::string& input) {
  if (input.rfind("box:", 0) == 0) return "box.vtu";
  return std::filesystem::path(input).stem().string() + ".vtu";
}

std::vector<std::string> written(const std::string& mesh, const std::string& report) {
  std::vector<std::string> out{mesh};
  if (!report.empty()) out.push_back(report);
  return out;
}

// The options given: -r, or --cells for the library to choose r (the summary says which).
froth::MeshOptions options_of(const MeshArgs& a) {
  if (a.cells == 0 && a.r == -INFINITY) froth::fail(froth::ErrorKind::Usage, "give -r R (the sampling radius) or --cells N");
  froth::MeshOptions opt = froth_cli::mesh_options(a);
  opt.cells = a.cells;
  return opt;
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

// The input read and validated (its self-intersection test can be the longest stage of a
// finely tessellated part), timed as the run's first stage.
struct Reading {
  explicit Reading(const MeshArgs& a) {
    const auto t0 = std::chrono::steady_clock::now();
    domain = froth::load_regions(a.inputs, a.load_options());
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    peak_bytes = froth::peak_rss_bytes();
  }
  void add_stage(froth::RunReport& run) const {
    run.stages.insert(run.stages.begin(), {"reading", seconds, peak_bytes});
    run.total_seconds += seconds;
  }
  froth::Domain domain;
  double seconds = 0;
  size_t peak_bytes = 0;
};

int run_mesh(const MeshArgs& a) {
  const std::string output = a.output.empty() ? default_output(a.input) : a.output;
  froth_cli::refuse_same_files(
      {{"the input", a.input}, {"-o", output}, {"--report", a.report}, {"--boundary", a.boundary}});
  froth_cli::refuse_unknown_mesh_format("-o", output);
  if (!a.boundary.empty()) froth_cli::refuse_unknown_format("--boundary", a.boundary, {".vtu"});
  if (!a.dry_run) froth_cli::refuse_unwritable_outputs({{"-o", output}, {"--report", a.report}, {"--boundary", a.boundary}});
  const Reading reading(a);
  const froth::Domain& domain = reading.domain;
  froth::MeshOptions opt = options_of(a);
  if (a.dry_run) return dry_run(a, domain, froth::resolve_options(domain, opt, false));
  froth_cli::ProgressBar bar(!a.quiet);
  opt.progress = bar.callback();
  froth::RunReport run;
  froth::PolyMesh mesh = froth::generate_mesh(domain, opt, &run);
  reading.add_stage(run);
  auto t0 = std::chrono::steady_clock::now();
  if (opt.progress) opt.progress("writing", 0);
  froth::OutputGroup outputs;  // the mesh and its report appear together, or neither
  froth::write_mesh(mesh, run, output,
                   opt.progress ? [&](double f) { opt.progress("writing", f); } : std::function<void(double)>(),
                   a.compress);
  const double write_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  run.stages.push_back({"writing", write_seconds, froth::peak_rss_bytes()});
  run.total_seconds += write_seconds;
  if (!a.boundary.empty()) froth::write_boundary_vtu(mesh, a.boundary);
  if (!a.report.empty()) froth::write_report_json(run, a.report);
  outputs.commit();
  bar.clear();
  std::vector<std::string> files = written(output, a.report);
  if (!a.boundary.empty()) files.push_back(a.boundary);
  fmt::print("{}", froth_cli::mesh_summary(run, files, a.verbosity()));
  return 0;
}

// One mesh over all ranks (froth/partition.hpp): each rank writes its piece,
// OUT/OUT_<rank>.vtu beside OUT.pvtu, and rank 0 the .pvtu, the report and the summary once every
// piece is written. A rank that fails while the others wait for it aborts the run.
int run_mesh_partitioned(const MeshArgs& a, froth::Communicator& comm) {
  std::filesystem::path output = a.output.empty() ? default_output(a.input) : a.output;
  if (output.extension() == ".vtu") output.replace_extension(".pvtu");
  froth_cli::refuse_unknown_format("-o with --partition", output.string(), {".pvtu"});
  froth_cli::refuse_unwritable_outputs({{"-o", output.string()}, {"--report", a.report}});
  const Reading reading(a);
  const froth::Domain& domain = reading.domain;
  froth::MeshOptions opt = options_of(a);
  froth_cli::ProgressBar bar(!a.quiet && comm.rank() == 0);
  opt.progress = bar.callback();
  froth::RunReport run;
  froth::PartitionReport part;
  froth::PolyMesh piece = froth::generate_mesh_piece(domain, opt, comm, &run, &part);
  reading.add_stage(run);

  const std::string stem = output.stem().string();
  const std::filesystem::path dir = output.parent_path() / stem;
  const std::string relative = fmt::format("{}/{}_{}.vtu", stem, stem, comm.rank());
  auto t0 = std::chrono::steady_clock::now();
  if (opt.progress) opt.progress("writing", 0);
  int code = froth_cli::run_with_exit_codes(
      [&] {
        std::filesystem::create_directories(dir);
        froth::write_vtu(piece, run, output.parent_path() / relative);
        return 0;
      },
      fmt::format(" (rank {})", comm.rank()));
  // Every piece is written (or every rank removes its own) before the .pvtu names them.
  code = int(comm.max(code));
  if (code != 0) {
    std::filesystem::remove(output.parent_path() / relative);
    return code;
  }
  const double write_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  run.stages.push_back({"writing", write_seconds, froth::peak_rss_bytes()});
  run.total_seconds += write_seconds;
  froth::PartitionSummary all = froth::combine_rank_reports(comm, run, part);
  if (comm.rank() != 0) return 0;
  std::vector<std::string> pieces;
  for (int k = 0; k < comm.size(); ++k) pieces.push_back(fmt::format("{}/{}_{}.vtu", stem, stem, k));
  try {
    froth::write_pvtu(pieces, opt.quality, domain.regions != nullptr, output);
  } catch (const froth::Error&) {
    for (const std::string& p : pieces) std::filesystem::remove(output.parent_path() / p);  // no .pvtu, no pieces
    throw;
  }
  if (!a.report.empty()) froth::write_report_json(all.run, a.report, &all);
  bar.clear();
  if (a.quiet) return 0;
  fmt::print("{}", froth_cli::mesh_summary(all.run, written(output.string(), a.report), a.verbosity()));
  size_t owned = 0, ghosts = 0, shared = 0, fewest = SIZE_MAX, most = 0;
  for (const auto& p : all.ranks) {
    owned += p.owned_seeds, ghosts += p.ghost_seeds, shared += p.partition_faces;
    fewest = std::min(fewest, p.owned_seeds), most = std::max(most, p.owned_seeds);
  }
  fmt::print("  {:<10}over {} rank{} in slabs of z layers: {} to {} cells per rank, halo {} ghost seeds ({:.3f} per "
             "owned seed), {} cell faces shared between ranks (each counted from both sides)\n",
             "partition",
             comm.size(), comm.size() == 1 ? "" : "s", fewest, most, ghosts, owned ? double(ghosts) / double(owned) : 0.0,
             shared);
  return 0;
}

struct EnsembleArgs : CommonArgs {
  std::string dir;
  size_t members = 0;
  bool overwrite = false;
};

// Members are spread over the ranks (member k on rank k % ranks); rank 0 writes the summary
// once every rank is done. A rank that fails makes every rank exit with its code.
int run_ensemble(const EnsembleArgs& a, const std::string& command, froth::Communicator& world) {
  froth::EnsembleOptions opt;
  opt.input = a.input;
  opt.mesh = froth_cli::mesh_options(a);
  opt.members = a.members;
  opt.dir = a.dir;
  opt.command = command;
  opt.rank = world.rank();
  opt.ranks = world.size();
  froth_cli::ProgressBar bar(!a.quiet && world.rank() == 0);
  opt.progress = bar.callback();
  const auto t0 = std::chrono::steady_clock::now();
  froth::EnsembleProgress done;
  const std::string where = world.size() > 1 ? fmt::format(" (rank {})", world.rank()) : "";
  // Every rank reaches each world.max, whatever it threw: none waits for a rank that left.
  std::optional<froth::Domain> domain;
  froth::FolderLock lock;  // rank 0 holds the folder until the run ends
  int code = froth_cli::run_with_exit_codes(
      [&] {
        domain = froth::load_regions(a.inputs, a.load_options());
        // One rank looks at the folder (and empties it with --overwrite) before any rank builds.
        if (world.rank() == 0) {
          froth_cli::refuse_unwritable_outputs({{"-o", (std::filesystem::path(a.dir) / "ensemble.json").string()}});
          lock = froth::prepare_ensemble_folder(*domain, opt, a.overwrite);
        }
        return 0;
      },
      where);
  code = world.max(code);
  if (code == 0) code = froth_cli::run_with_exit_codes([&] { return done = froth::build_members(*domain, opt), 0; }, where);
  code = world.max(code);
  if (code != 0) return code;
  done.built = world.sum(done.built);
  done.resumed = world.sum(done.resumed);
  done.failed = world.sum(done.failed);
  if (world.rank() != 0) return 0;
  const std::vector<int> failed = froth::write_ensemble_summary(*domain, opt, done);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  bar.clear();
  if (!a.quiet)
    fmt::print("froth: ensemble of {} members of {} with r = {} and seed {} in {}\n"
               "  {:<10}{} built, {} already complete{}; {:.3f} s ({:.2f} members per minute)\n"
               "  {:<10}{}/ensemble.pvd, {}/ensemble.json\n",
               a.members, a.input, a.r, a.seed, a.dir, "members", done.built, done.resumed,
               world.size() > 1 ? fmt::format(" on {} ranks", world.size()) : "", seconds,
               done.built > 0 ? 60.0 * double(done.built) / seconds : 0.0, "wrote", a.dir, a.dir);
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
  bool quiet = false;
};

// "mesh.vtu: r = 0.1, seed 1, 3392 cells", as far as the mesh records them.
std::string mesh_title(const std::string& path, const froth::PolyMesh& mesh) {
  std::string title = std::filesystem::path(path).filename().string();
  if (mesh.r > 0) title += fmt::format(": r = {:.4g}", mesh.r);
  if (mesh.random_seed) title += fmt::format(", seed {}", *mesh.random_seed);
  return title + fmt::format(", {} cells", mesh.cell_count());
}

int run_quality(const QualityArgs& a) {
  froth_cli::refuse_same_files({{"the mesh", a.input}, {"--json", a.json}, {"--plots", a.plots}});
  froth_cli::refuse_unwritable_outputs({{"--json", a.json}, {"--plots", a.plots.empty() ? "" : a.plots + "/aspect.png"}});
  if (a.threads > 0) omp_set_num_threads(a.threads);
  froth::PolyMesh mesh = froth::read_vtu(a.input);
  mesh.volumes.clear();  // the check measures the file's geometry, not the volumes it claims
  const froth::MeshCheck check = froth::check_mesh(mesh);
  const froth::QualityReport q = froth::assess_quality(mesh);
  std::string json = a.json;
  if (json.empty() && !a.plots.empty()) json = (std::filesystem::path(a.plots) / "quality.json").string();
  if (!a.plots.empty()) std::filesystem::create_directories(a.plots);
  if (!json.empty()) froth::write_quality_json(q, a.input, json);
  if (!a.plots.empty())
    froth_cli::run_python_script("quality_plots.py", {json, a.plots, mesh_title(a.input, mesh)}, false,
                                 fmt::format("draw the plots in {} (python3-matplotlib)", a.plots));
  std::vector<std::string> files;
  if (!json.empty()) files.push_back(json);
  if (!a.plots.empty()) files.push_back(a.plots + "/aspect.png, " + a.plots + "/dihedral.png");
  if (!a.quiet) fmt::print("{}", froth_cli::quality_summary(a.input, check, q, files));
  return 0;
}

struct ConvertArgs {
  std::string input, output;
  bool quiet = false;
};

// A mesh already written (froth's VTU, or any polyhedral VTU) in another format.
int run_convert(const ConvertArgs& a) {
  froth_cli::refuse_same_files({{"the mesh", a.input}, {"-o", a.output}});
  froth_cli::refuse_unknown_mesh_format("-o", a.output);
  froth_cli::refuse_unwritable_outputs({{"-o", a.output}});
  froth::RunReport run;  // what the VTU's field data keep
  froth::PolyMesh mesh = froth::read_vtu(a.input, &run);
  // The file's geometry is checked as `quality` checks it (not the volumes it claims): an open
  // or inverted cell would reach a solver as a negative volume.
  std::vector<double> claimed = std::move(mesh.volumes);
  mesh.volumes.clear();
  const froth::MeshCheck check = froth::check_mesh(mesh);
  if (!check.ok())
    froth::fail(froth::ErrorKind::InvalidInput,
                fmt::format("{}: not a valid mesh, so it is not converted: {} open cells, {} cells of volume zero or "
                            "less; first: {}",
                            a.input, check.open_cells, check.nonpositive_cells, check.first_problem));
  mesh.volumes = std::move(claimed);
  froth::write_mesh(mesh, run, a.output);
  if (!a.quiet)
    fmt::print("froth: converted {} ({} cells)\n  {:<10}{}\n", a.input, mesh.cell_count(), "wrote", a.output);
  return 0;
}

struct RenderArgs {
  std::string input, output, colour = "kind";
  int width = 1200, height = 900;
  bool quiet = false;
};

// A PNG of the mesh cut open at the middle (scripts/render_mesh.py, VTK offscreen), written to a
// temporary name and renamed on success.
int run_render(const RenderArgs& a) {
  froth_cli::refuse_same_files({{"the mesh", a.input}, {"-o", a.output}});
  froth_cli::refuse_unknown_format("-o", a.output, {".png"}, "PNG images");
  froth_cli::refuse_unwritable_outputs({{"-o", a.output}});
  froth::read_vtu(a.input);  // a clear error (exit 3 or 4) for a file that is not a polyhedral VTU
  // (The PNG's folder is made as every output's is; VTK names no reason when it cannot write.)
  std::filesystem::create_directories(std::filesystem::absolute(a.output).parent_path());
  froth::write_atomically_by_name(
      a.output,
      [&](const std::filesystem::path& tmp) {
        froth_cli::run_python_script("render_mesh.py",
                                     {a.input, tmp.string(), a.colour, std::to_string(a.width), std::to_string(a.height)},
                                     true, fmt::format("render {} (python3-vtk9)", a.input));
      },
      ".png");
  if (!a.quiet) fmt::print("froth: rendered {}\n  {:<10}{}\n", a.input, "wrote", a.output);
  return 0;
}

}  // namespace

// --partition: errors on one rank while the others wait in an exchange abort the whole run.
static int run_partitioned(const MeshArgs& a, froth::Communicator& world) {
  bool threw = true;
  const int code = froth_cli::run_with_exit_codes(
      [&] {
        const int c = run_mesh_partitioned(a, world);
        threw = false;
        return c;
      },
      world.size() > 1 ? fmt::format(" (rank {})", world.rank()) : "");
  if (!threw) return code;
#ifdef FROTH_MPI
  if (world.size() > 1) MPI_Abort(MPI_COMM_WORLD, code);
#endif
  return code;
}

int froth_main(int argc, char** argv, froth::Communicator& world) {
  CLI::App app{"froth: uniform random Voronoi meshes by maximal Poisson-disk sampling"};
  app.set_version_flag("--version", FROTH_VERSION);
  app.require_subcommand(1);
  MeshArgs a;
  CLI::App* mesh = app.add_subcommand("mesh", "mesh a box or the solid a closed surface encloses with clipped Voronoi cells");
  CLI::Option* radius = froth_cli::add_common_options(*mesh, a);
  CLI::Option* cells = mesh->add_option("--cells", a.cells, "instead of -r: choose r for about this many cells (reported)");
  radius->excludes(cells);
  mesh->add_flag("--convex", a.convex,
                 "split every non-convex cell into convex pieces that conform with their neighbours (cell data "
                 "parent; no welding)");
  mesh->add_flag("--dry-run", a.dry_run, "print the estimated cells, memory and time, and stop");
  mesh->add_option("-o,--output", a.output,
                   "output: OUT.vtu (default <input stem>.vtu), a folder named polyMesh (OpenFOAM), OUT.npz (facet "
                   "graph) or OUT.nodes (peridynamic nodes)");
  mesh->add_option("--report", a.report, "write a JSON run report here");
  mesh->add_flag("--compress", a.compress, "zlib-compress the VTU's arrays (VTK and ParaView read it; about half the size)");
  mesh->add_option("--boundary", a.boundary,
                   "write the border faces here as a surface VTU with each face's patch (STL solid, OBJ group, or "
                   "smooth region between feature curves)");
  mesh->add_flag("--partition", a.partition,
                 "split the mesh over the MPI ranks (slabs of the sampling grid along z); writes a .pvtu with one "
                 "piece per rank, the same cells as one process makes");
  EnsembleArgs ea;
  CLI::App* ensemble = app.add_subcommand("ensemble", "make N independent meshes of one domain (resumable)");
  froth_cli::add_common_options(*ensemble, ea)->required();
  ensemble->add_option("-n,--members", ea.members, "number of members")->required()->check(CLI::Range(1, 1000000));
  ensemble->add_option("-o,--output", ea.dir, "output folder")->required();
  ensemble->add_flag("--overwrite", ea.overwrite,
                     "replace an ensemble made with other inputs in the folder (without it such a folder is refused)");
  QualityArgs qa;
  CLI::App* quality = app.add_subcommand("quality", "measure the cells of a polyhedral VTU: aspect ratios, dihedrals, edges");
  quality->add_option("mesh", qa.input, "a VTU of VTK_POLYHEDRON cells (froth's or any other writer's)")->required();
  quality->add_option("--json", qa.json, "write the quality report (JSON) here");
  quality->add_option("--plots", qa.plots, "write PNG histograms (aspect ratio by cell kind, dihedrals by class) here");
  quality->add_option("--threads", qa.threads, "threads (default 0: all cores); never changes the result")
      ->check(CLI::Range(0, 4096));
  quality->add_flag("-q,--quiet", qa.quiet, "print nothing on success");
  ConvertArgs ca;
  CLI::App* convert = app.add_subcommand("convert", "write a mesh already made (a polyhedral VTU) in another format");
  convert->add_option("mesh", ca.input, "a VTU of VTK_POLYHEDRON cells")->required();
  convert->add_option("-o,--output", ca.output, "OUT.vtu, a folder named polyMesh (OpenFOAM), OUT.npz (facet graph) or OUT.nodes (peridynamic nodes)")->required();
  convert->add_flag("-q,--quiet", ca.quiet, "print nothing on success");
  RenderArgs ra;
  CLI::App* render = app.add_subcommand("render", "draw a mesh cut open at the middle as a PNG (VTK, offscreen)");
  render->add_option("mesh", ra.input, "a VTU of VTK_POLYHEDRON cells")->required();
  render->add_option("-o,--output", ra.output, "the PNG to write")->required();
  render->add_option("--color", ra.colour, "colour by cell kind or by this cell array (aspect, volume, radius, ...)")
      ->capture_default_str();
  render->add_option("--width", ra.width, "image width in pixels")->capture_default_str()->check(CLI::Range(64, 8192));
  render->add_option("--height", ra.height, "image height in pixels")->capture_default_str()->check(CLI::Range(64, 8192));
  render->add_flag("-q,--quiet", ra.quiet, "print nothing on success");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints the help, the version or the parse error
    return code == 0 ? 0 : int(froth::ErrorKind::Usage);
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
  if (world.rank() != 0) return 0;
  return froth_cli::run_with_exit_codes([&] {
    if (mesh->parsed()) return run_mesh(a);
    if (quality->parsed()) return run_quality(qa);
    if (render->parsed()) return run_render(ra);
    if (convert->parsed()) return run_convert(ca);
    return int(froth::ErrorKind::Usage);
  });
}

int main(int argc, char** argv) {
  froth::remove_temporaries_on_signal();
#ifdef FROTH_MPI
  MPI_Init(&argc, &argv);
  int code;
  {
    froth_cli::MpiCommunicator world;
    code = froth_main(argc, argv, world);
  }
  MPI_Finalize();
  return code;
#else
  froth::SoloCommunicator world;
  return froth_main(argc, argv, world);
#endif
}

// froth mesh: one mesh of a part, by one process or (--partition) over all MPI ranks.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>

#include <omp.h>
#ifdef FROTH_MPI
#include <mpi.h>
#endif

#include <fmt/format.h>

#include "cli_guards.hpp"
#include "commands.hpp"
#include "progress_bar.hpp"
#include "summary.hpp"
#include "froth/froth.hpp"

namespace froth_cli {
namespace {

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
  froth::MeshOptions opt = mesh_options(a);
  opt.cells = a.cells;
  return opt;
}

// --dry-run: what the run would take, from the saturated density (froth::estimate_run) and the
// pipeline's time per cell on 2 threads, erring high (docs/performance.md measures it: a box's
// time per cell, and real parts' multiples of it).
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
    domain = a.load();
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

// The writing stage, timed into the report as the library times its stages.
class WritingStage {
 public:
  explicit WritingStage(const froth::MeshOptions& opt) : opt_(opt) {
    if (opt_.progress) opt_.progress("writing", 0);
  }
  std::function<void(double)> progress() const {
    if (!opt_.progress) return {};
    return [this](double f) { opt_.progress("writing", f); };
  }
  void done(froth::RunReport& run) const {
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
    run.stages.push_back({"writing", seconds, froth::peak_rss_bytes()});
    run.total_seconds += seconds;
  }

 private:
  const froth::MeshOptions& opt_;
  std::chrono::steady_clock::time_point t0_ = std::chrono::steady_clock::now();
};

int run_mesh_whole(const MeshArgs& a) {
  const std::string output = a.output.empty() ? default_output(a.input) : a.output;
  refuse_same_files(
      {{"the input", a.input}, {"-o", output}, {"--report", a.report}, {"--boundary", a.boundary}});
  refuse_unknown_mesh_format("-o", output);
  if (!a.boundary.empty()) refuse_unknown_format("--boundary", a.boundary, {".vtu"});
  if (!a.dry_run) refuse_unwritable_outputs({{"-o", output}, {"--report", a.report}, {"--boundary", a.boundary}});
  const Reading reading(a);
  const froth::Domain& domain = reading.domain;
  froth::MeshOptions opt = options_of(a);
  if (a.dry_run) return dry_run(a, domain, froth::resolve_options(domain, opt, false));
  ProgressBar bar(!a.quiet);
  opt.progress = bar.callback();
  froth::RunReport run;
  froth::PolyMesh mesh = froth::generate_mesh(domain, opt, &run);
  reading.add_stage(run);
  const WritingStage writing(opt);
  froth::OutputGroup outputs;  // the mesh and its report appear together, or neither
  froth::write_mesh(mesh, run, output, writing.progress(), a.compress);
  writing.done(run);
  if (!a.boundary.empty()) froth::write_boundary_vtu(mesh, a.boundary);
  if (!a.report.empty()) froth::write_report_json(run, a.report);
  outputs.commit();
  bar.clear();
  std::vector<std::string> files = written(output, a.report);
  if (!a.boundary.empty()) files.push_back(a.boundary);
  fmt::print("{}", mesh_summary(run, files, a.verbosity()));
  return 0;
}

// One mesh over all ranks (froth/partition.hpp): each rank writes its piece,
// OUT/OUT_<rank>.vtu beside OUT.pvtu, and rank 0 the .pvtu, the report and the summary once every
// piece is written. A rank that fails while the others wait for it aborts the run.
int run_mesh_partitioned(const MeshArgs& a, froth::Communicator& comm) {
  std::filesystem::path output = a.output.empty() ? default_output(a.input) : a.output;
  if (output.extension() == ".vtu") output.replace_extension(".pvtu");
  refuse_unknown_format("-o with --partition", output.string(), {".pvtu"});
  refuse_unwritable_outputs({{"-o", output.string()}, {"--report", a.report}});
  const Reading reading(a);
  const froth::Domain& domain = reading.domain;
  froth::MeshOptions opt = options_of(a);
  ProgressBar bar(!a.quiet && comm.rank() == 0);
  opt.progress = bar.callback();
  froth::RunReport run;
  froth::PartitionReport part;
  froth::PolyMesh piece = froth::generate_mesh_piece(domain, opt, comm, &run, &part);
  reading.add_stage(run);

  const std::string stem = output.stem().string();
  const std::filesystem::path dir = output.parent_path() / stem;
  const std::string relative = fmt::format("{}/{}_{}.vtu", stem, stem, comm.rank());
  const WritingStage writing(opt);
  int code = run_with_exit_codes(
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
  writing.done(run);
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
  fmt::print("{}", mesh_summary(all.run, written(output.string(), a.report), a.verbosity()));
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

// --partition: errors on one rank while the others wait in an exchange abort the whole run.
int run_partitioned(const MeshArgs& a, froth::Communicator& world) {
  bool threw = true;
  const int code = run_with_exit_codes(
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

}  // namespace

CLI::App* add_mesh_command(CLI::App& app, MeshArgs& a) {
  CLI::App* mesh = app.add_subcommand("mesh", "mesh a box or the solid a closed surface encloses with clipped Voronoi cells");
  CLI::Option* radius = add_common_options(*mesh, a);
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
  return mesh;
}

int run_mesh(const MeshArgs& a, froth::Communicator& world) {
  if (a.partition) return run_partitioned(a, world);
  if (world.rank() != 0) return 0;  // one mesh, made by one process
  return run_with_exit_codes([&] { return run_mesh_whole(a); });
}

}  // namespace froth_cli

// froth ensemble: many independent meshes of one part, spread over the MPI ranks; resumable.
#include <chrono>
#include <filesystem>
#include <optional>

#include <fmt/format.h>

#include "cli_guards.hpp"
#include "commands.hpp"
#include "progress_bar.hpp"
#include "froth/froth.hpp"

namespace froth_cli {

CLI::App* add_ensemble_command(CLI::App& app, EnsembleArgs& ea) {
  CLI::App* ensemble = app.add_subcommand("ensemble", "make N independent meshes of one domain (resumable)");
  add_common_options(*ensemble, ea)->required();
  ensemble->add_option("-n,--members", ea.members, "number of members")->required()->check(CLI::Range(1, 1000000));
  ensemble->add_option("-o,--output", ea.dir, "output folder")->required();
  ensemble->add_flag("--overwrite", ea.overwrite,
                     "replace an ensemble made with other inputs in the folder (without it such a folder is refused)");
  return ensemble;
}

// Members are spread over the ranks (member k on rank k % ranks); rank 0 writes the summary
// once every rank is done. A rank that fails makes every rank exit with its code.
int run_ensemble(const EnsembleArgs& a, const std::string& command, froth::Communicator& world) {
  froth::EnsembleOptions opt;
  opt.input = a.input;
  opt.mesh = mesh_options(a);
  opt.members = a.members;
  opt.dir = a.dir;
  opt.command = command;
  opt.rank = world.rank();
  opt.ranks = world.size();
  ProgressBar bar(!a.quiet && world.rank() == 0);
  opt.progress = bar.callback();
  const auto t0 = std::chrono::steady_clock::now();
  froth::EnsembleProgress done;
  const std::string where = world.size() > 1 ? fmt::format(" (rank {})", world.rank()) : "";
  // Every rank reaches each world.max, whatever it threw: none waits for a rank that left.
  std::optional<froth::Domain> domain;
  froth::FolderLock lock;  // rank 0 holds the folder until the run ends
  int code = run_with_exit_codes(
      [&] {
        domain = a.load();
        // One rank looks at the folder (and empties it with --overwrite) before any rank builds.
        if (world.rank() == 0) {
          refuse_unwritable_outputs({{"-o", (std::filesystem::path(a.dir) / "ensemble.json").string()}});
          lock = froth::prepare_ensemble_folder(*domain, opt, a.overwrite);
        }
        return 0;
      },
      where);
  code = world.max(code);
  if (code == 0) code = run_with_exit_codes([&] { return done = froth::build_members(*domain, opt), 0; }, where);
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

}  // namespace froth_cli

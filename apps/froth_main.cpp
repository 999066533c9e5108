// froth command line: the subcommands (apps/*_command.cpp) parsed and run. Exit codes: 0
// success, 2 usage, 3 invalid input, 4 I/O failure, 5 internal error.
#ifdef FROTH_MPI
#include <mpi.h>
#endif

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdlib>

#include "cli_guards.hpp"
#include "commands.hpp"
#include "communicators.hpp"
#include "froth/froth.hpp"

int froth_main(int argc, char** argv, froth::Communicator& world) {
  CLI::App app{"froth: uniform random Voronoi meshes by maximal Poisson-disk sampling"};
  app.set_version_flag("--version", FROTH_VERSION);
  app.require_subcommand(1);
  froth_cli::MeshArgs a;
  CLI::App* mesh = froth_cli::add_mesh_command(app, a);
  froth_cli::EnsembleArgs ea;
  CLI::App* ensemble = froth_cli::add_ensemble_command(app, ea);
  froth_cli::QualityArgs qa;
  CLI::App* quality = froth_cli::add_quality_command(app, qa);
  froth_cli::ConvertArgs ca;
  CLI::App* convert = froth_cli::add_convert_command(app, ca);
  froth_cli::RenderArgs ra;
  CLI::App* render = froth_cli::add_render_command(app, ra);
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
      return froth_cli::run_ensemble(ea, command, world);
    });
  }
  if (mesh->parsed()) {
    if (const int code = froth_cli::run_with_exit_codes([&] { return a.seed = froth_cli::parse_seed(a.seed_text), 0; }))
      return code;
    return froth_cli::run_mesh(a, world);
  }
  // The other subcommands run in one process.
  if (world.rank() != 0) return 0;
  return froth_cli::run_with_exit_codes([&] {
    if (quality->parsed()) return froth_cli::run_quality(qa);
    if (render->parsed()) return froth_cli::run_render(ra);
    if (convert->parsed()) return froth_cli::run_convert(ca);
    return int(froth::ErrorKind::Usage);
  });
}

namespace {

// glibc's allocator, set to back its large blocks with huge pages. Each stage builds arrays of
// hundreds of MB and frees them; glibc maps each afresh, and the program then faulted it in 4 KiB
// page by page: a tenth of a 750,000-cell run, more in a virtual machine. Freed blocks still go
// back to the system, so the peak does not grow. glibc reads this setting only from the
// environment at start, so froth sets it and runs itself again, once. It does not where the user
// set GLIBC_TUNABLES, or where a tool preloads a library (valgrind, heaptrack): the second run
// would escape the tool. The marker is removed again, so programs froth starts (Python) get the
// user's environment.
constexpr const char* kTunedMarker = "FROTH_ALLOCATOR_SET";
void tune_allocator(char** argv) {
  if (std::getenv(kTunedMarker)) {
    unsetenv(kTunedMarker);
    unsetenv("GLIBC_TUNABLES");
    return;
  }
  if (std::getenv("GLIBC_TUNABLES") || std::getenv("LD_PRELOAD")) return;
  setenv(kTunedMarker, "1", 1);
  setenv("GLIBC_TUNABLES", "glibc.malloc.hugetlb=1", 1);
  execv("/proc/self/exe", argv);
  unsetenv(kTunedMarker);  // no exec: run as started
  unsetenv("GLIBC_TUNABLES");
}

}  // namespace

int main(int argc, char** argv) {
  tune_allocator(argv);
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

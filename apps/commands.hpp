// froth's subcommands, one file each: each registers its options on the command line and runs.
// Exit codes: 0 success, 2 usage, 3 invalid input, 4 I/O failure, 5 internal error.
#pragma once
#include <string>

#include <CLI/CLI.hpp>

#include "cli_options.hpp"
#include "froth/communicator.hpp"

namespace froth_cli {

struct MeshArgs : CommonArgs {
  std::string output;
  std::string report;
  std::string boundary;  // --boundary: the border faces with their patches
  bool compress = false;
  bool partition = false;
  double cells = 0;  // --cells: choose r for about this many (0: -r given)
  bool dry_run = false;
};
CLI::App* add_mesh_command(CLI::App& app, MeshArgs& a);
// One process's mesh, or with --partition one mesh over all ranks.
int run_mesh(const MeshArgs& a, froth::Communicator& world);

struct EnsembleArgs : CommonArgs {
  std::string dir;
  size_t members = 0;
  bool overwrite = false;
};
CLI::App* add_ensemble_command(CLI::App& app, EnsembleArgs& a);
int run_ensemble(const EnsembleArgs& a, const std::string& command, froth::Communicator& world);

struct QualityArgs {
  std::string input, json, plots;
  int threads = 0;
  bool quiet = false;
};
CLI::App* add_quality_command(CLI::App& app, QualityArgs& a);
int run_quality(const QualityArgs& a);

struct ConvertArgs {
  std::string input, output;
  bool quiet = false;
};
CLI::App* add_convert_command(CLI::App& app, ConvertArgs& a);
int run_convert(const ConvertArgs& a);

struct RenderArgs {
  std::string input, output, colour = "kind";
  int width = 1200, height = 900;
  bool quiet = false;
};
CLI::App* add_render_command(CLI::App& app, RenderArgs& a);
int run_render(const RenderArgs& a);

}  // namespace froth_cli

// The options `froth mesh` and `froth ensemble` share, registered once, and what they become:
// the library's MeshOptions.
#pragma once
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "froth/froth.hpp"
#include "summary.hpp"

namespace froth_cli {

inline const std::string kVtuDescription = "a VTK XML unstructured grid of polyhedra that ParaView and VTK read";

struct CommonArgs {
  std::vector<std::string> inputs;  // several: one region each (a multi-region solid)
  std::string input;                // the first
  std::vector<std::string> cracks;  // --crack: sheets the solid is cut open along
  double r = -INFINITY;  // -INFINITY: not given
  std::string seed_text = "0";
  uint64_t seed = 0;  // parsed from seed_text (cli_guards)
  double weld = -1;   // -1: not given (the library's default)
  int threads = 0;
  bool no_quality = false;
  bool convex = false;  // froth mesh --convex
  double feature_angle = froth::kDefaultFeatureAngle;
  bool repair = false;
  bool grade = false;
  double min_r = 0, max_grading = 0.2;
  double max_memory_gb = 0;  // 0: the machine's available memory
  bool quiet = false, verbose = false;

  Verbosity verbosity() const { return quiet ? Verbosity::Quiet : verbose ? Verbosity::Verbose : Verbosity::Normal; }
  froth::DomainOptions load_options() const { return {feature_angle, repair, max_memory_gb * 1e9}; }
  // The inputs read as one domain (load_regions), cut along the cracks if any are given.
  froth::Domain load() const { return froth::load_cracks(froth::load_regions(inputs, load_options()), cracks, load_options()); }
};

// Registers INPUT, --crack, -r, --seed, --weld, --threads, --no-quality, --feature-angle, --repair,
// --grade, --min-r, --max-grading, --max-memory, --quiet and --verbose on `app`; returns -r.
CLI::Option* add_common_options(CLI::App& app, CommonArgs& a);

// The options the user gave, the others left to the library's defaults (froth::MeshOptions).
froth::MeshOptions mesh_options(const CommonArgs& a);

// Refuses (Usage) an output whose extension froth does not write there: `allowed` e.g. {".vtu"},
// `what` what those files are, for the message.
void refuse_unknown_format(const std::string& option, const std::string& path, const std::vector<std::string>& allowed,
                           const std::string& what = kVtuDescription);

// Refuses (Usage) a mesh output froth::write_mesh cannot write, listing the ones it can.
void refuse_unknown_mesh_format(const std::string& option, const std::string& path);

}  // namespace froth_cli

#include "cli_options.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <fmt/format.h>

namespace froth_cli {

// A length that must be a finite number >= 0 (CLI11's own range check prints DBL_MAX in full).
const CLI::Validator kFiniteNonNegative(
    [](std::string& text) -> std::string {
      double v = 0;
      try {
        v = std::stod(text);
      } catch (const std::exception&) {
        return "not a number: " + text;
      }
      return std::isfinite(v) && v >= 0 ? "" : "must be a finite number >= 0, got " + text;
    },
    "FINITE >= 0");

CLI::Option* add_common_options(CLI::App& app, CommonArgs& a) {
  app.add_option("input", a.inputs,
                 "box:X0,Y0,Z0,X1,Y1,Z1 or a closed surface (STL, OBJ, OFF, PLY); several: one region each")
      ->required()
      ->each([&a](const std::string& s) {
        if (a.input.empty()) a.input = s;
      });
  app.add_option("--crack", a.cracks,
                 "a sheet (STL, OBJ, OFF, PLY) the solid is cut open along (a through, edge or penny crack, "
                 "or a closed sheet); repeat for several")
      ->expected(1)
      ->take_all();
  CLI::Option* radius =
      app.add_option("-r,--radius", a.r, "sampling radius r: seeds are at least r apart, every point within r of one");
  app.add_option("--seed", a.seed_text, "random seed, 0 to 2^64-1 (the mesh is a pure function of input, r and seed)")
      ->capture_default_str();
  app.add_option("--weld", a.weld,
                 "weld tolerance w: vertices joined by an edge shorter than w merge (default 1e-4 min(r, the "
                 "domain's diagonal); 0 = off)")
      ->check(kFiniteNonNegative);
  app.add_option("--threads", a.threads, "threads (default 0: all cores); never changes the result")
      ->check(CLI::Range(0, froth::kMaxThreads));
  app.add_option("--max-memory", a.max_memory_gb,
                 "refuse a run estimated to need more than this many GB (default: the memory available)")
      ->check(CLI::PositiveNumber);
  app.add_flag("--no-quality", a.no_quality, "skip the per-cell quality metrics (VTU cell data and report)");
  app.add_option("--feature-angle", a.feature_angle, "input edges turning by more than this many degrees are features")
      ->capture_default_str();
  app.add_flag("--repair", a.repair, "reorient shells whose triangles are inconsistently wound (reported)");
  CLI::Option* grade = app.add_flag("--grade", a.grade,
               "grade the radius to the input's thin walls and gaps: h(x) <= r, at least --min-r (experimental)");
  app.add_option("--min-r", a.min_r,
                 "with --grade: the smallest radius h may take (default: from r/4 up, the lowest that keeps the "
                 "estimated cells within 3 times a uniform mesh's)")
      ->check(CLI::PositiveNumber)
      ->needs(grade);
  app.add_option("--max-grading", a.max_grading,
                 "with --grade: the slope of h along its grid, in (0, 0.25) (|grad h| <= sqrt(3) times it)")
      ->capture_default_str()
      ->needs(grade);
  CLI::Option* quiet = app.add_flag("-q,--quiet", a.quiet, "print nothing on success (errors still go to stderr)");
  app.add_flag("-v,--verbose", a.verbose, "add every stage's details to the summary")->excludes(quiet);
  return radius;
}

froth::MeshOptions mesh_options(const CommonArgs& a) {
  froth::MeshOptions opt;  // the library's defaults, and what the user gave
  if (a.r != -INFINITY) opt.r = a.r;
  opt.seed = a.seed;
  if (a.weld >= 0) opt.weld = a.weld;
  opt.convex = a.convex;
  opt.threads = a.threads;
  opt.quality = !a.no_quality;
  opt.grade = a.grade, opt.min_r = a.min_r, opt.grading = a.max_grading;
  opt.max_memory_bytes = a.max_memory_gb * 1e9;
  return opt;
}

void refuse_unknown_format(const std::string& option, const std::string& path, const std::vector<std::string>& allowed,
                           const std::string& what) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (std::find(allowed.begin(), allowed.end(), ext) != allowed.end()) return;
  std::string names;
  for (const std::string& e : allowed) names += (names.empty() ? "" : ", ") + e;
  froth::fail(froth::ErrorKind::Usage,
              fmt::format("{} {}: froth cannot write {} files there; it writes {} ({}): give {} a name ending in {}",
                          option, path, ext.empty() ? "extensionless" : ext, names, what, option, allowed.front()));
}

void refuse_unknown_mesh_format(const std::string& option, const std::string& path) {
  if (froth::mesh_format_of(path) != froth::MeshFormat::Unknown) return;
  std::string ext = std::filesystem::path(path).extension().string();
  froth::fail(froth::ErrorKind::Usage,
              fmt::format("{} {}: froth cannot write {} files; it writes OUT.vtu ({}), OUT.exo (Exodus II), a "
                          "folder named polyMesh (OpenFOAM), OUT.npz (a facet graph numpy reads) and OUT.nodes (peridynamic nodes)",
                          option, path, ext.empty() ? "extensionless" : ext, kVtuDescription));
}

}  // namespace froth_cli

// froth quality: a polyhedral VTU checked and measured, with a report and histograms.
#include <filesystem>

#include <omp.h>
#include <fmt/format.h>

#include "cli_guards.hpp"
#include "commands.hpp"
#include "python_scripts.hpp"
#include "summary.hpp"
#include "froth/froth.hpp"

namespace froth_cli {
namespace {

// "mesh.vtu: r = 0.1, seed 1, 3392 cells", as far as the mesh records them.
std::string mesh_title(const std::string& path, const froth::PolyMesh& mesh) {
  std::string title = std::filesystem::path(path).filename().string();
  if (mesh.r > 0) title += fmt::format(": r = {:.4g}", mesh.r);
  if (mesh.random_seed) title += fmt::format(", seed {}", *mesh.random_seed);
  return title + fmt::format(", {} cells", mesh.cell_count());
}

}  // namespace

CLI::App* add_quality_command(CLI::App& app, QualityArgs& qa) {
  CLI::App* quality = app.add_subcommand("quality", "measure the cells of a polyhedral VTU: aspect ratios, dihedrals, edges");
  quality->add_option("mesh", qa.input, "a VTU of VTK_POLYHEDRON cells (froth's or any other writer's)")->required();
  quality->add_option("--json", qa.json, "write the quality report (JSON) here");
  quality->add_option("--plots", qa.plots, "write PNG histograms (aspect ratio by cell kind, dihedrals by class) here");
  quality->add_option("--threads", qa.threads, "threads (default 0: all cores); never changes the result")
      ->check(CLI::Range(0, 4096));
  quality->add_flag("-q,--quiet", qa.quiet, "print nothing on success");
  return quality;
}

int run_quality(const QualityArgs& a) {
  refuse_same_files({{"the mesh", a.input}, {"--json", a.json}, {"--plots", a.plots}});
  refuse_unwritable_outputs({{"--json", a.json}, {"--plots", a.plots.empty() ? "" : a.plots + "/aspect.png"}});
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
    run_python_script("quality_plots.py", {json, a.plots, mesh_title(a.input, mesh)}, false,
                                 fmt::format("draw the plots in {} (python3-matplotlib)", a.plots));
  std::vector<std::string> files;
  if (!json.empty()) files.push_back(json);
  if (!a.plots.empty()) files.push_back(a.plots + "/aspect.png, " + a.plots + "/dihedral.png");
  if (!a.quiet) fmt::print("{}", quality_summary(a.input, check, q, files));
  return 0;
}

}  // namespace froth_cli

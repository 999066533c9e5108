// froth convert: a mesh already made (a polyhedral VTU), checked, in another format.
#include <fmt/format.h>

#include "cli_guards.hpp"
#include "commands.hpp"
#include "froth/froth.hpp"

namespace froth_cli {

CLI::App* add_convert_command(CLI::App& app, ConvertArgs& ca) {
  CLI::App* convert = app.add_subcommand("convert", "write a mesh already made (a polyhedral VTU) in another format");
  convert->add_option("mesh", ca.input, "a VTU of VTK_POLYHEDRON cells")->required();
  convert->add_option("-o,--output", ca.output, "OUT.vtu, a folder named polyMesh (OpenFOAM), OUT.npz (facet graph) or OUT.nodes (peridynamic nodes)")->required();
  convert->add_flag("-q,--quiet", ca.quiet, "print nothing on success");
  return convert;
}

// A mesh already written (froth's VTU, or any polyhedral VTU) in another format.
int run_convert(const ConvertArgs& a) {
  refuse_same_files({{"the mesh", a.input}, {"-o", a.output}});
  refuse_unknown_mesh_format("-o", a.output);
  refuse_unwritable_outputs({{"-o", a.output}});
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

}  // namespace froth_cli

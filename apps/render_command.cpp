// froth render: a PNG of a mesh cut open at the middle (VTK, offscreen).
#include <filesystem>
#include <string>

#include <fmt/format.h>

#include "cli_guards.hpp"
#include "commands.hpp"
#include "python_scripts.hpp"
#include "froth/froth.hpp"

namespace froth_cli {

CLI::App* add_render_command(CLI::App& app, RenderArgs& ra) {
  CLI::App* render = app.add_subcommand("render", "draw a mesh cut open at the middle as a PNG (VTK, offscreen)");
  render->add_option("mesh", ra.input, "a VTU of VTK_POLYHEDRON cells")->required();
  render->add_option("-o,--output", ra.output, "the PNG to write")->required();
  render->add_option("--color", ra.colour, "colour by cell kind or by this cell array (aspect, volume, radius, ...)")
      ->capture_default_str();
  render->add_option("--width", ra.width, "image width in pixels")->capture_default_str()->check(CLI::Range(64, 8192));
  render->add_option("--height", ra.height, "image height in pixels")->capture_default_str()->check(CLI::Range(64, 8192));
  render->add_flag("-q,--quiet", ra.quiet, "print nothing on success");
  return render;
}

// A PNG of the mesh cut open at the middle (scripts/render_mesh.py, VTK offscreen), written to a
// temporary name and renamed on success.
int run_render(const RenderArgs& a) {
  refuse_same_files({{"the mesh", a.input}, {"-o", a.output}});
  refuse_unknown_format("-o", a.output, {".png"}, "PNG images");
  refuse_unwritable_outputs({{"-o", a.output}});
  froth::read_vtu(a.input);  // a clear error (exit 3 or 4) for a file that is not a polyhedral VTU
  // (The PNG's folder is made as every output's is; VTK names no reason when it cannot write.)
  std::filesystem::create_directories(std::filesystem::absolute(a.output).parent_path());
  froth::write_atomically_by_name(
      a.output,
      [&](const std::filesystem::path& tmp) {
        run_python_script("render_mesh.py",
                                     {a.input, tmp.string(), a.colour, std::to_string(a.width), std::to_string(a.height)},
                                     true, fmt::format("render {} (python3-vtk9)", a.input));
      },
      ".png");
  if (!a.quiet) fmt::print("froth: rendered {}\n  {:<10}{}\n", a.input, "wrote", a.output);
  return 0;
}

}  // namespace froth_cli

// froth's Python helpers (scripts/): the quality plots and the mesh picture, run with Debian's
// /usr/bin/python3 (matplotlib, VTK), found beside an installed froth or in the source tree.
#pragma once
#include <string>
#include <vector>

namespace froth_cli {

// The path of scripts/NAME: PREFIX/share/froth/NAME beside an installed froth program, else the
// source tree's scripts folder (a build tree). Io error if neither exists.
std::string script_path(const std::string& name);

// Runs /usr/bin/python3 SCRIPT ARGS... and waits; under xvfb-run when `needs_display` and there
// is no X display (VTK renders offscreen through one). Io error naming `what` if it fails.
void run_python_script(const std::string& name, const std::vector<std::string>& args, bool needs_display,
                       const std::string& what);

}  // namespace froth_cli

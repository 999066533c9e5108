// Outputs are written to a temporary name beside the target and renamed on success, so a
// failed or interrupted run never leaves a half-written file under the real name. A target that
// is a device or a pipe (/dev/null, /dev/stdout) is written in place; a symbolic link keeps
// pointing at its (replaced) target.
#pragma once
#include <filesystem>
#include <fstream>
#include <functional>

#include "froth/io.hpp"

namespace froth {

void write_atomically(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write);

}  // namespace froth

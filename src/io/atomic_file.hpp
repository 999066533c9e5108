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

// The same for a writer that opens files by name (a library such as Exodus II): `write` is given
// the temporary path to create; it is renamed into place (or deferred, in an OutputGroup) when
// `write` returns, and removed when it throws.
void write_atomically_by_name(const std::filesystem::path& path,
                              const std::function<void(const std::filesystem::path& tmp)>& write);

}  // namespace froth

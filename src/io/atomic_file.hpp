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

// PATH.tmpPID (PATH.tmpPIDEXTENSION with an extension), after removing the temporaries of PATH
// that processes no longer running left (a SIGKILL'd run's).
std::filesystem::path temporary_name(const std::filesystem::path& path, const std::string& extension = "");

// Makes `folder` and its missing parents. Within an OutputGroup they are removed again (when
// empty) if the group is not committed, and by the signal handler: no empty folders are left.
void make_output_folder(const std::filesystem::path& folder);

}  // namespace froth

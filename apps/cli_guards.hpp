// The command line's guards against losing data and against arguments that do not mean what
// they say: outputs that would overwrite an input or each other, seeds beyond 64 bits, and
// failures of the file system mapped to their exit code.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace froth_cli {

// Refuses (froth::Error, Usage) when two of the named paths are the same file: {what, path},
// empty paths and box specs skipped. E.g. {{"the input", in}, {"-o", out}, {"--report", rep}}.
void refuse_same_files(const std::vector<std::pair<std::string, std::string>>& paths);

// Refuses (froth::Error, Io) before any work when an output cannot be written: the nearest
// folder of each {what, path} that exists (a polyMesh folder's case may not yet) must be a
// folder where a file can be made. Tried by making one, as root passes every permission test.
void refuse_unwritable_outputs(const std::vector<std::pair<std::string, std::string>>& paths);

// An unsigned 64-bit seed in decimal; Usage error naming the value otherwise (CLI11 would clamp
// 2^64 to 2^64 - 1 and wrap a negative one around).
uint64_t parse_seed(const std::string& text);

// Runs `body` and turns what it throws into a message on stderr and an exit code: froth::Error
// by its kind, file system errors 4, out of memory and anything else 5. `where`: " (rank K)".
int run_with_exit_codes(const std::function<int()>& body, const std::string& where = "");

}  // namespace froth_cli

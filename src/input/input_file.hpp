// An input surface file's bytes, read within bounds: a file is refused before it is read when it
// is larger than the memory it may take, and a device or pipe (/dev/zero) is read only until the
// file could no longer be what its first bytes say it is.
#pragma once
#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

namespace froth {

// From a file's first bytes (up to 4 KiB): the most bytes a file of this format that starts so
// can hold (SIZE_MAX: no bound but memory). Throws Error(InvalidInput) for a start that cannot be
// this format.
using SizeFromHead = std::function<size_t(std::string_view head)>;

// The file's bytes may take a quarter of the memory (`max_memory_bytes`, 0: the memory
// available): the surface made from them and its checks take the rest.
std::string read_input_file(const std::filesystem::path& path, double max_memory_bytes, const SizeFromHead& size_from_head);

// Refuses (InvalidInput) a text format's start that holds a NUL byte (`text_end`: where the text
// ends, as a binary PLY's header does): binary data or a zeroed file, not `format`.
void refuse_binary_text(const std::string& file, std::string_view head, const char* format,
                        size_t text_end = std::string_view::npos);

// Text quoted from a file in a message: at most 60 characters, bytes that do not print as \xNN
// (a NUL would otherwise end the message).
std::string quoted_text(std::string_view text);

}  // namespace froth

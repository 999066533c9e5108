// The process's memory, as each stage's report records it.
#pragma once
#include <cstddef>

namespace froth {

// The process's peak resident memory so far (Linux VmHWM), in bytes; 0 where unknown.
size_t peak_rss_bytes();

}  // namespace froth

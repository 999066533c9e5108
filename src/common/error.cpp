#include "froth/error.hpp"

namespace froth {
void fail(ErrorKind kind, const std::string& message) { throw Error(kind, message); }
}  // namespace froth

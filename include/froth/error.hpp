// Errors the library returns (by exception); the CLI maps each kind to an exit code.
#pragma once
#include <stdexcept>
#include <string>

namespace froth {

enum class ErrorKind {
  Usage = 2,         // bad parameters (r <= 0, malformed box spec, ...)
  InvalidInput = 3,  // the input surface is unreadable or not a valid domain
  Io = 4,            // a file could not be read or written
  Internal = 5,      // a guarantee failed inside froth: a bug, never the user's fault
  Interrupted = 130, // MeshOptions::interrupted asked the run to stop (130: as for SIGINT)
};

class Error : public std::runtime_error {
 public:
  Error(ErrorKind kind, const std::string& message) : std::runtime_error(message), kind_(kind) {}
  ErrorKind kind() const { return kind_; }
  int exit_code() const { return static_cast<int>(kind_); }

 private:
  ErrorKind kind_;
};

[[noreturn]] void fail(ErrorKind kind, const std::string& message);

}  // namespace froth

// Progress on a terminal: one line on stderr, rewritten in place, with the stage, a bar, the
// percent done and the time left; nothing when stderr is not a terminal (a pipe, a log file).
#pragma once
#include <chrono>
#include <functional>
#include <string>

namespace froth_cli {

class ProgressBar {
 public:
  // Draws only if `enabled` and stderr is a terminal.
  explicit ProgressBar(bool enabled);
  ~ProgressBar();  // clears the line
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  // For MeshOptions::progress and EnsembleOptions::progress (or empty when not drawing).
  std::function<void(const std::string&, double)> callback();
  void clear();  // before printing anything else

 private:
  void update(const std::string& stage, double fraction);
  bool drawing_ = false, shown_ = false;
  std::string stage_;
  std::chrono::steady_clock::time_point stage_start_, last_draw_;
};

}  // namespace froth_cli

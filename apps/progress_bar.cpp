#include "progress_bar.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

#include <fmt/format.h>

namespace froth_cli {

ProgressBar::ProgressBar(bool enabled) : drawing_(enabled && isatty(STDERR_FILENO)) {}

ProgressBar::~ProgressBar() { clear(); }

std::function<void(const std::string&, double)> ProgressBar::callback() {
  if (!drawing_) return {};
  return [this](const std::string& stage, double fraction) { update(stage, fraction); };
}

void ProgressBar::clear() {
  if (!shown_) return;
  fmt::print(stderr, "\r\033[K");
  std::fflush(stderr);
  shown_ = false;
}

void ProgressBar::update(const std::string& stage, double fraction) {
  const auto now = std::chrono::steady_clock::now();
  if (stage != stage_) {
    stage_ = stage, stage_start_ = now;
  } else if (now - last_draw_ < std::chrono::milliseconds(100)) {
    return;  // ten frames a second at most
  }
  last_draw_ = now;
  shown_ = true;
  if (fraction <= 0) {  // a stage begins: its name until it says how far it is
    fmt::print(stderr, "\r\033[Kfroth: {}...", stage);
    std::fflush(stderr);
    return;
  }
  fraction = std::min(fraction, 1.0);
  constexpr int kWidth = 30;
  const int filled = int(fraction * kWidth);
  const double elapsed = std::chrono::duration<double>(now - stage_start_).count();
  // The time left by the rate so far, once there is a rate to go by.
  const std::string left = fraction > 0.02 && elapsed > 0.5
                               ? fmt::format("  {:.0f} s left", elapsed * (1 - fraction) / fraction)
                               : "";
  fmt::print(stderr, "\r\033[Kfroth: {:<12} [{}{}] {:3.0f}%{}", stage, std::string(size_t(filled), '#'),
             std::string(size_t(kWidth - filled), ' '), 100 * fraction, left);
  std::fflush(stderr);
}

}  // namespace froth_cli

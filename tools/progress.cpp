#include "tools/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

#include "sdcb/core/common/progress.h"

namespace sdcb::cli {

ProgressBar::ProgressBar(std::string command, bool quiet)
    : command_(std::move(command)),
      enabled_(!quiet && ::isatty(STDERR_FILENO)),
      start_(std::chrono::steady_clock::now()),
      pass_start_(start_) {}

ProgressBar::~ProgressBar() { Finish(); }

void ProgressBar::Update(const std::string& stage, double fraction) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (fraction < 0.5 * last_fraction_) pass_start_ = now;
  last_fraction_ = fraction;
  if (drawn_ && fraction < 1.0 &&
      now - last_draw_ < std::chrono::milliseconds(100)) {
    return;
  }
  last_draw_ = now;
  drawn_ = true;
  fraction = std::clamp(fraction, 0.0, 1.0);
  constexpr int kWidth = 28;
  const int filled = static_cast<int>(fraction * kWidth + 0.5);
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double pass = std::chrono::duration<double>(now - pass_start_).count();
  char eta[32] = "";
  if (fraction > 0.02 && fraction < 1.0) {
    std::snprintf(eta, sizeof eta, " ETA %.0fs",
                  pass * (1 - fraction) / fraction);
  }
  std::fprintf(stderr, "\r%s [%s%s] %3.0f%% %-25s %5.1fs%-10s",
               command_.c_str(), std::string(filled, '#').c_str(),
               std::string(kWidth - filled, '.').c_str(), 100 * fraction,
               stage.c_str(), elapsed, eta);
  std::fflush(stderr);
}

void ProgressBar::Finish() {
  if (enabled_ && drawn_) {
    std::fprintf(stderr, "\n");
    std::fflush(stderr);
  }
  drawn_ = false;
  enabled_ = false;
}

ProgressCallback ProgressBar::Callback() {
  return [this](const std::string& stage, double fraction) {
    Update(stage, fraction);
  };
}

}  // namespace sdcb::cli

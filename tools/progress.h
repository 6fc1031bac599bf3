// A progress bar on stderr for long commands: stage name, bar, percentage
// and ETA, redrawn in place. Shown only when stderr is a terminal and the
// user did not pass --quiet; otherwise every call is a no-op.
#ifndef SDCB_TOOLS_PROGRESS_H_
#define SDCB_TOOLS_PROGRESS_H_

#include <chrono>
#include <functional>
#include <string>

#include "sdcb/core/common/progress.h"

namespace sdcb::cli {

class ProgressBar {
 public:
  // `command` prefixes the line ("sdcb fit").
  ProgressBar(std::string command, bool quiet);
  ~ProgressBar();  // finishes the line if anything was drawn

  bool enabled() const { return enabled_; }
  // Draws stage and fraction (0..1); rate-limited to ~10 redraws a second.
  // A fraction that falls below half the last (a second pass, as the fit's
  // second fit on the split input) starts the ETA's clock again; the elapsed
  // time runs on.
  void Update(const std::string& stage, double fraction);
  // Ends the line (before printing anything else to stderr).
  void Finish();
  // A callback for library options structs.
  ProgressCallback Callback();

 private:
  std::string command_;
  bool enabled_ = false;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_, last_draw_, pass_start_;
  double last_fraction_ = 0.0;
};

}  // namespace sdcb::cli

#endif  // SDCB_TOOLS_PROGRESS_H_

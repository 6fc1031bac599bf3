// Wall-clock seconds since a start: the "seconds" of the fit's and the
// converters' reports.
#ifndef SDCB_CORE_COMMON_STOPWATCH_H_
#define SDCB_CORE_COMMON_STOPWATCH_H_

#include <chrono>

namespace sdcb {

class Stopwatch {
 public:
  // Seconds since construction or the last Restart.
  double Seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                         start_)
        .count();
  }
  void Restart() { start_ = std::chrono::steady_clock::now(); }

 private:
  std::chrono::steady_clock::time_point start_ =
      std::chrono::steady_clock::now();
};

}  // namespace sdcb

#endif  // SDCB_CORE_COMMON_STOPWATCH_H_

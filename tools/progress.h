// A one-line progress bar on stderr, shown only when stderr is a terminal and the work has
// already taken over a second (so quick runs and logs stay clean).
#pragma once

#include <chrono>
#include <string>

namespace meshlift::cli {

class ProgressBar {
 public:
  explicit ProgressBar(std::string label);
  ~ProgressBar();  ///< clears the line if one was drawn
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  /// Reports `fraction` in [0, 1] of the work done; redraws at most ten times a second.
  void update(double fraction);

 private:
  std::string label_;
  bool terminal_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_, last_draw_;
};

}  // namespace meshlift::cli

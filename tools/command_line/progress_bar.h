// A one-line progress bar on stderr, drawn only when stderr is a terminal. Shared by the command
// line tools (mocapd, mocap).
#pragma once

#include <chrono>
#include <string>

namespace mocap {

class ProgressBar {
 public:
  ProgressBar(std::string label, long total, bool enabled);
  ~ProgressBar();
  // Redraws at most ~10 times a second; `detail` follows the counts (e.g. "48,000 frames/s").
  void Update(long done, const std::string& detail);
  void SetTotal(long total) { total_ = total; }
  void Finish();

 private:
  std::string label_;
  long total_;
  bool enabled_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point last_draw_{};
};

}  // namespace mocap

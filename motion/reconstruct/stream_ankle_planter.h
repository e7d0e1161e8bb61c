// The stream's counterpart of PlantAnkleContacts (docs/method.md A7, "planted at the mean"): at a
// fixed lag no contact is seen whole, so each decided A4 ankle estimate is planted as it comes.
// While the cleanup's rule says a foot is planted (a ground-plane step slower than
// `contact_speed`, at most `contact_height` above the planted ankle height; held over
// `stream_hold_seconds`, as FootskateCleaner holds it), the estimate becomes the mean of the
// estimates since the contact began: each frame's ankles are another candidate of the A4 cloud,
// one noisy sample of where the foot stands, and A6 then places the pelvis over feet that stand
// still rather than over their wobble (and the cleanup, reading these, sees one contact where the
// wobble broke it into several). A foot that never lifts does not step while the body stands (the
// hands' midpoint moved slower than `standing_hands_speed` on average over each of the last
// kHandsWindowsSeconds, the guard's windows): its contact goes on however the estimate slides with
// the hands (every A4 candidate is placed in the wrists' frame). When a contact ends the estimate
// returns from the mean over `release_frames` frames. Causal and allocation-free.
#pragma once

#include <array>

#include <Eigen/Core>

#include "motion/core/recent_values.h"
#include "motion/reconstruct/ankle_path.h"
#include "motion/reconstruct/footskate_cleanup.h"

namespace mocap {

class StreamAnklePlanter {
 public:
  // `standing_hands_speed`: m/s (0 = contacts are never held by standing hands).
  StreamAnklePlanter(float planted_ankle_height, double frame_time, const FootskateOptions& options,
                     float standing_hands_speed);

  // The next decided frame's ankles (A4, smoothed; world metres), rewritten where planted;
  // `hands`: the input wrists (left, right) over the ground at that frame.
  void Next(AnklePair* ankles, const std::array<Eigen::Vector2f, 2>& hands);

 private:
  struct Foot {
    bool planted = false;
    Eigen::Vector3f sum = Eigen::Vector3f::Zero();  // of the estimates since the contact began
    int frames = 0;
    Eigen::Vector3f release_offset = Eigen::Vector3f::Zero();
    int release_left = 0;
  };
  bool Stands() const;
  // Whether the ground point `at(b)` (b frames back) moved slower than `standing_speed_` over
  // both of the guard's windows.
  template <typename At>
  bool StandsOver(At at) const;

  float planted_height_, rate_;
  FootskateOptions options_;
  float standing_speed_;
  int hold_frames_, short_frames_, standing_frames_;
  std::array<Foot, 2> feet_;
  RecentValues<AnklePair> estimates_;                   // the last estimates as decided (before planting)
  RecentValues<std::array<Eigen::Vector2f, 2>> hands_;  // the hands over the last standing window
};

}  // namespace mocap

// GripOffset: a device held in the hand, tracked without its orientation (issue #22: devices never
// seen). A phone in a closed grip or a controller's handle sits in the palm, some 8–10 cm beyond
// the wrist joint along the forearm, so the tracked point is not the wrist the database's features
// and the A6 solve speak of: read as a wrist it lengthens every arm by that much (mocap-eval's
// `phone_in_hand` device: landmark error 10.1 → 15.9 cm). Declared (ReconstructionOptions::
// grip_offset), each A2-smoothed device point goes back that far along the forearms of the database
// frames nearest the previous frame's query (the first frame of a segment: of its own nearest,
// once), in the query's reference frame, and the final arm IK reaches the device with the forearm
// extended past the wrist (docs/method.md A2).
//
// Thread safety: one per segment of one session.
#pragma once

#include <array>
#include <optional>
#include <span>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "motion/reconstruct/ankle_cloud.h"
#include "motion/reconstruct/reconstruction_database.h"
#include "motion/reconstruct/wrist_smoother.h"

namespace mocap {

// Unit vectors from each elbow to its wrist (left, right) of database row `row`, in the row's own
// wrist reference frame (A1). Zero where the rig's landmarks give no elbow or the two coincide.
std::array<Eigen::Vector3f, 2> RowForearms(const ReconstructionDatabase& database, int row);

class GripOffset {
 public:
  // `metres`: the tracked point's distance beyond the wrist (0: the input is the wrist).
  explicit GripOffset(float metres) : metres_(metres) {}
  bool active() const { return metres_ > 0.0f; }
  // Whether a forearm is known yet (a segment's first frame has none: the caller reads it from the
  // nearest row of the device points themselves, then calls ToWrists).
  bool knows_forearms() const { return forearms_.has_value(); }
  // The forearms of the database rows nearest the frame's query (the first kRows of `nearest_first`,
  // its cloud), their mean direction: what the next frame's points go back along.
  void Remember(const ReconstructionDatabase& database, std::span<const AnkleCandidate> nearest_first);
  // `points`: the A2-smoothed device points, becoming the wrists they imply (positions only:
  // velocities corrected by the remembered forearms' turn were worse, docs/evaluation.md stop 64).
  // `heading`: the reference frame's (A3's cloud heading), read, not updated. No change before a
  // forearm is known.
  void ToWrists(float heading, SmoothedWrists* points);
  // The same for the hands' final targets, along the forearms of the body about to reach for them
  // (`world_positions`: its joints').
  void ToWrists(const BodyModel& body, const std::vector<Eigen::Vector3f>& world_positions,
                SmoothedWrists* points) const;
  float metres() const { return metres_; }  // how far past the wrist the arm IK reaches (SolveLegIk's `beyond`)

 private:
  float metres_;
  std::optional<std::array<Eigen::Vector3f, 2>> forearms_;  // in the reference frame
  // The forearms the wrists were taken back along (world), following the nearest rows' by
  // kFollow of the way each frame.
  static constexpr float kFollow = 0.25f;
  static constexpr size_t kRows = 10;
  std::array<Eigen::Vector3f, 2> world_forearms_{Eigen::Vector3f::Zero(), Eigen::Vector3f::Zero()};
};

}  // namespace mocap

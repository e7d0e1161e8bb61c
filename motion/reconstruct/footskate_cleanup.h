// Footskate cleanup of docs/method.md A7 (in the manner of Kovar, Schreiner & Gleicher 2002), causal so
// that the stream and the offline path share it. Which foot is planted comes either from the
// captured database frame the A4 path chose for this frame (its foot was planted: the contact
// labels motion-matching systems use) or from the estimated ankle itself. Either way "planted" is
// a ground-plane ankle speed below `contact_speed` at most `contact_height` above the database's
// planted ankle height. While planted the ankle is pinned where the contact began and the leg is
// solved by two-bone inverse kinematics (hip and knee turn; the foot keeps its world orientation).
// When the contact ends the correction fades out over `release_frames` frames.
#pragma once

#include <array>
#include <optional>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "motion/reconstruct/ankle_path.h"
#include "motion/reconstruct/body_model.h"
#include "motion/reconstruct/database_frame.h"

namespace mocap {

enum class ContactSource {
  kDatabaseFrame,    // the chosen database frame's captured foot (full method only)
  kEstimatedAnkles,  // the A4 ankle estimate's own speed and height
  kBoth,             // both must say planted
};

struct FootskateOptions {
  bool enabled = true;
  // Measured on mocap-eval --quick: the database frame's contacts cut skating most (0.20 vs 0.33
  // cm/frame) but cost lower-body accuracy (7.5 vs 6.7 cm); the estimate keeps accuracy.
  ContactSource contact_source = ContactSource::kEstimatedAnkles;
  float contact_speed = 0.30f;   // m/s, ground-plane ankle speed
  float contact_height = 0.06f;  // m above the planted ankle height
  int release_frames = 4;
  // Where a contact pins its foot: at the mean of the ankle estimate over the whole contact, when
  // the frames after it show where the contact ends (always offline; when streaming, a contact
  // short enough for the lag's look-ahead), rather than where the contact began. The estimate
  // wanders about the planted place from frame to frame (a new candidate of the ankle cloud each
  // frame), so its first frame is one noisy sample of it (standard split, whole clip: MPJPE 2.174
  // → 2.065 cm). The foot eases towards that pin over the `release_frames` frames before the
  // contact, while it still swings, so that it does not jump there when it lands. False: where
  // the contact began.
  bool pin_at_contact_mean = true;
  // Only for contacts at least this long: a shorter one's pin, eased in and out, is a bump in the
  // leg's path (0 s: 2.048 cm but joint jitter 1.41 → 1.48 × the capture's, and the jerk after a
  // 2 s dropout 1.97 → 2.16 ×; 0.5 s: 1.42 and 2.01).
  float mean_pin_min_seconds = 0.5f;
};

// The ankle estimates of the frames after the one being cleaned, as far as they are known: the
// decided ones, then the tentative continuation (fixed lag).
struct AnkleLookahead {
  std::span<const AnklePair> decided, tentative;
  bool complete = false;  // no frame follows them: the segment ends
  // The k-th frame after the one being cleaned; nullptr beyond what is known.
  const AnklePair* at(size_t k) const {
    if (k < decided.size()) return &decided[k];
    k -= decided.size();
    return k < tentative.size() ? &tentative[k] : nullptr;
  }
};

// Moves `pose` so that the ankle (the leg's end joint) reaches `target`: analytic two-bone IK on
// the ankle's parent (knee) and grandparent (hip). Out-of-reach targets stretch the leg straight
// towards them.
void SolveLegIk(const BodyModel& body, int ankle_joint, const Eigen::Vector3f& target, BodyPose* pose);

// Whether each foot of a captured database frame is planted (ground-plane speed and height).
std::array<bool, 2> PlantedFeet(const DatabaseFrame& frame, float planted_ankle_height,
                                const FootskateOptions& options);

class FootskateCleaner {
 public:
  FootskateCleaner(const BodyModel& body, float planted_ankle_height, double frame_time,
                   const FootskateOptions& options);

  // Where the leg IK put each ankle this frame (a pin, or a release step); none when untouched.
  using AnkleTargets = std::array<std::optional<Eigen::Vector3f>, 2>;

  // Next frame: `estimated_ankles` are the A4 ankle controls, `source_frame` the database frame
  // the A4 path chose (nullptr: contacts from the estimate whatever the option). Adjusts `pose`;
  // returns the contact flags [left, right]; `targets` (optional) gets the IK targets, so that a
  // later joint-space filter can re-impose them.
  // `ahead`: the estimates of the frames after this one (FootskateOptions::pin_at_contact_mean).
  std::array<bool, 2> Process(const std::array<Eigen::Vector3f, 2>& estimated_ankles, const DatabaseFrame* source_frame,
                              BodyPose* pose, AnkleTargets* targets = nullptr, const AnkleLookahead& ahead = {});
  void Reset();

 private:
  struct Foot {
    bool planted = false;
    Eigen::Vector3f pin = Eigen::Vector3f::Zero();
    Eigen::Vector3f release_offset = Eigen::Vector3f::Zero();
    int release_left = 0;
    bool has_previous = false;
    Eigen::Vector3f previous = Eigen::Vector3f::Zero();
  };
  const BodyModel& body_;
  float planted_height_;
  float rate_;
  FootskateOptions options_;
  // The mean of one foot's estimate over the contact that begins at `landing` (that frame and
  // those of `ahead` from `from` on that continue it); none when `ahead` ends before the contact.
  std::optional<Eigen::Vector3f> ContactMean(int side, const Eigen::Vector3f& landing, const AnkleLookahead& ahead,
                                             size_t from) const;
  // The offset of the pin from the landing estimate (FootskateOptions::pin_at_contact_mean) of a
  // contact the look-ahead shows beginning within `release_frames`, eased in by how near it is.
  Eigen::Vector3f ApproachOffset(int side, const Eigen::Vector3f& estimate, const AnkleLookahead& ahead) const;
  // The estimate rule of a contact: a ground-plane step slower than contact_speed, low enough.
  bool EstimateSaysPlanted(const Eigen::Vector3f& previous, const Eigen::Vector3f& estimate) const;

  std::array<Foot, 2> feet_;
  std::vector<Eigen::Quaternionf> rotations_;
  std::vector<Eigen::Vector3f> positions_;
};

}  // namespace mocap

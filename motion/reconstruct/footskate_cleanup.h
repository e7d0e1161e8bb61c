// Footskate cleanup of docs/method.md A7 (in the manner of Kovar, Schreiner & Gleicher 2002), causal so
// that the stream and the offline path share it. Which foot is planted comes either from the
// captured database frame the A4 path chose for this frame (its foot was planted: the contact
// labels motion-matching systems use) or from the estimated ankle itself. Either way "planted" is
// a ground-plane ankle speed below `contact_speed` at most `contact_height` above the database's
// planted ankle height. While planted the ankle is pinned where the contact began and the leg is
// solved by two-bone inverse kinematics (hip and knee turn; the foot keeps its world orientation).
// When the contact ends the correction fades out over `release_frames` frames. In a stream (a
// fixed lag: no contact is seen whole) a planted foot stays planted until its estimate has moved
// faster than `contact_speed` on average over `stream_hold_seconds`, and its pin follows the mean
// of the estimate over the contact so far.
#pragma once

#include <array>
#include <optional>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "motion/core/recent_values.h"
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
  // A foot is planted where both say so (stop 50; docs/method.md A7): the estimate's own speed
  // holds every change of the A4 path's mind (a stream decides each frame on a new best path),
  // the chosen frame's contacts are a database actor's feet. Standard split lag 5 / lag 0:
  // 2.1904 / 2.9626 cm with the estimate alone, 2.1731 / 2.9415 with both; the database frame
  // alone measured best in the lab (2.1616 / 2.9396) and worst off it (cross-dataset lag 5
  // 16.224 → 16.659 cm).
  ContactSource contact_source = ContactSource::kBoth;
  float contact_speed = 0.30f;   // m/s, ground-plane ankle speed
  float contact_height = 0.06f;  // m above the planted ankle height
  int release_frames = 4;
  // A contact that begins while the last one's release is under way (the estimate broke for a frame
  // or a few) begins where the released foot is, not where that frame's solve put the ankle: a
  // solve that drifted under the planted foot slid it there along the ground in one frame (stop 78;
  // development split lag 5 / lag 0: skate 0.164 / 0.309 -> 0.152 / 0.295 cm/frame, MPJPE 2.1094 /
  // 2.6606 -> 2.1014 / 2.6581 cm).
  bool resume_where_released = true;
  // PlantAnkleContacts: contacts at least this long are planted at their mean (0 = none).
  float plant_min_seconds = 0.5f;
  // Streams only (FootskateCleaner's `streaming`; whole clips and windows are planted at their
  // contacts' means first). The estimate of a planted foot wobbles about where it stands from
  // frame to frame (each frame's ankles are another candidate of the cloud), so one frame's step
  // ended a contact and its first frame set the pin: a contact ends when the estimate's mean
  // ground speed over this span is above `contact_speed` (0: over one frame), and the pin goes
  // where the estimate has been on average since the contact began. Development split, fixed lag 5
  // (docs/method.md A7): MPJPE 2.276 -> 2.267 cm, skate 0.350 -> 0.311 cm/frame, jitter 171 -> 158.
  float stream_hold_seconds = 0.1f;
  bool stream_pin_at_mean = true;
  // Streams only: the decided A4 ankles planted at their contacts' running means before A6
  // (StreamAnklePlanter), as whole clips plant theirs (PlantAnkleContacts).
  bool stream_plant_ankles = true;
  // Streams only: a planted foot that has not lifted is held while either hand stands, not only
  // the hands' midpoint: a hand that waves or rises faster than the other moves the midpoint, and
  // the wrists' frame every A4 candidate is placed in, while the stiller hand still stands, and the
  // stream (unlike a whole clip's path) followed the sliding estimate into a step the body never
  // took (docs/evaluation.md stop 82).
  bool stream_stands_on_either_hand = true;
};

// The planted feet of a stretch of A4 ankle estimates (docs/method.md A7, "planted at the mean"):
// the estimate wanders about where a planted foot stands, from frame to frame (each frame's
// ankles are another candidate of the cloud), so each of its frames is one noisy sample of that
// place. Every contact (the cleanup's rule: a ground-plane step slower than `contact_speed`, at
// most `contact_height` above the planted height) whose whole length the stretch shows and that
// lasts `plant_min_seconds` or more is set to its mean, eased in over the `release_frames` frames
// before it and out over those after it. Contacts the stretch does not show whole are left as
// they are: one that began before it (`before` is the estimate of the frame before, nullptr at a
// segment's start), or that goes on past its end unless `segment_ends`, or whose easing would
// reach outside it.
//
// A foot that never lifts does not step: two contacts of one foot are one contact when the
// estimate stays within `contact_height` of the planted height all the way between them while the
// body stands — the input wrists' midpoint (`standing.midpoints`, one per frame of the stretch,
// over the ground) moved slower than `standing.speed` on average over the kHandsWindowsSeconds[1]
// about the gap. The estimate then slid with the hands (a standing body's gestures move every A4
// candidate, eq. 2, placed in the wrists' frame), not the foot. A walk's hands travel; its feet
// lift or, where the estimate slid along with them, are left to the path.
struct StandingHands {
  std::span<const Eigen::Vector2f> midpoints;  // empty: no contacts are joined
  float speed = 0;                             // m/s
};
void PlantAnkleContacts(std::span<std::array<Eigen::Vector3f, 2>> ankles, const std::array<Eigen::Vector3f, 2>* before,
                        bool segment_ends, float planted_ankle_height, double frame_time,
                        const FootskateOptions& options, const StandingHands& standing = {});

// A foot's A7 pins eased by a joint-space filter's kernel (the filter that looks ahead: fixed
// lags of a frame or more, sub-intervals, whole clips). `pins` holds, for each frame the kernel
// reaches (kernel.size() of them, the frame itself in the middle), the foot's pin where it is
// planted and nothing where it is free. The foot goes to the kernel's mean of the pins by the
// kernel's weight of the planted frames (its positive lobes only: the negative ones would push a
// foot past its pin): inside a contact the kernel covers, the pin itself by 1; about its ends a
// fraction that rises and falls as the filtered body does. A foot the cleaner released follows
// the filtered body instead of the release's steps, which follow the unfiltered solve (issue #25:
// a new segment's first solves hop, and the released foot hopped with them). None when no frame
// the kernel reaches is planted.
struct EasedPin {
  Eigen::Vector3f target;
  float weight;  // (0, 1]: the fraction of the way from where the body puts the foot to `target`
};
std::optional<EasedPin> EasePin(std::span<const float> kernel, std::span<const std::optional<Eigen::Vector3f>> pins);

// Moves `pose` so that the ankle (the leg's end joint) reaches `target`: analytic two-bone IK on
// the ankle's parent (knee) and grandparent (hip). Out-of-reach targets stretch the leg straight
// towards them. `beyond`: the point that reaches it lies this far past the end joint, along the
// lower bone (a device gripped beyond the wrist, grip_offset.h); 0: the end joint itself.
void SolveLegIk(const BodyModel& body, int ankle_joint, const Eigen::Vector3f& target, BodyPose* pose,
                float beyond = 0.0f);

// SolveLegIk for a leg whose knee must stay on or above the floor: where reaching `target` would
// put the knee under `knee_floor` (world height), and lower than it was, the ankle goes only the
// largest part of the way from where it is that keeps the knee up (a bisection to 1/64). The body
// is not moved: lifting it instead made a one-frame jump of the pelvis. Returns the part taken,
// in [0, 1].
float SolveLegIkKneeAboveFloor(const BodyModel& body, int ankle_joint, const Eigen::Vector3f& target, float knee_floor,
                               BodyPose* pose);

// The cleanup's rule for a contact by the estimate: a ground-plane step slower than
// `contact_speed` into `estimate` from `previous` (`rate` steps a second), at most
// `contact_height` above the planted ankle height.
bool EstimateSaysPlanted(const Eigen::Vector3f& previous, const Eigen::Vector3f& estimate, float planted_ankle_height,
                         float rate, const FootskateOptions& options);

// Whether each foot of a captured database frame is planted (ground-plane speed and height).
std::array<bool, 2> PlantedFeet(const DatabaseFrame& frame, float planted_ankle_height,
                                const FootskateOptions& options);

class FootskateCleaner {
 public:
  // `streaming`: a fixed lag (the stream_* options apply).
  FootskateCleaner(const BodyModel& body, float planted_ankle_height, double frame_time,
                   const FootskateOptions& options, bool streaming = false);

  // Where the leg IK put each ankle this frame (a pin, or a release step); none when untouched.
  using AnkleTargets = std::array<std::optional<Eigen::Vector3f>, 2>;

  // Next frame: `estimated_ankles` are the A4 ankle controls, `source_frame` the database frame
  // the A4 path chose (nullptr: contacts from the estimate whatever the option). Adjusts `pose`;
  // returns the contact flags [left, right]; `targets` (optional) gets the IK targets, so that a
  // later joint-space filter can re-impose them.
  std::array<bool, 2> Process(const std::array<Eigen::Vector3f, 2>& estimated_ankles, const DatabaseFrame* source_frame,
                              BodyPose* pose, AnkleTargets* targets = nullptr);
  void Reset();

 private:
  struct Foot {
    bool planted = false;
    Eigen::Vector3f pin = Eigen::Vector3f::Zero();
    Eigen::Vector3f release_offset = Eigen::Vector3f::Zero();
    int release_left = 0;
    // The last estimates (while a frame is processed, recent.Back(0) is the one before its own), and
    // in streams the contact's so far.
    static constexpr size_t kRecentFrames = 16;
    RecentValues<Eigen::Vector3f> recent{kRecentFrames};
    Eigen::Vector3f contact_start_estimate = Eigen::Vector3f::Zero();
    Eigen::Vector3f contact_estimate_sum = Eigen::Vector3f::Zero();
    int contact_frames = 0;
    Eigen::Vector3f current_pin = Eigen::Vector3f::Zero();  // where the ankle is held this frame
  };
  // Whether a planted foot's estimate still stands (streams): its mean ground speed over the hold
  // span (a planted foot has seen at least two estimates).
  bool StillPlanted(const Foot& foot, const Eigen::Vector3f& estimate) const;
  // Where a foot's release has it this frame: the solved ankle plus the release's remaining
  // fraction of the offset from its last pin.
  Eigen::Vector3f ReleaseTarget(const Foot& foot, const Eigen::Vector3f& solved) const;
  const BodyModel& body_;
  float planted_height_;
  float rate_;
  FootskateOptions options_;
  int hold_frames_ = 0;  // streams: the hold span in frames (0: the one-frame rule)
  bool pin_at_mean_ = false;
  std::array<Foot, 2> feet_;
  std::vector<Eigen::Quaternionf> rotations_;
  std::vector<Eigen::Vector3f> positions_;
};

}  // namespace mocap

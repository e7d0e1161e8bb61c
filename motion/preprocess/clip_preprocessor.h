// Turns parsed BVH clips into database-ready clips (docs/method.md A1): unit conversion to metres,
// world turned Y-up, resampling to the database rate, per-frame features, compact pose encoding.
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "absl/status/statusor.h"
#include "motion/bvh/bvh_clip.h"
#include "motion/core/units.h"
#include "motion/preprocess/frame_features.h"
#include "motion/skeleton/body_topology.h"
#include "motion/skeleton/local_motion.h"

namespace mocap {

struct PreprocessOptions {
  double frame_rate = 30.0;        // database rate, frames per second (docs/method.md A8: 30 fps)
  std::optional<LengthUnit> unit;  // override unit detection
  // For importers: a clip of another rig is retargeted onto the database's rig instead of being
  // refused (motion/retarget/retarget_clip.h; its own unit is detected).
  bool retarget_other_rigs = false;
};

// Limits checked before any resampling or allocation (a request names them in its error).
inline constexpr double kMinDatabaseFrameRate = 1.0, kMaxDatabaseFrameRate = 1000.0;  // fps
inline constexpr int kMaxClipFrames = 1'000'000;      // frames of one clip at the database rate
inline constexpr double kMaxTranslationMetres = 1e4;  // any joint translation, after unit conversion
// InvalidArgument naming the limits for a rate outside [kMinDatabaseFrameRate, kMaxDatabaseFrameRate].
absl::Status CheckDatabaseFrameRate(double frame_rate);

// What a motion database knows about its rig, fixed when the database is created from its first
// clip. Every later clip must have the same joint names and hierarchy.
struct RigModel {
  Skeleton skeleton;      // the first clip's hierarchy (file units, file channels)
  BodyTopology topology;  // groups and landmarks (B1)
  LengthUnit unit = LengthUnit::kCentimetre;
  Eigen::Quaternionf to_y_up = Eigen::Quaternionf::Identity();  // world rotation making up = +Y
  // Per-joint rotation the pose encoding is relative to (mean over the first clip), so encoded
  // rotations stay small and away from the exp-map singularity.
  std::vector<Eigen::Quaternionf> reference_rotations;
  Eigen::Vector3f pelvis_up_local = Eigen::Vector3f::UnitY();  // pelvis-local "up" (for θ)
};

// InvalidArgument, naming --units, when the detected unit makes the body no person's size (legs
// outside 0.4-1.2 m: a 0.9 m or 3.5 m person). A declared unit is the caller's word: not checked.
absl::Status CheckBodySize(const BodyTopology& topology);

// The database rig from its first clip: topology, unit, Y-up turn, reference rotations.
absl::StatusOr<RigModel> BuildRigModel(const BvhClip& first_clip, const PreprocessOptions& options);

// The inverse of the import's conversion: a clip as stored (`skeleton` in metres, `motion` in
// metres, world Y up, at the database rate) as BVH in its rig's own file conventions: the rig's
// length unit and up axis, joint order and channels (`mocap export`: a file exported reads like
// the file imported, at the database rate).
BvhClip ToFileConventions(const Skeleton& skeleton_in_metres, const LocalMotion& motion, const RigModel& rig);
// The same for any rig given its turn to Y up and its unit (a retargeting target's).
BvhClip ToFileConventions(const Skeleton& skeleton_in_metres, LocalMotion motion, const Eigen::Quaternionf& to_y_up,
                          LengthUnit unit);

struct PreparedClip {
  Skeleton skeleton;   // this clip's own offsets in metres (performers differ in bone lengths)
  LocalMotion motion;  // database rate, metres, world Y up
  std::vector<FrameFeatures> features;
  // Non-root joints whose translation changes within the clip (as Bandai's Hips under a static
  // joint_Root): the store keeps their per-frame translations; the offsets carry all others.
  std::vector<int> animated_joints;
  double source_frame_rate = 0.0;
  int source_frames = 0;
  int num_frames() const { return motion.num_frames(); }
};

// FailedPrecondition when the clip's rig differs from `rig`. InvalidArgument, naming --units, when
// the clip's body is no person's size in the rig's unit (legs outside CheckBodySize's 0.4-1.2 m and
// more than 1.25x off the rig's own: a file of the rig in another unit or exported at another scale;
// every imported clip, not only the first, is checked so).
absl::StatusOr<PreparedClip> PrepareClip(const BvhClip& clip, const RigModel& rig, const PreprocessOptions& options);

// Compact pose encoding: per frame, the root translation (3 floats, metres) then every joint's
// rotation as the rotation vector (exp map, 3 floats) of reference⁻¹ · rotation.
inline int EncodedPoseFloats(int num_joints) { return 3 + 3 * num_joints; }
std::vector<float> EncodePoses(const LocalMotion& motion, const RigModel& rig);
// Inverse of EncodePoses; non-root translations come from `skeleton` offsets.
LocalMotion DecodePoses(const std::vector<float>& encoded, const Skeleton& skeleton, const RigModel& rig,
                        double frame_time);

}  // namespace mocap

#include "motion/preprocess/clip_preprocessor.h"

#include <array>
#include <cmath>

#include "motion/core/rotation_vector.h"
#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"
#include "motion/skeleton/forward_kinematics.h"

namespace mocap {
namespace {

// Checked before the resampling allocates: the rate, the resampled length, finite and plausible
// translations.
absl::StatusOr<LocalMotion> ToDatabaseWorld(const BvhClip& clip, const RigModel& rig,
                                            const PreprocessOptions& options) {
  MOCAP_RETURN_IF_ERROR(CheckDatabaseFrameRate(options.frame_rate));
  const double target = 1.0 / options.frame_rate;
  const double resampled_frames = (clip.num_frames() - 1) * clip.frame_time / target + 1;
  if (resampled_frames > kMaxClipFrames) {
    return absl::InvalidArgumentError(StrCat("clip would have ", static_cast<long long>(resampled_frames),
                                             " frames at the database rate of ", options.frame_rate,
                                             " fps, more than the limit of ", kMaxClipFrames));
  }
  LocalMotion motion = MotionFromChannels(clip.skeleton, clip.channels, clip.frame_time);
  ScaleTranslations(motion, static_cast<float>(MetresPerUnit(rig.unit)));
  for (const Eigen::ArrayXXf* t : {&motion.tx, &motion.ty, &motion.tz}) {
    if (!(t->abs() <= static_cast<float>(kMaxTranslationMetres)).all()) {
      return absl::InvalidArgumentError(StrCat("a joint translation is not finite or beyond ", kMaxTranslationMetres,
                                               " m (after unit conversion): not plausible motion"));
    }
  }
  RotateWorld(motion, rig.to_y_up);
  if (std::abs(clip.frame_time - target) > 1e-6 * target) motion = Resample(motion, target);
  motion.frame_time = target;
  return motion;
}

// A person's legs, hip joint to ankle: from a small child's to the tallest adult's.
constexpr double kMinLegMetres = 0.4, kMaxLegMetres = 1.2;
// A later clip of the rig may differ from the database's own body by this factor either way even
// outside that range (a body the caller declared the unit of: the rig's legs lie outside it).
constexpr double kSameBodyFactor = 1.25;

double RoundedMetres(double metres) { return std::round(metres * 100) / 100; }

// Hip joint to ankle along `skeleton`'s bones (offsets in metres: a prepared clip's first-frame
// translations), mean of both legs, on the rig's leg chains as AnalyseBody measures them; 0 when
// the rig's landmarks give no such chain (then nothing is checked).
double LegMetres(const Skeleton& skeleton, const BodyTopology& topology) {
  const std::array<std::array<int, 2>, 2> legs = {
      std::array<int, 2>{topology.group_top[static_cast<int>(BodyGroup::kLeftLeg)], topology.landmarks.left_ankle},
      std::array<int, 2>{topology.group_top[static_cast<int>(BodyGroup::kRightLeg)], topology.landmarks.right_ankle}};
  double sum = 0.0;
  for (const auto& [top, ankle] : legs) {
    if (top < 0 || ankle < 0 || ankle >= skeleton.num_joints()) return 0.0;
    int j = ankle;
    for (; j > top; j = skeleton.parent(j)) sum += skeleton.joint(j).offset.norm();  // parents come first
    if (j != top) return 0.0;  // the ankle does not hang under the leg's top
  }
  return sum / 2;
}

// Every clip's body against the database's unit (issue #23): a file of the same rig in another
// unit, or exported at another scale, would otherwise be stored as a 0.9 m or 3.5 m person. Cheap:
// a walk up the two leg chains of the prepared skeleton (metres).
absl::Status CheckClipBodySize(const PreparedClip& prepared, const RigModel& rig) {
  const double leg = LegMetres(prepared.skeleton, rig.topology);
  if (!(leg > 0.0)) return absl::OkStatus();
  if (leg >= kMinLegMetres && leg <= kMaxLegMetres) return absl::OkStatus();
  const double rig_leg = rig.topology.leg_length * MetresPerUnit(rig.unit);
  if (!(rig_leg > 0.0)) return absl::OkStatus();  // a rig without its size: nothing to compare
  if (leg >= rig_leg / kSameBodyFactor && leg <= rig_leg * kSameBodyFactor) return absl::OkStatus();
  const std::string_view unit = UnitName(rig.unit);
  return absl::InvalidArgumentError(
      StrCat("the body would be about ", RoundedMetres(leg / kLegShareOfStature), " m tall (legs ", RoundedMetres(leg),
             " m) in the database's length unit '", unit, "', whose rig has legs of ", RoundedMetres(rig_leg),
             " m: the file is in another unit or exported at another scale. Rescale it to '", unit,
             "', or import it into a database of its own, declaring its length unit with --units (m, cm, mm, in, "
             "or cmu for CMU's 1/0.45 inch)"));
}

}  // namespace

BvhClip ToFileConventions(const Skeleton& skeleton_in_metres, const LocalMotion& motion, const RigModel& rig) {
  return ToFileConventions(skeleton_in_metres, motion, rig.to_y_up, rig.unit);
}

BvhClip ToFileConventions(const Skeleton& skeleton_in_metres, LocalMotion motion, const Eigen::Quaternionf& to_y_up,
                          LengthUnit unit) {
  RotateWorld(motion, to_y_up.conjugate());
  const float to_file = static_cast<float>(1.0 / MetresPerUnit(unit));
  ScaleTranslations(motion, to_file);
  std::vector<Joint> joints = skeleton_in_metres.joints();
  for (Joint& joint : joints) {
    joint.offset *= to_file;
    if (joint.end_site) *joint.end_site *= to_file;
  }
  BvhClip clip;
  clip.skeleton = Skeleton(std::move(joints));
  clip.frame_time = motion.frame_time;
  clip.channels = ChannelsFromMotion(clip.skeleton, motion);
  return clip;
}

absl::Status CheckDatabaseFrameRate(double frame_rate) {
  if (!(frame_rate >= kMinDatabaseFrameRate && frame_rate <= kMaxDatabaseFrameRate)) {
    return absl::InvalidArgumentError(StrCat("frame rate ", frame_rate, " fps is outside the limits [",
                                             kMinDatabaseFrameRate, ", ", kMaxDatabaseFrameRate, "]"));
  }
  return absl::OkStatus();
}

absl::Status CheckBodySize(const BodyTopology& topology) {
  // Hip joint to ankle: ~0.8 m for an adult. A detected unit must give a body between a small
  // child's and the tallest adult's; a declared unit is the caller's word and is kept.
  if (!topology.unit_detected) return absl::OkStatus();
  const double leg_metres = topology.leg_length * MetresPerUnit(topology.unit);
  if (leg_metres >= kMinLegMetres && leg_metres <= kMaxLegMetres) return absl::OkStatus();
  const double height = leg_metres / kLegShareOfStature;
  return absl::InvalidArgumentError(
      StrCat("the body would be about ", RoundedMetres(height), " m tall (legs ", RoundedMetres(leg_metres),
             " m) in the detected unit '", UnitName(topology.unit),
             "': declare the file's length unit with --units (m, cm, mm, in, or cmu for CMU's 1/0.45 inch); "
             "a file exported at another scale needs rescaling first"));
}

absl::StatusOr<RigModel> BuildRigModel(const BvhClip& first_clip, const PreprocessOptions& options) {
  MOCAP_RETURN_IF_ERROR(first_clip.skeleton.Validate());
  RigModel rig;
  rig.skeleton = first_clip.skeleton;
  const LocalMotion file_motion = MotionFromChannels(first_clip.skeleton, first_clip.channels, first_clip.frame_time);
  MOCAP_ASSIGN_OR_RETURN(rig.topology,
                         AnalyseBody(first_clip.skeleton, file_motion, BodyTopologyOptions{.unit = options.unit}));
  rig.unit = rig.topology.unit;
  MOCAP_RETURN_IF_ERROR(CheckBodySize(rig.topology));
  rig.to_y_up = Eigen::Quaternionf::FromTwoVectors(rig.topology.up(), Eigen::Vector3f::UnitY());

  MOCAP_ASSIGN_OR_RETURN(const LocalMotion motion, ToDatabaseWorld(first_clip, rig, options));
  const int joints = motion.num_joints();
  rig.reference_rotations.resize(joints);
  for (int j = 0; j < joints; ++j) {
    const Eigen::Quaternionf first = motion.rotation(0, j);
    Eigen::Vector4f sum = Eigen::Vector4f::Zero();
    for (int f = 0; f < motion.num_frames(); ++f) {
      Eigen::Quaternionf q = motion.rotation(f, j);
      if (q.dot(first) < 0) q.coeffs() *= -1.0f;
      sum += q.coeffs();
    }
    rig.reference_rotations[j] = Eigen::Quaternionf(sum.normalized());
  }
  // The pelvis-local direction that points up on average over the clip.
  const GlobalPoses poses = ForwardKinematics(first_clip.skeleton, motion);
  Eigen::Vector3f up_local = Eigen::Vector3f::Zero();
  for (int f = 0; f < poses.num_frames(); ++f) {
    up_local += poses.rotation(f, rig.topology.landmarks.pelvis).normalized().conjugate() * Eigen::Vector3f::UnitY();
  }
  rig.pelvis_up_local = up_local.norm() > 0 ? up_local.normalized() : Eigen::Vector3f::UnitY();
  return rig;
}

absl::StatusOr<PreparedClip> PrepareClip(const BvhClip& clip, const RigModel& rig, const PreprocessOptions& options) {
  if (!clip.skeleton.SameRigAs(rig.skeleton)) {
    const Skeleton& a = clip.skeleton;
    const Skeleton& b = rig.skeleton;
    if (a.num_joints() != b.num_joints()) {
      auto missing_from = [](const Skeleton& x, const Skeleton& y) {  // names in x not in y
        std::string names;
        int count = 0;
        for (const Joint& joint : x.joints()) {
          if (y.Find(joint.name) >= 0) continue;
          if (count++ < 3) names += StrCat(names.empty() ? "" : ", ", "'", joint.name, "'");
        }
        return count > 3 ? StrCat(names, " and ", count - 3, " more") : names;
      };
      std::string detail;
      if (const std::string extra = missing_from(a, b); !extra.empty()) detail += StrCat("; the clip adds ", extra);
      if (const std::string lacking = missing_from(b, a); !lacking.empty())
        detail += StrCat("; the clip lacks ", lacking);
      return absl::FailedPreconditionError(StrCat("rig differs from the database's: ", a.num_joints(),
                                                  " joints where the database has ", b.num_joints(), detail));
    }
    for (int j = 0; j < a.num_joints(); ++j) {
      if (a.joint(j).name != b.joint(j).name || a.parent(j) != b.parent(j)) {
        return absl::FailedPreconditionError(StrCat("rig differs from the database's: joint ", j, " is '",
                                                    a.joint(j).name, "' where the database has '", b.joint(j).name,
                                                    "' (or a different parent)"));
      }
    }
  }
  PreparedClip prepared;
  prepared.source_frame_rate = clip.frame_rate();
  prepared.source_frames = clip.num_frames();
  MOCAP_ASSIGN_OR_RETURN(prepared.motion, ToDatabaseWorld(clip, rig, options));
  if (prepared.motion.num_frames() < 2) {
    return absl::InvalidArgumentError("clip is shorter than two frames at the database rate");
  }
  // This performer's offsets: the local translations (constant unless animated), in metres.
  std::vector<Joint> joints = clip.skeleton.joints();
  const float metres = static_cast<float>(MetresPerUnit(rig.unit));
  for (int j = 0; j < static_cast<int>(joints.size()); ++j) {
    if (j == 0) {
      joints[j].offset *= metres;
      continue;
    }
    joints[j].offset = prepared.motion.translation(0, j);
    bool animated = false;
    for (Eigen::ArrayXXf* t : {&prepared.motion.tx, &prepared.motion.ty, &prepared.motion.tz}) {
      if (t->col(j).maxCoeff() - t->col(j).minCoeff() > 1e-5f) animated = true;
    }
    if (animated) prepared.animated_joints.push_back(j);
    if (joints[j].end_site) *joints[j].end_site *= metres;
  }
  prepared.skeleton = Skeleton(std::move(joints));
  MOCAP_RETURN_IF_ERROR(CheckClipBodySize(prepared, rig));
  const GlobalPoses poses = ForwardKinematics(prepared.skeleton, prepared.motion);
  prepared.features =
      ComputeFrameFeatures(poses, rig.topology.landmarks, rig.pelvis_up_local, prepared.motion.frame_time);
  return prepared;
}

std::vector<float> EncodePoses(const LocalMotion& motion, const RigModel& rig) {
  const int joints = motion.num_joints();
  const int stride = EncodedPoseFloats(joints);
  std::vector<float> out(static_cast<size_t>(motion.num_frames()) * stride);
  for (int f = 0; f < motion.num_frames(); ++f) {
    float* row = out.data() + static_cast<size_t>(f) * stride;
    const Eigen::Vector3f root = motion.translation(f, 0);
    row[0] = root.x();
    row[1] = root.y();
    row[2] = root.z();
    for (int j = 0; j < joints; ++j) {
      const Eigen::Vector3f v = RotationVector(rig.reference_rotations[j].conjugate() * motion.rotation(f, j));
      row[3 + 3 * j] = v.x();
      row[4 + 3 * j] = v.y();
      row[5 + 3 * j] = v.z();
    }
  }
  return out;
}

LocalMotion DecodePoses(const std::vector<float>& encoded, const Skeleton& skeleton, const RigModel& rig,
                        double frame_time) {
  const int joints = skeleton.num_joints();
  const int stride = EncodedPoseFloats(joints);
  const int frames = static_cast<int>(encoded.size() / stride);
  LocalMotion motion;
  motion.frame_time = frame_time;
  motion.Resize(frames, joints);
  for (int f = 0; f < frames; ++f) {
    const float* row = encoded.data() + static_cast<size_t>(f) * stride;
    for (int j = 0; j < joints; ++j) {
      const Eigen::Vector3f v(row[3 + 3 * j], row[4 + 3 * j], row[5 + 3 * j]);
      motion.SetRotation(f, j, rig.reference_rotations[j] * FromRotationVector(v));
      motion.SetTranslation(f, j, j == 0 ? Eigen::Vector3f(row[0], row[1], row[2]) : skeleton.joint(j).offset);
    }
  }
  return motion;
}

}  // namespace mocap

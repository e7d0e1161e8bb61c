#include "server/reconstruction_convert.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "motion/core/str_cat.h"
#include "motion/reconstruct/body_model.h"
#include "server/proto_convert.h"

namespace mocap {
namespace {

// The A7 contact sources the API names, both ways (FOOT_CONTACTS_DEFAULT is none of them: the
// options' own).
constexpr std::array<std::pair<v1::FootContacts, ContactSource>, 3> kFootContacts = {{
    {v1::FOOT_CONTACTS_ESTIMATED_ANKLES, ContactSource::kEstimatedAnkles},
    {v1::FOOT_CONTACTS_DATABASE_FRAME, ContactSource::kDatabaseFrame},
    {v1::FOOT_CONTACTS_BOTH, ContactSource::kBoth},
}};

void ToProto(const Eigen::Vector3f& v, float scale, v1::Vec3* out) {
  out->set_x(v.x() * scale);
  out->set_y(v.y() * scale);
  out->set_z(v.z() * scale);
}

void ToProto(const Eigen::Quaternionf& q, v1::Quaternion* out) {
  out->set_w(q.w());
  out->set_x(q.x());
  out->set_y(q.y());
  out->set_z(q.z());
}

Eigen::Vector3f FromProto(const v1::Vec3& v, float scale) { return Eigen::Vector3f(v.x(), v.y(), v.z()) * scale; }

absl::Status CheckRange(const char* field, double value, double low, double high) {
  if (!(value >= low && value <= high)) {
    return absl::InvalidArgumentError(StrCat(field, " must be in [", low, ", ", high, "], not ", value));
  }
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<ReconstructionOptions> OptionsFromConfig(const v1::SessionConfig& config) {
  ReconstructionOptions options;
  switch (config.method()) {
    case v1::RECONSTRUCTION_METHOD_FULL:
      options.method = ReconstructionMethod::kFull;
      break;
    case v1::RECONSTRUCTION_METHOD_WRISTS_ONLY:
      options.method = ReconstructionMethod::kWristsOnly;
      break;
    case v1::RECONSTRUCTION_METHOD_NEAREST_NEIGHBOUR:
      options.method = ReconstructionMethod::kNearestNeighbour;
      break;
    default:
      return absl::InvalidArgumentError(StrCat("unknown method ", static_cast<int>(config.method())));
  }
  if (config.has_fixed_lag()) {
    options.mode = StreamMode::kFixedLag;
    options.lag = config.fixed_lag().lag_frames();
    if (auto s = CheckRange("fixed_lag.lag_frames", options.lag, 0, 600); !s.ok()) return s;
  } else {
    options.mode = StreamMode::kSubInterval;
    options.window = config.sub_interval().window_frames();
    if (auto s = CheckRange("sub_interval.window_frames", options.window, 0, kMaxWindowFrames); !s.ok()) return s;
  }
  const v1::MethodOverrides& o = config.overrides();
  if (o.foot_contacts() != v1::FOOT_CONTACTS_DEFAULT) {  // DEFAULT: ReconstructionOptions' own
    const auto* named = std::find_if(kFootContacts.begin(), kFootContacts.end(),
                                     [&](const auto& pair) { return pair.first == o.foot_contacts(); });
    if (named == kFootContacts.end()) {
      return absl::InvalidArgumentError(
          StrCat("overrides.foot_contacts: unknown value ", static_cast<int>(o.foot_contacts())));
    }
    options.footskate.contact_source = named->second;
  }
  if (auto s = ApplyMethodOverrides(o, &options); !s.ok()) return s;
  if (auto s = CheckRange("min_confidence", config.min_confidence(), 0, 1); !s.ok()) return s;
  // An unknown value (a newer client, or 7, -1) is refused, not silently taken as the default.
  if (!v1::OutputFrame_IsValid(config.output_frame())) {
    return absl::InvalidArgumentError(StrCat("output_frame: unknown value ", static_cast<int>(config.output_frame()),
                                             " (OUTPUT_FRAME_INPUT or OUTPUT_FRAME_SERVER)"));
  }
  return options;
}

v1::SessionConfig EffectiveConfig(const v1::SessionConfig& config, const ReconstructionOptions& options) {
  v1::SessionConfig out = config;
  if (options.mode == StreamMode::kFixedLag) {
    out.mutable_fixed_lag()->set_lag_frames(options.lag);
  } else {
    out.mutable_sub_interval()->set_window_frames(options.window);
  }
  WriteMethodOverrides(options, out.mutable_overrides());
  // The enum is written apart (method_overrides.h): the contacts the session uses, not "default".
  for (const auto& [proto, source] : kFootContacts) {
    if (source == options.footskate.contact_source) out.mutable_overrides()->set_foot_contacts(proto);
  }
  return out;
}

absl::StatusOr<PerformerScale> ScaleForPerformer(const ReconstructionDatabase& database, float performer_height) {
  PerformerScale scale;
  // The database performer's height as a person states theirs (floor to the top of the head): the
  // extent of a rest pose that does not stand is no height (Bandai's: 1.84 m for a 1.70 m actor,
  // so every declared height came out ~8% small, issue #22).
  scale.database_height = EstimatedStature(database.body());
  if (!(scale.database_height > 0.0f)) scale.database_height = RestPoseHeight(database.body());
  if (performer_height == 0.0f || scale.database_height <= 0.0f) return scale;
  if (!(performer_height >= 0.3f * scale.database_height && performer_height <= 3.0f * scale.database_height)) {
    return absl::InvalidArgumentError(StrCat("performer_height ", performer_height,
                                             " m is not plausible for a database ", "performer of ",
                                             scale.database_height, " m (0 keeps the database's)"));
  }
  scale.scale = performer_height / scale.database_height;
  return scale;
}

SampleCheck FromProto(const v1::WristSample& sample, float min_confidence, const InputConversion& input,
                      WristSample* out, std::array<StillHand, 2>* still_hands) {
  auto refused = [](std::string reason) { return SampleCheck{SampleCheck::kRefused, std::move(reason)}; };
  if (!std::isfinite(sample.time())) return refused("time is not a finite number");
  const float confidences[2] = {sample.has_left_confidence() ? sample.left_confidence() : 1.0f,
                                sample.has_right_confidence() ? sample.right_confidence() : 1.0f};
  for (float c : confidences) {
    if (!(c >= 0.0f && c <= 1.0f)) return refused(StrCat("confidence ", c, " is outside [0, 1]"));
  }
  // Confidence 0 is a tracker saying it has lost the hand (OpenXR's and ARKit's "not tracked"),
  // whatever min_confidence is: its position, often NaN, is not read.
  const std::array<bool, 2> tracked = {confidences[0] > 0.0f && confidences[0] >= min_confidence,
                                       confidences[1] > 0.0f && confidences[1] >= min_confidence};
  if (!tracked[0] && !tracked[1])
    return {SampleCheck::kDropout, "confidence below min_confidence (treated as a dropout)"};
  const LengthUnit unit = input.frame.convention.unit;
  const double metres_per_unit = MetresPerUnit(unit);
  for (int side = 0; side < 2; ++side) {
    if (!tracked[side]) continue;  // a lost hand's position is not read
    const v1::Vec3* v = side == 0 ? &sample.left() : &sample.right();
    for (double x : {v->x(), v->y(), v->z()}) {
      if (!std::isfinite(x)) return refused("a wrist position is not a finite number");
      if (std::abs(x * metres_per_unit) > kMaxWristCoordinateMetres) {
        return refused(StrCat("a wrist coordinate of ", x, " ", UnitName(unit), " is beyond ",
                              kMaxWristCoordinateMetres, " m from the origin"));
      }
    }
  }
  Eigen::Vector3f left = FromProto(sample.left(), 1.0f), right = FromProto(sample.right(), 1.0f);
  if (!tracked[0]) left = right;  // placeholders, finite: the session holds a lost hand by the other
  if (!tracked[1]) right = left;
  if (input.frame.tracked_device) {
    Eigen::Quaternionf orientations[2] = {Eigen::Quaternionf::Identity(), Eigen::Quaternionf::Identity()};
    for (int side = 0; side < 2; ++side) {
      if (!tracked[side]) continue;
      const v1::Quaternion& q = side == 0 ? sample.left_orientation() : sample.right_orientation();
      orientations[side] = Eigen::Quaternionf(q.w(), q.x(), q.y(), q.z());
      const float norm = orientations[side].norm();
      if (!(norm > 0.5f && norm < 2.0f)) {
        return refused(StrCat("the tracked point is a device: the ", side == 0 ? "left" : "right",
                              "_orientation must be a unit quaternion (norm ", norm, ")"));
      }
      orientations[side].normalize();
    }
    left = DeviceToWrist(left, orientations[0], input.frame.device_offset);
    right = DeviceToWrist(right, orientations[1], input.frame.device_offset);
  }
  out->time = sample.time();
  out->left = input.transform.PositionToNative(left);
  out->right = input.transform.PositionToNative(right);
  out->tracked = tracked;
  double longest_still = 0.0;
  if (still_hands != nullptr) {
    for (int side = 0; side < 2; ++side) {
      StillHand& hand = (*still_hands)[side];
      if (tracked[side]) {
        longest_still = std::max(longest_still, hand.Update(side == 0 ? out->left : out->right, out->time));
      } else {
        hand.Forget();
      }
    }
  }
  if (tracked[0] && tracked[1]) {
    const bool device_left = longest_still >= kDeviceLeftSeconds &&
                             std::abs(out->left.y()) <= kMaxWristSeparationMetres &&
                             std::abs(out->right.y()) <= kMaxWristSeparationMetres;
    if (std::optional<std::string> problem = WristSeparationProblem((out->left - out->right).norm(), unit);
        problem && !device_left) {
      return refused(*std::move(problem));
    }
  }
  return {};
}

void ToProto(const ReconstructionDatabase& database, const PerformerScale& scale, v1::Skeleton* out) {
  // The body's skeleton is the rig's hierarchy in metres; reuse the rig conversion with it.
  RigModel rig = database.body().rig();
  std::vector<Joint> joints = database.body().skeleton().joints();
  for (Joint& joint : joints) {
    joint.offset *= scale.scale;
    if (joint.end_site) *joint.end_site *= scale.scale;
  }
  rig.skeleton = Skeleton(std::move(joints));
  rig.unit = LengthUnit::kMetre;
  ToProto(rig, out);
}

void ToProto(const LandmarkErrors& errors, float scale, v1::LandmarkErrors* out) {
  // The message's fields are the landmarks in BodyLandmarkJoints order (checked by
  // FrameToProtoTest.LandmarkErrorFieldsAreTheLandmarksInOrderScaledToThePerformer).
  const google::protobuf::Descriptor* descriptor = v1::LandmarkErrors::descriptor();
  const google::protobuf::Reflection* reflection = v1::LandmarkErrors::GetReflection();
  for (int k = 0; k < kNumBodyLandmarks; ++k) reflection->SetFloat(out, descriptor->field(k), errors[k] * scale);
}

void ToProto(const ReconstructedFrame& frame, const SizeMap& map, float skeleton_scale, bool diagnostics,
             v1::Frame* out) {
  const float s = map.scale;
  out->set_index(frame.index);
  out->set_segment(frame.segment);
  out->set_frame_in_segment(frame.frame_in_segment);
  out->set_time(frame.time);
  if (s != skeleton_scale) out->set_body_scale(s / skeleton_scale);
  ToProto(map.ToPerformer(frame.pose.root_position), 1.0f, out->mutable_root_position());
  out->mutable_rotations()->Reserve(static_cast<int>(frame.pose.rotations.size()));
  for (const Eigen::Quaternionf& q : frame.pose.rotations) ToProto(q, out->add_rotations());
  ToProto(map.ToPerformer(frame.pelvis_position), 1.0f, out->mutable_pelvis_position());
  ToProto(frame.pelvis_rotation, out->mutable_pelvis_rotation());
  ToProto(map.ToPerformer(frame.ankles[0]), 1.0f, out->mutable_left_ankle());
  ToProto(map.ToPerformer(frame.ankles[1]), 1.0f, out->mutable_right_ankle());
  ToProto(map.ToPerformer(frame.wrists[0]), 1.0f, out->mutable_left_wrist());
  ToProto(map.ToPerformer(frame.wrists[1]), 1.0f, out->mutable_right_wrist());
  auto state = [](TrackingState t) {
    switch (t) {
      case TrackingState::kImplausible:
        return v1::TRACKING_STATE_IMPLAUSIBLE;
      case TrackingState::kPredicted:
        return v1::TRACKING_STATE_PREDICTED;
      case TrackingState::kOutOfReach:
        return v1::TRACKING_STATE_OUT_OF_REACH;
      case TrackingState::kPutDown:
        return v1::TRACKING_STATE_PUT_DOWN;
      case TrackingState::kLost:
        return v1::TRACKING_STATE_LOST;
      case TrackingState::kTracked:
        break;
    }
    return v1::TRACKING_STATE_TRACKED;
  };
  out->set_left_hand_state(state(frame.hand_state[0]));
  out->set_right_hand_state(state(frame.hand_state[1]));
  out->set_motion_limited(frame.motion_limited);
  ToProto(frame.landmark_error, s, out->mutable_expected_error());
  if (!diagnostics) return;
  const FrameDiagnostics& d = frame.diagnostics;
  v1::FrameDiagnostics* o = out->mutable_diagnostics();
  o->set_wrist_neighbour_distance(d.wrist_neighbour_distance);
  o->set_ankle_source_row(d.ankle_source_row);
  o->set_pose_neighbour_distance(d.pose_neighbour_distance);
  o->set_solver_cost(d.solver_cost);
  o->set_prior_weight_factor(d.prior_weight_factor);
  o->set_solver_evaluations(d.solver_evaluations);
  o->set_left_wrist_error(d.control_error[0] * s);
  o->set_right_wrist_error(d.control_error[1] * s);
  o->set_left_ankle_error(d.control_error[2] * s);
  o->set_right_ankle_error(d.control_error[3] * s);
  o->set_left_foot_planted(d.contact[0]);
  o->set_right_foot_planted(d.contact[1]);
  o->set_bridged(d.bridged);
  o->set_left_untracked_seconds(d.untracked_seconds[0]);
  o->set_right_untracked_seconds(d.untracked_seconds[1]);
}

void ToProto(const SessionStatistics& statistics, v1::SessionSummary* out) {
  out->set_frames(statistics.frames);
  out->set_segments(statistics.segments);
  out->set_repeated_hand_samples(statistics.repeated_hand_samples);
  const double per_frame = statistics.frames > 0 ? 1e3 / static_cast<double>(statistics.frames) : 0.0;
  out->set_cloud_ms_per_frame(statistics.cloud_seconds * per_frame);
  out->set_path_ms_per_frame(statistics.path_seconds * per_frame);
  out->set_pose_ms_per_frame(statistics.pose_seconds * per_frame);
  out->set_cleanup_ms_per_frame(statistics.post_seconds * per_frame);
}

absl::StatusOr<RetargetRig> FromProto(const v1::TargetRig& rig) {
  std::optional<LengthUnit> unit;
  if (!rig.unit().empty()) {
    unit = ParseUnit(rig.unit());
    if (!unit)
      return absl::InvalidArgumentError(
          "target_rig.unit must be \"m\", \"cm\", \"mm\", \"in\" or \"cmu\" (or empty: detected)");
  }
  switch (rig.rig_case()) {
    case v1::TargetRig::kBvh:
      if (rig.bvh().size() > kMaxTargetRigBvhBytes) {
        return absl::InvalidArgumentError(StrCat("target_rig.bvh has ", rig.bvh().size(), " bytes (at most ",
                                                 kMaxTargetRigBvhBytes, "; send the hierarchy and fewer frames)"));
      }
      return TargetRigFromBvh(rig.bvh(), unit);
    case v1::TargetRig::kJoints: {
      const auto& given = rig.joints().joints();
      if (given.size() > kMaxTargetJoints) {
        return absl::InvalidArgumentError(
            StrCat("target_rig.joints has ", given.size(), " joints (at most ", kMaxTargetJoints, ")"));
      }
      std::vector<Joint> joints;
      for (const v1::TargetJoint& entry : given) {
        // Named by index, not by the name the client sent: a name is checked (length, control
        // characters) only with the whole skeleton below, and a 3 MiB one came back in this error
        // as a metadata-size failure (issue #24).
        const int index = static_cast<int>(joints.size());
        Joint joint;
        joint.name = entry.name();
        joint.parent = entry.parent();
        joint.offset = FromProto(entry.offset(), 1.0f);
        if (!joint.offset.allFinite())
          return absl::InvalidArgumentError(StrCat("target_rig.joints[", index, "]: offset is not finite"));
        if (entry.has_end_site()) {
          joint.end_site = FromProto(entry.end_site(), 1.0f);
          if (!joint.end_site->allFinite()) {  // never echoed back as NaN in SessionStarted
            return absl::InvalidArgumentError(StrCat("target_rig.joints[", index, "]: end_site is not finite"));
          }
        }
        using C = ChannelType;
        joint.channels = {C::kZrotation, C::kXrotation, C::kYrotation};
        if (joint.parent < 0)
          joint.channels.insert(joint.channels.begin(), {C::kXposition, C::kYposition, C::kZposition});
        joints.push_back(std::move(joint));
      }
      const Skeleton skeleton(std::move(joints));
      if (absl::Status valid = skeleton.Validate(); !valid.ok()) {
        return absl::InvalidArgumentError(StrCat("target_rig.joints: ", valid.message()));
      }
      return TargetRigFromSkeleton(skeleton, unit);
    }
    case v1::TargetRig::RIG_NOT_SET:
      break;
  }
  return absl::InvalidArgumentError("target_rig has neither bvh nor joints");
}

void ToProto(const RetargetRig& rig, v1::Skeleton* out) {
  RigModel model;
  model.skeleton = rig.skeleton;
  model.topology = rig.topology;
  model.unit = LengthUnit::kMetre;
  ToProto(model, out);
}

void SetTargetPose(const BodyPose& pose, const Eigen::Quaternionf& pelvis_rotation,
                   const Eigen::Vector3f& pelvis_position, v1::Frame* out) {
  ToProto(pose.root_position, 1.0f, out->mutable_root_position());
  out->clear_rotations();
  out->mutable_rotations()->Reserve(static_cast<int>(pose.rotations.size()));
  for (const Eigen::Quaternionf& q : pose.rotations) ToProto(q, out->add_rotations());
  ToProto(pelvis_position, 1.0f, out->mutable_pelvis_position());
  ToProto(pelvis_rotation, out->mutable_pelvis_rotation());
}

}  // namespace mocap

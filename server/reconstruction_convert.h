// Reconstruction domain types <-> mocap.v1 messages (reconstruction.proto), and the performer
// scaling the service applies at its boundary (SessionConfig.performer_height).
#pragma once

#include <array>
#include <string>

#include "absl/status/statusor.h"
#include "mocap/v1/reconstruction.pb.h"
#include "motion/reconstruct/body_sizer.h"
#include "motion/reconstruct/hand_rest.h"
#include "motion/reconstruct/reconstruction_session.h"
#include "motion/retarget/retarget_rig.h"
#include "proto/convert/method_overrides.h"
#include "server/input_frame_convert.h"

namespace mocap {

// Server-side caps on the method's parameters (a K1 of 10⁵ would be 10¹⁰ edges per frame; the
// tunables' ranges, kMaxAnkleCandidates among them, are in proto/convert/method_overrides.h).
inline constexpr int kMaxWindowFrames = 3000;

// The session options a config asks for: defaults, then the config's mode and overrides.
// InvalidArgument naming the field when one is out of range.
absl::StatusOr<ReconstructionOptions> OptionsFromConfig(const v1::SessionConfig& config);
// The config with every effective value filled in (SessionStarted.config).
v1::SessionConfig EffectiveConfig(const v1::SessionConfig& config, const ReconstructionOptions& options);

// Lengths in the session are the database performer's; `scale` = performer / database height
// turns them into the caller's (and 1/scale turns the caller's samples into the session's).
struct PerformerScale {
  float database_height = 0;  // metres
  float scale = 1;
};
// InvalidArgument for a height that is negative, not finite, or outside 0.3–3 × the database's.
absl::StatusOr<PerformerScale> ScaleForPerformer(const ReconstructionDatabase& database, float performer_height);

// A sample to native metres (the input frame's transform; performer scaling comes after).
// What became of one wire sample: accepted (into `out`), a dropout (confidence below
// min_confidence: the session bridges or splits it), or refused with a reason (not finite,
// positions or confidences out of range, a tracked device without its orientation, wrists more
// than kMaxWristSeparationMetres apart: garbage is never reconstructed). Wrists that far apart are
// taken where one hand has lain still for kDeviceLeftSeconds and both are within
// kMaxWristSeparationMetres of the floor's height: a device put down and walked away from (issue
// #25), which a unit mistake, scaling every coordinate and its noise, never looks like.
struct SampleCheck {
  enum Kind { kAccepted, kDropout, kRefused } kind = kAccepted;
  std::string reason;
};
// Positions beyond this many metres from the origin, in any axis, are refused.
inline constexpr double kMaxWristCoordinateMetres = 10000.0;
inline constexpr double kDeviceLeftSeconds = 0.5;
// `still_hands`: how long each hand has lain still over the stream so far (updated here with the
// accepted sample; null: no stream, no exemption).
SampleCheck FromProto(const v1::WristSample& sample, float min_confidence, const InputConversion& input,
                      WristSample* out, std::array<StillHand, 2>* still_hands = nullptr);

void ToProto(const ReconstructionDatabase& database, const PerformerScale& scale, v1::Skeleton* out);
// Expected landmark errors, metres × `scale` (the performer's size).
void ToProto(const LandmarkErrors& errors, float scale, v1::LandmarkErrors* out);
// `map`: the frame's input's way into the database body's space (body_sizer.h), taken back;
// `skeleton_scale`: the scale of the skeleton the client animates (Frame.body_scale is the ratio).
void ToProto(const ReconstructedFrame& frame, const SizeMap& map, float skeleton_scale, bool diagnostics,
             v1::Frame* out);
void ToProto(const SessionStatistics& statistics, v1::SessionSummary* out);

// SessionConfig.target_rig (target_rig.proto) analysed into a rig to retarget onto.
// InvalidArgument for a bad unit, oversized or malformed BVH text, joints that are not a
// hierarchy; FailedPrecondition when no humanoid body is found.
inline constexpr size_t kMaxTargetRigBvhBytes = 1 << 20;
absl::StatusOr<RetargetRig> FromProto(const v1::TargetRig& rig);
// The target rig as SessionStarted.skeleton (metres, its groups and landmarks).
void ToProto(const RetargetRig& rig, v1::Skeleton* out);
// Puts a retargeted pose into a frame already converted by ToProto: root, rotations and pelvis
// on the target rig (metres; the rig sets the size, no performer scaling).
void SetTargetPose(const BodyPose& pose, const Eigen::Quaternionf& pelvis_rotation,
                   const Eigen::Vector3f& pelvis_position, v1::Frame* out);

}  // namespace mocap

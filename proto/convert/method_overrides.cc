#include "proto/convert/method_overrides.h"

#include <array>
#include <cmath>
#include <string>

#include "motion/core/str_cat.h"

namespace mocap {
namespace {

using Reflection = google::protobuf::Reflection;
using Field = google::protobuf::FieldDescriptor;

// A row whose option is a plain member path: `OPTION` names it (e.g. `ankle_path.data_weight`).
#define MOCAP_TUNABLE(field, flag, help, min, max, option)                                                     \
  MethodTunable {                                                                                              \
    field, flag, help, min, max, [](const ReconstructionOptions& o) { return static_cast<double>(o.option); }, \
        [](ReconstructionOptions& o, double v) { o.option = static_cast<decltype(o.option)>(v); }              \
  }

const std::array kTunables = {
    MOCAP_TUNABLE("ankle_candidates", "--k1", "A3 ankle candidates K1", 1, kMaxAnkleCandidates, ankle_candidates),
    MOCAP_TUNABLE("pose_neighbours", "--k2", "A5 pose neighbours K2", 2, kMaxPoseNeighbours, pose_neighbours),
    MOCAP_TUNABLE("pose_components", "--pose-components", "A5 pose model components D'", 1, 64, pose_components),
    MOCAP_TUNABLE("pose_neighbour_kernel", "--pose-kernel",
                  "A5: weigh the K2 examples by a Gaussian kernel of this × the median neighbour's squared distance "
                  "(0: alike, the patent's)",
                  0, 100, pose_neighbour_kernel),
    MOCAP_TUNABLE("wrist_smoothing", "", "A2 exponential smoothing s (when wrist_fit_frames is 0)", 0, 1,
                  smoothing.smoothing),
    // The σ the session's mode uses (by default a stream has its own, AnklePathOptions); set, one σ
    // for every mode, so that an effective config sent again means the same session.
    MethodTunable{"ankle_smoothing_frames", "--ankle-smoothing",
                  "A4 Gaussian σ on the ankle path, frames (default 1; 2 in a stream)", 0, 30,
                  [](const ReconstructionOptions& o) { return static_cast<double>(AnkleSmoothingSigma(o)); },
                  [](ReconstructionOptions& o, double v) {
                    o.ankle_path.smoothing_sigma_frames = o.ankle_path.stream_smoothing_sigma_frames =
                        static_cast<float>(v);
                  }},
    MOCAP_TUNABLE("joint_smoothing_frames", "--joint-smoothing",
                  "A7 joint filter σ, frames (Gaussian; whole clip: a sharp low-pass of its cutoff)", 0, 30,
                  joint_smoothing_sigma),
    MOCAP_TUNABLE("footskate_cleanup", "", "A7 contact pinning and leg IK (1 on, 0 off)", 0, 1, footskate.enabled),
    MOCAP_TUNABLE("max_gap_seconds", "", "longer input dropouts start a new segment, seconds", 1e-3, 10,
                  max_gap_seconds),
    MOCAP_TUNABLE("wrist_fit_frames", "", "A2 local linear fit σ, frames (0: exponential smoothing)", 0, 10,
                  smoothing.local_linear_sigma),
    MOCAP_TUNABLE("wrist_lookahead_frames", "", "frames the A2 fit looks ahead", 0, 30, smoothing.lookahead),
    MOCAP_TUNABLE("hand_target_frames", "", "σ of the hands' IK targets, frames (negative: no hand IK)", -1e9, 10,
                  hand_target_sigma),
    MOCAP_TUNABLE("ankle_data_weight", "", "A4 node cost on the wrist distance (0: the patent's path cost)", 0, 100,
                  ankle_path.data_weight),
    MOCAP_TUNABLE("unfamiliar_prior_max", "",
                  "A6: the largest factor on the prior weight in a session unlike the database (1: off)", 1, 16,
                  unfamiliar_prior.max_factor),
};
#undef MOCAP_TUNABLE

const Field* FieldOf(const MethodTunable& tunable) {
  return v1::MethodOverrides::descriptor()->FindFieldByName(std::string(tunable.field));
}

double Read(const v1::MethodOverrides& message, const Field* field) {
  const Reflection* r = message.GetReflection();
  switch (field->cpp_type()) {
    case Field::CPPTYPE_INT32:
      return r->GetInt32(message, field);
    case Field::CPPTYPE_FLOAT:
      return r->GetFloat(message, field);
    case Field::CPPTYPE_DOUBLE:
      return r->GetDouble(message, field);
    case Field::CPPTYPE_BOOL:
      return r->GetBool(message, field) ? 1.0 : 0.0;
    default:
      return 0.0;  // no such row (MethodOverridesTest checks every row's type)
  }
}

}  // namespace

std::span<const MethodTunable> MethodTunables() { return kTunables; }

absl::Status ApplyMethodOverrides(const v1::MethodOverrides& overrides, ReconstructionOptions* options) {
  for (const MethodTunable& tunable : kTunables) {
    const Field* field = FieldOf(tunable);
    if (field != nullptr && overrides.GetReflection()->HasField(overrides, field))
      tunable.set(*options, Read(overrides, field));
  }
  for (const MethodTunable& tunable : kTunables) {
    const double value = tunable.get(*options);
    if (!(value >= tunable.min && value <= tunable.max)) {
      return absl::InvalidArgumentError(
          StrCat("overrides.", tunable.field, " must be in [", tunable.min, ", ", tunable.max, "], not ", value));
    }
  }
  return absl::OkStatus();
}

void SetMethodOverride(const MethodTunable& tunable, double value, v1::MethodOverrides* overrides) {
  const Field* field = FieldOf(tunable);
  if (field == nullptr) return;
  const Reflection* r = overrides->GetReflection();
  switch (field->cpp_type()) {
    case Field::CPPTYPE_INT32:
      r->SetInt32(overrides, field, static_cast<std::int32_t>(std::lround(value)));
      break;
    case Field::CPPTYPE_FLOAT:
      r->SetFloat(overrides, field, static_cast<float>(value));
      break;
    case Field::CPPTYPE_DOUBLE:
      r->SetDouble(overrides, field, value);
      break;
    case Field::CPPTYPE_BOOL:
      r->SetBool(overrides, field, value != 0.0);
      break;
    default:
      break;
  }
}

void WriteMethodOverrides(const ReconstructionOptions& options, v1::MethodOverrides* overrides) {
  for (const MethodTunable& tunable : kTunables) SetMethodOverride(tunable, tunable.get(options), overrides);
}

}  // namespace mocap

// Reconstruction messages <-> domain (server/reconstruction_convert.h): a config's options with
// every out-of-range field refused by name, the effective config read back into the same options,
// performer scaling, wire samples checked one by one, frames and statistics scaled and converted,
// target rigs analysed or refused.
#include "server/reconstruction_convert.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "motion/bvh/bvh_writer.h"
#include "motion/reconstruct/body_model.h"
#include "tests/support/synthetic_clip.h"
#include "tests/support/synthetic_database.h"

namespace mocap {
// Named, so that helpers do not meet other files' in a unity batch.
namespace reconstruction_convert_test {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

const testing::SyntheticReconstructionSetup& SyntheticSetup() {
  static const auto* setup =
      new testing::SyntheticReconstructionSetup(testing::MakeSyntheticReconstructionSetup({}, 30));
  return *setup;
}

void Set(v1::Vec3* v, double x, double y, double z) {
  v->set_x(x);
  v->set_y(y);
  v->set_z(z);
}

// ---- OptionsFromConfig / EffectiveConfig

TEST(OptionsFromConfigTest, AnEmptyConfigIsTheDefaultOfflineFullMethod) {
  auto options = OptionsFromConfig(v1::SessionConfig());
  ASSERT_TRUE(options.ok()) << options.status();
  const ReconstructionOptions defaults;
  EXPECT_EQ(options->method, ReconstructionMethod::kFull);
  EXPECT_EQ(options->mode, StreamMode::kSubInterval);
  EXPECT_EQ(options->window, 0);
  EXPECT_EQ(options->ankle_candidates, defaults.ankle_candidates);
  EXPECT_EQ(options->pose_neighbours, defaults.pose_neighbours);
  EXPECT_EQ(options->joint_smoothing_sigma, defaults.joint_smoothing_sigma);
  EXPECT_EQ(options->max_gap_seconds, defaults.max_gap_seconds);
  EXPECT_EQ(options->footskate.contact_source, ContactSource::kBoth);
}

TEST(OptionsFromConfigTest, ModesMethodsAndOverridesAreTaken) {
  v1::SessionConfig config;
  config.set_method(v1::RECONSTRUCTION_METHOD_NEAREST_NEIGHBOUR);
  config.mutable_fixed_lag()->set_lag_frames(600);  // the largest lag
  v1::MethodOverrides* o = config.mutable_overrides();
  o->set_ankle_candidates(kMaxAnkleCandidates);
  o->set_pose_neighbours(2);
  o->set_pose_components(64);
  o->set_wrist_smoothing(0.25f);
  o->set_footskate_cleanup(false);
  o->set_max_gap_seconds(1.5f);
  o->set_hand_target_frames(-1.0f);  // off
  o->set_foot_contacts(v1::FOOT_CONTACTS_BOTH);
  auto options = OptionsFromConfig(config);
  ASSERT_TRUE(options.ok()) << options.status();
  EXPECT_EQ(options->method, ReconstructionMethod::kNearestNeighbour);
  EXPECT_EQ(options->mode, StreamMode::kFixedLag);
  EXPECT_EQ(options->lag, 600);
  EXPECT_EQ(options->ankle_candidates, kMaxAnkleCandidates);
  EXPECT_EQ(options->pose_neighbours, 2);
  EXPECT_EQ(options->pose_components, 64);
  EXPECT_FLOAT_EQ(options->smoothing.smoothing, 0.25f);
  EXPECT_FALSE(options->footskate.enabled);
  EXPECT_FLOAT_EQ(options->max_gap_seconds, 1.5);
  EXPECT_FLOAT_EQ(options->hand_target_sigma, -1.0f);
  EXPECT_EQ(options->footskate.contact_source, ContactSource::kBoth);

  config.clear_fixed_lag();
  config.mutable_sub_interval()->set_window_frames(kMaxWindowFrames);
  options = OptionsFromConfig(config);
  ASSERT_TRUE(options.ok()) << options.status();
  EXPECT_EQ(options->mode, StreamMode::kSubInterval);
  EXPECT_EQ(options->window, kMaxWindowFrames);
}

struct BadConfig {
  std::string field;  // the error must name it
  std::function<void(v1::SessionConfig&)> edit;
};

TEST(OptionsFromConfigTest, EveryOutOfRangeFieldIsRefusedByName) {
  const std::vector<BadConfig> cases = {
      {"unknown method", [](auto& c) { c.set_method(static_cast<v1::ReconstructionMethod>(42)); }},
      {"fixed_lag.lag_frames", [](auto& c) { c.mutable_fixed_lag()->set_lag_frames(601); }},
      {"fixed_lag.lag_frames", [](auto& c) { c.mutable_fixed_lag()->set_lag_frames(-1); }},
      {"sub_interval.window_frames",
       [](auto& c) { c.mutable_sub_interval()->set_window_frames(kMaxWindowFrames + 1); }},
      {"sub_interval.window_frames", [](auto& c) { c.mutable_sub_interval()->set_window_frames(-5); }},
      {"overrides.ankle_candidates", [](auto& c) { c.mutable_overrides()->set_ankle_candidates(0); }},
      {"overrides.ankle_candidates",
       [](auto& c) { c.mutable_overrides()->set_ankle_candidates(kMaxAnkleCandidates + 1); }},
      {"overrides.pose_neighbours", [](auto& c) { c.mutable_overrides()->set_pose_neighbours(1); }},
      {"overrides.pose_neighbours",
       [](auto& c) { c.mutable_overrides()->set_pose_neighbours(kMaxPoseNeighbours + 1); }},
      {"overrides.pose_components", [](auto& c) { c.mutable_overrides()->set_pose_components(65); }},
      {"overrides.wrist_smoothing", [](auto& c) { c.mutable_overrides()->set_wrist_smoothing(1.5f); }},
      {"overrides.wrist_smoothing", [](auto& c) { c.mutable_overrides()->set_wrist_smoothing(NAN); }},
      {"overrides.ankle_smoothing_frames", [](auto& c) { c.mutable_overrides()->set_ankle_smoothing_frames(31); }},
      {"overrides.joint_smoothing_frames", [](auto& c) { c.mutable_overrides()->set_joint_smoothing_frames(-0.5f); }},
      {"overrides.max_gap_seconds", [](auto& c) { c.mutable_overrides()->set_max_gap_seconds(0.0f); }},
      {"overrides.max_gap_seconds", [](auto& c) { c.mutable_overrides()->set_max_gap_seconds(INFINITY); }},
      {"overrides.wrist_fit_frames", [](auto& c) { c.mutable_overrides()->set_wrist_fit_frames(11); }},
      {"overrides.wrist_lookahead_frames", [](auto& c) { c.mutable_overrides()->set_wrist_lookahead_frames(31); }},
      {"overrides.hand_target_frames", [](auto& c) { c.mutable_overrides()->set_hand_target_frames(10.5f); }},
      {"overrides.ankle_data_weight", [](auto& c) { c.mutable_overrides()->set_ankle_data_weight(-1); }},
      {"overrides.unfamiliar_prior_max", [](auto& c) { c.mutable_overrides()->set_unfamiliar_prior_max(0.5f); }},
      {"overrides.pose_neighbour_kernel", [](auto& c) { c.mutable_overrides()->set_pose_neighbour_kernel(-0.1f); }},
      {"overrides.pose_neighbour_kernel", [](auto& c) { c.mutable_overrides()->set_pose_neighbour_kernel(NAN); }},
      {"overrides.unfamiliar_prior_max", [](auto& c) { c.mutable_overrides()->set_unfamiliar_prior_max(NAN); }},
      {"overrides.foot_contacts",
       [](auto& c) { c.mutable_overrides()->set_foot_contacts(static_cast<v1::FootContacts>(9)); }},
      {"min_confidence", [](auto& c) { c.set_min_confidence(1.01f); }},
      {"min_confidence", [](auto& c) { c.set_min_confidence(NAN); }},
      {"output_frame", [](auto& c) { c.set_output_frame(static_cast<v1::OutputFrame>(7)); }},
      {"output_frame", [](auto& c) { c.set_output_frame(static_cast<v1::OutputFrame>(-1)); }},
  };
  for (const BadConfig& bad : cases) {
    v1::SessionConfig config;
    bad.edit(config);
    auto options = OptionsFromConfig(config);
    EXPECT_EQ(options.status().code(), absl::StatusCode::kInvalidArgument) << bad.field << ": " << options.status();
    const std::string named = bad.field == "unknown method" ? "method" : bad.field;
    EXPECT_NE(options.status().message().find(named), std::string::npos) << options.status();
  }
}

// Issue #24: a target rig's NaN End Site was echoed back in SessionStarted.
TEST(TargetRigFromProtoTest, NonFiniteEndSitesAreRefusedByJoint) {
  v1::TargetRig rig;
  v1::TargetJoint* joint = rig.mutable_joints()->add_joints();
  joint->set_name("Hips");
  joint->set_parent(-1);
  joint->mutable_end_site()->set_y(NAN);
  auto converted = FromProto(rig);
  EXPECT_EQ(converted.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(converted.status().message().find("joints[0]: end_site is not finite"), std::string::npos)
      << converted.status();
}

// Issue #24: a 3 MiB joint name with a non-finite offset came back inside the error (a
// metadata-size failure instead of INVALID_ARGUMENT); the joint is named by its index.
TEST(TargetRigFromProtoTest, ANonFiniteOffsetNeverEchoesTheJointsName) {
  v1::TargetRig rig;
  v1::TargetJoint* joint = rig.mutable_joints()->add_joints();
  joint->set_name(std::string(3 << 20, 'x'));
  joint->set_parent(-1);
  joint->mutable_offset()->set_x(NAN);
  auto converted = FromProto(rig);
  EXPECT_EQ(converted.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_LT(converted.status().message().size(), 200u);
  EXPECT_NE(converted.status().message().find("joints[0]: offset is not finite"), std::string::npos)
      << converted.status().message().substr(0, 200);
}

TEST(OptionsFromConfigTest, TheEffectiveConfigReadsBackIntoTheSameOptions) {
  v1::SessionConfig config;
  config.set_database("walks");
  config.mutable_fixed_lag()->set_lag_frames(7);
  config.mutable_overrides()->set_ankle_candidates(123);
  config.mutable_overrides()->set_wrist_lookahead_frames(3);
  config.mutable_overrides()->set_foot_contacts(v1::FOOT_CONTACTS_DATABASE_FRAME);
  auto options = OptionsFromConfig(config);
  ASSERT_TRUE(options.ok()) << options.status();
  const v1::SessionConfig effective = EffectiveConfig(config, *options);
  // Every override is filled in, and what the caller set is kept.
  const v1::MethodOverrides& o = effective.overrides();
  EXPECT_TRUE(o.has_pose_neighbours() && o.has_pose_components() && o.has_wrist_smoothing() &&
              o.has_ankle_smoothing_frames() && o.has_joint_smoothing_frames() && o.has_footskate_cleanup() &&
              o.has_max_gap_seconds() && o.has_wrist_fit_frames() && o.has_hand_target_frames() &&
              o.has_ankle_data_weight() && o.has_unfamiliar_prior_max() && o.has_pose_neighbour_kernel());
  EXPECT_EQ(o.pose_neighbour_kernel(), ReconstructionOptions().pose_neighbour_kernel);
  EXPECT_EQ(o.unfamiliar_prior_max(), ReconstructionOptions().unfamiliar_prior.max_factor);
  EXPECT_EQ(effective.database(), "walks");
  EXPECT_EQ(effective.fixed_lag().lag_frames(), 7);
  EXPECT_EQ(o.ankle_candidates(), 123);
  EXPECT_EQ(o.pose_neighbours(), ReconstructionOptions().pose_neighbours);
  EXPECT_EQ(o.foot_contacts(), v1::FOOT_CONTACTS_DATABASE_FRAME);
  // Left to the server, the contacts read back as the ones it uses.
  v1::SessionConfig unset = config;
  unset.mutable_overrides()->clear_foot_contacts();
  auto defaults = OptionsFromConfig(unset);
  ASSERT_TRUE(defaults.ok()) << defaults.status();
  EXPECT_EQ(defaults->footskate.contact_source, ContactSource::kBoth);
  EXPECT_EQ(EffectiveConfig(unset, *defaults).overrides().foot_contacts(), v1::FOOT_CONTACTS_BOTH);
  // Sent again, it means the same session.
  auto again = OptionsFromConfig(effective);
  ASSERT_TRUE(again.ok()) << again.status();
  EXPECT_EQ(again->mode, options->mode);
  EXPECT_EQ(again->lag, options->lag);
  EXPECT_EQ(again->ankle_candidates, options->ankle_candidates);
  EXPECT_EQ(again->pose_neighbours, options->pose_neighbours);
  EXPECT_EQ(again->pose_components, options->pose_components);
  EXPECT_EQ(again->smoothing.smoothing, options->smoothing.smoothing);
  EXPECT_EQ(again->smoothing.local_linear_sigma, options->smoothing.local_linear_sigma);
  EXPECT_EQ(again->smoothing.lookahead, options->smoothing.lookahead);
  EXPECT_EQ(AnkleSmoothingSigma(*again), AnkleSmoothingSigma(*options));  // the σ its mode uses
  EXPECT_EQ(again->ankle_path.data_weight, options->ankle_path.data_weight);
  EXPECT_EQ(again->joint_smoothing_sigma, options->joint_smoothing_sigma);
  EXPECT_EQ(again->hand_target_sigma, options->hand_target_sigma);
  EXPECT_EQ(again->footskate.enabled, options->footskate.enabled);
  EXPECT_EQ(again->footskate.contact_source, options->footskate.contact_source);
  EXPECT_FLOAT_EQ(again->max_gap_seconds, options->max_gap_seconds);

  // Sub-interval sessions echo their window, not a lag.
  config.clear_fixed_lag();
  options = OptionsFromConfig(config);
  ASSERT_TRUE(options.ok());
  const v1::SessionConfig windowed = EffectiveConfig(config, *options);
  EXPECT_TRUE(windowed.has_sub_interval());
  EXPECT_FALSE(windowed.has_fixed_lag());
}

TEST(OptionsFromConfigTest, TheAnkleFilterReadsBackAsTheOneItsModeUses) {
  // A stream has an ankle filter of its own (docs/method.md A4): the effective config says the one
  // the session uses, and sent again it means the same session.
  for (const bool stream : {true, false}) {
    v1::SessionConfig config;
    if (stream) config.mutable_fixed_lag()->set_lag_frames(5);
    auto options = OptionsFromConfig(config);
    ASSERT_TRUE(options.ok()) << options.status();
    const float used =
        stream ? AnklePathOptions().stream_smoothing_sigma_frames : AnklePathOptions().smoothing_sigma_frames;
    EXPECT_EQ(AnkleSmoothingSigma(*options), used) << "stream " << stream;
    const v1::SessionConfig effective = EffectiveConfig(config, *options);
    EXPECT_EQ(effective.overrides().ankle_smoothing_frames(), used) << "stream " << stream;
    auto again = OptionsFromConfig(effective);
    ASSERT_TRUE(again.ok()) << again.status();
    EXPECT_EQ(AnkleSmoothingSigma(*again), used) << "stream " << stream;
  }
  EXPECT_NE(AnklePathOptions().stream_smoothing_sigma_frames, AnklePathOptions().smoothing_sigma_frames);
  // Set by the caller, one σ for every mode.
  v1::SessionConfig config;
  config.mutable_fixed_lag()->set_lag_frames(0);
  config.mutable_overrides()->set_ankle_smoothing_frames(1.5f);
  auto options = OptionsFromConfig(config);
  ASSERT_TRUE(options.ok()) << options.status();
  EXPECT_EQ(options->ankle_path.smoothing_sigma_frames, 1.5f);
  EXPECT_EQ(options->ankle_path.stream_smoothing_sigma_frames, 1.5f);
}

// ---- ScaleForPerformer

TEST(ScaleForPerformerTest, ScalesWithinThePlausibleRangeAndRefusesTheRest) {
  const ReconstructionDatabase& database = *SyntheticSetup().database;
  const float height = EstimatedStature(database.body());
  ASSERT_GT(height, 1.0f);
  auto same = ScaleForPerformer(database, 0.0f);
  ASSERT_TRUE(same.ok());
  EXPECT_EQ(same->scale, 1.0f);
  EXPECT_EQ(same->database_height, height);
  for (float factor : {0.3f, 0.5f, 1.0f, 2.0f, 3.0f}) {
    auto scaled = ScaleForPerformer(database, factor * height);
    ASSERT_TRUE(scaled.ok()) << factor << ": " << scaled.status();
    EXPECT_NEAR(scaled->scale, factor, 1e-5f);
  }
  for (float bad : {-1.0f, 0.29f * height, 3.01f * height, static_cast<float>(kNaN), static_cast<float>(kInf),
                    -static_cast<float>(kInf)}) {
    auto refused = ScaleForPerformer(database, bad);
    EXPECT_EQ(refused.status().code(), absl::StatusCode::kInvalidArgument) << bad;
    EXPECT_NE(refused.status().message().find("performer_height"), std::string::npos) << refused.status();
  }
}

// ---- Wire samples

v1::WristSample Sample(double time, double lx, double ly, double lz, double rx, double ry, double rz) {
  v1::WristSample sample;
  sample.set_time(time);
  Set(sample.mutable_left(), lx, ly, lz);
  Set(sample.mutable_right(), rx, ry, rz);
  return sample;
}

TEST(SampleFromProtoTest, AcceptedSamplesArriveInNativeMetres) {
  const InputConversion native;  // metres, Y up, floor at 0
  WristSample out;
  SampleCheck check = FromProto(Sample(1.5, 0.2, 1.0, 0.1, -0.2, 0.9, 0.0), 0.0f, native, &out);
  ASSERT_EQ(check.kind, SampleCheck::kAccepted) << check.reason;
  EXPECT_EQ(out.time, 1.5);
  EXPECT_TRUE(out.left.isApprox(Eigen::Vector3f(0.2f, 1.0f, 0.1f)));
  EXPECT_TRUE(out.right.isApprox(Eigen::Vector3f(-0.2f, 0.9f, 0.0f)));

  // Centimetres, Z up (Blender-like), floor 10 cm below the origin.
  InputFrame frame;
  frame.convention = {LengthUnit::kCentimetre, UpAxis::kPosZ, Handedness::kRight};
  frame.floor.height = -10.0;
  const InputConversion cm{frame, FrameTransform(frame.convention, frame.floor.height)};
  check = FromProto(Sample(0.0, 20, 0, 100, -20, 0, 90), 0.0f, cm, &out);
  ASSERT_EQ(check.kind, SampleCheck::kAccepted) << check.reason;
  EXPECT_NEAR(out.left.y(), 1.10f, 1e-5f);  // 100 cm up, 10 cm above the floor
  EXPECT_NEAR(out.right.y(), 1.00f, 1e-5f);
  EXPECT_NEAR((out.left - out.right).norm(), std::hypot(0.4, 0.1), 1e-5);
}

TEST(SampleFromProtoTest, GarbageIsRefusedWithAReasonAndLowConfidenceIsADropout) {
  const InputConversion native;
  const v1::WristSample good = Sample(0.0, 0.2, 1.0, 0.0, -0.2, 1.0, 0.0);
  struct Case {
    std::string reason;  // a piece of the expected reason
    std::function<void(v1::WristSample&)> edit;
  };
  const std::vector<Case> refused = {
      {"time", [](auto& s) { s.set_time(kNaN); }},
      {"time", [](auto& s) { s.set_time(kInf); }},
      {"confidence", [](auto& s) { s.set_left_confidence(1.5f); }},
      {"confidence", [](auto& s) { s.set_right_confidence(-0.1f); }},
      {"confidence", [](auto& s) { s.set_right_confidence(NAN); }},
      {"finite", [](auto& s) { s.mutable_left()->set_y(kNaN); }},
      {"finite", [](auto& s) { s.mutable_right()->set_z(-kInf); }},
      {"beyond",
       [](auto& s) {
         s.mutable_left()->set_x(20000.0);
         s.mutable_right()->set_x(20000.0);
       }},
      {"apart", [](auto& s) { s.mutable_right()->set_x(50.0); }},
  };
  for (const Case& c : refused) {
    v1::WristSample sample = good;
    c.edit(sample);
    WristSample out;
    const SampleCheck check = FromProto(sample, 0.5f, native, &out);
    EXPECT_EQ(check.kind, SampleCheck::kRefused) << c.reason;
    EXPECT_NE(check.reason.find(c.reason), std::string::npos) << check.reason;
  }
  // The coordinate limit is in metres, whatever the caller's unit: 9 km in millimetres passes it.
  InputFrame mm;
  mm.convention.unit = LengthUnit::kMillimetre;
  const InputConversion millimetres{mm, FrameTransform(mm.convention, 0.0)};
  WristSample out;
  EXPECT_EQ(FromProto(Sample(0, 9e6, 1000, 0, 9e6 - 400, 1000, 0), 0.0f, millimetres, &out).kind,
            SampleCheck::kAccepted);
  EXPECT_EQ(FromProto(Sample(0, 2e7, 1000, 0, 2e7 - 400, 1000, 0), 0.0f, millimetres, &out).kind,
            SampleCheck::kRefused);

  // One hand below min_confidence: the sample goes on with that hand lost (its position, even
  // NaN, is not read); both below: a dropout.
  v1::WristSample unsure = good;
  unsure.set_left_confidence(0.3f);
  unsure.mutable_left()->set_x(NAN);
  ASSERT_EQ(FromProto(unsure, 0.5f, native, &out).kind, SampleCheck::kAccepted);
  EXPECT_FALSE(out.tracked[0]);
  EXPECT_TRUE(out.tracked[1]);
  EXPECT_TRUE(out.left.allFinite());
  unsure.set_right_confidence(0.1f);
  EXPECT_EQ(FromProto(unsure, 0.5f, native, &out).kind, SampleCheck::kDropout);
  unsure.set_right_confidence(0.9f);
  // Confidence 0 is a lost hand even with min_confidence 0 (no gating asked for): a tracker's NaN
  // position beside it is not refused.
  unsure.set_left_confidence(0.0f);
  ASSERT_EQ(FromProto(unsure, 0.0f, native, &out).kind, SampleCheck::kAccepted);
  EXPECT_FALSE(out.tracked[0]);
  EXPECT_TRUE(out.tracked[1]);
  unsure.set_left_confidence(0.3f);
  unsure.mutable_left()->set_x(0.2);
  ASSERT_EQ(FromProto(unsure, 0.2f, native, &out).kind, SampleCheck::kAccepted);
  EXPECT_TRUE(out.tracked[0] && out.tracked[1]);
}

// A controller put down and walked away from (issue #25) ends up metres from the other hand: taken
// once it has lain still for kDeviceLeftSeconds at a body's heights; a unit mistake, which scales
// every coordinate and its noise, is still refused, and so is one sample far off while both move.
TEST(SampleFromProtoTest, WristsFarApartAreTakenWhereADeviceWasLeft) {
  const InputConversion native;
  auto walk_away = [&](double scale, double device_jitter) {
    std::array<StillHand, 2> still;
    long refused = 0;
    for (int i = 0; i < 240; ++i) {  // 60 Hz: the left device lies still, the right hand walks off at 1.2 m/s
      const double t = i / 60.0;
      const double jitter = device_jitter * std::sin(13.0 * t);
      v1::WristSample sample = Sample(t, scale * (0.2 + jitter), scale * 0.75, 0.0, scale * -0.2,
                                      scale * (0.9 + 0.02 * std::sin(6.0 * t)), scale * 1.2 * t);
      WristSample out;
      refused += FromProto(sample, 0.0f, native, &out, &still).kind == SampleCheck::kRefused;
    }
    return refused;
  };
  EXPECT_EQ(walk_away(1.0, 0.002), 0) << "3 m and more apart after 2.5 s, 4.8 m at the end";
  EXPECT_GT(walk_away(100.0, 0.002), 100) << "centimetres declared as metres";
  EXPECT_GT(walk_away(1.0, 0.05), 10) << "no hand still: not a device left";
}

TEST(SampleFromProtoTest, TrackedDevicesNeedAUnitOrientationAndAreOffsetToTheWrist) {
  InputFrame frame;
  frame.tracked_device = true;
  frame.device_offset = Eigen::Vector3f(0.0f, 0.0f, 0.1f);
  const InputConversion device{frame, FrameTransform(frame.convention, 0.0)};
  v1::WristSample sample = Sample(0.0, 0.2, 1.0, 0.0, -0.2, 1.0, 0.0);
  WristSample out;
  SampleCheck check = FromProto(sample, 0.0f, device, &out);
  EXPECT_EQ(check.kind, SampleCheck::kRefused);  // no orientations sent
  EXPECT_NE(check.reason.find("left_orientation"), std::string::npos) << check.reason;
  sample.mutable_left_orientation()->set_w(1.0);
  check = FromProto(sample, 0.0f, device, &out);
  EXPECT_NE(check.reason.find("right_orientation"), std::string::npos) << check.reason;
  // Right device turned 90° about Y: its offset (0, 0, 0.1) points along +X. Not quite unit: normalised.
  const Eigen::Quaternionf turn(Eigen::AngleAxisf(static_cast<float>(M_PI / 2), Eigen::Vector3f::UnitY()));
  sample.mutable_right_orientation()->set_w(1.2 * turn.w());
  sample.mutable_right_orientation()->set_y(1.2 * turn.y());
  check = FromProto(sample, 0.0f, device, &out);
  ASSERT_EQ(check.kind, SampleCheck::kAccepted) << check.reason;
  EXPECT_TRUE(out.left.isApprox(Eigen::Vector3f(0.2f, 1.0f, 0.1f), 1e-5f)) << out.left.transpose();
  EXPECT_TRUE(out.right.isApprox(Eigen::Vector3f(-0.1f, 1.0f, 0.0f), 1e-5f)) << out.right.transpose();
}

// ---- Frames, statistics, skeletons

TEST(FrameToProtoTest, LengthsAreScaledToThePerformerAndRotationsAreNot) {
  ReconstructedFrame frame;
  frame.index = 12;
  frame.segment = 1;
  frame.frame_in_segment = 3;
  frame.time = 0.4;
  frame.pose.root_position = {0.1f, 0.9f, 0.2f};
  frame.pose.rotations = {Eigen::Quaternionf(Eigen::AngleAxisf(0.5f, Eigen::Vector3f::UnitY())),
                          Eigen::Quaternionf::Identity()};
  frame.pelvis_position = {0.1f, 1.0f, 0.2f};
  frame.pelvis_rotation = Eigen::Quaternionf(Eigen::AngleAxisf(0.2f, Eigen::Vector3f::UnitX()));
  frame.ankles = {Eigen::Vector3f(0.1f, 0.05f, 0.0f), Eigen::Vector3f(-0.1f, 0.05f, 0.3f)};
  frame.wrists = {Eigen::Vector3f(0.3f, 0.8f, 0.1f), Eigen::Vector3f(-0.3f, 0.8f, 0.0f)};
  frame.diagnostics.control_error = {0.01f, 0.02f, 0.03f, 0.04f};
  frame.diagnostics.ankle_source_row = 77;
  frame.diagnostics.contact = {true, false};
  frame.diagnostics.bridged = true;
  frame.diagnostics.prior_weight_factor = 2.5f;
  const SizeMap scale{.scale = 2.0f};

  v1::Frame out;
  ToProto(frame, scale, /*skeleton_scale=*/2.0f, /*diagnostics=*/false, &out);
  EXPECT_EQ(out.body_scale(), 0.0f);  // unset: the skeleton the client has
  EXPECT_EQ(out.index(), 12);
  EXPECT_EQ(out.segment(), 1);
  EXPECT_EQ(out.frame_in_segment(), 3);
  EXPECT_DOUBLE_EQ(out.time(), 0.4);
  EXPECT_FLOAT_EQ(out.root_position().y(), 1.8f);
  EXPECT_FLOAT_EQ(out.pelvis_position().y(), 2.0f);
  EXPECT_FLOAT_EQ(out.right_ankle().z(), 0.6f);
  EXPECT_FLOAT_EQ(out.left_wrist().x(), 0.6f);
  ASSERT_EQ(out.rotations_size(), 2);
  EXPECT_FLOAT_EQ(out.rotations(0).w(), frame.pose.rotations[0].w());
  EXPECT_FLOAT_EQ(out.rotations(0).y(), frame.pose.rotations[0].y());
  EXPECT_FLOAT_EQ(out.pelvis_rotation().x(), frame.pelvis_rotation.x());
  EXPECT_FALSE(out.has_diagnostics());

  ToProto(frame, scale, 2.0f, /*diagnostics=*/true, &out);
  ASSERT_TRUE(out.has_diagnostics());
  EXPECT_FLOAT_EQ(out.diagnostics().left_wrist_error(), 0.02f);
  EXPECT_FLOAT_EQ(out.diagnostics().right_ankle_error(), 0.08f);
  EXPECT_EQ(out.diagnostics().ankle_source_row(), 77);
  EXPECT_TRUE(out.diagnostics().left_foot_planted());
  EXPECT_FALSE(out.diagnostics().right_foot_planted());
  EXPECT_TRUE(out.diagnostics().bridged());
  EXPECT_FLOAT_EQ(out.diagnostics().prior_weight_factor(), 2.5f);
}

TEST(FrameToProtoTest, ABodyGrowingInAStreamCarriesItsScaleAndPositionsThroughItsMap) {
  ReconstructedFrame frame;
  frame.pose.rotations = {Eigen::Quaternionf::Identity()};
  frame.pose.root_position = {1.0f, 0.9f, 2.0f};
  frame.pelvis_position = {1.0f, 1.0f, 2.0f};
  frame.wrists = {Eigen::Vector3f(1.3f, 0.8f, 2.0f), Eigen::Vector3f(0.7f, 0.8f, 2.0f)};
  // Half-way through growing 1.0 → 1.2 about a performer standing near (5, 0, 7).
  const SizeMap map{.scale = 1.1f, .offset = Eigen::Vector2f(1.0f - 5.0f / 1.1f, 2.0f - 7.0f / 1.1f)};
  v1::Frame out;
  ToProto(frame, map, /*skeleton_scale=*/1.0f, /*diagnostics=*/false, &out);
  EXPECT_FLOAT_EQ(out.body_scale(), 1.1f);
  EXPECT_NEAR(out.root_position().x(), 5.0f, 1e-5f);
  EXPECT_NEAR(out.root_position().y(), 0.99f, 1e-5f);
  EXPECT_NEAR(out.root_position().z(), 7.0f, 1e-5f);
  EXPECT_NEAR(out.left_wrist().x(), 5.33f, 1e-5f);
  EXPECT_NEAR(out.pelvis_position().y(), 1.1f, 1e-5f);
}

TEST(FrameToProtoTest, LandmarkErrorFieldsAreTheLandmarksInOrderScaledToThePerformer) {
  // ToProto fills the message by field position: its fields must be the landmarks in order.
  const google::protobuf::Descriptor* descriptor = v1::LandmarkErrors::descriptor();
  ASSERT_EQ(descriptor->field_count(), kNumBodyLandmarks);
  for (int k = 0; k < kNumBodyLandmarks; ++k) EXPECT_EQ(descriptor->field(k)->name(), kBodyLandmarkNames[k]);

  ReconstructedFrame frame;
  frame.pose.rotations = {Eigen::Quaternionf::Identity()};
  for (int k = 0; k < kNumBodyLandmarks; ++k) frame.landmark_error[k] = 0.01f * (k + 1);
  v1::Frame out;
  ToProto(frame, SizeMap{.scale = 1.5f}, 1.5f, /*diagnostics=*/false, &out);
  ASSERT_TRUE(out.has_expected_error());
  EXPECT_FLOAT_EQ(out.expected_error().pelvis(), 0.015f);
  EXPECT_FLOAT_EQ(out.expected_error().left_wrist(), 0.105f);
  EXPECT_FLOAT_EQ(out.expected_error().right_ankle(), 0.21f);
}

TEST(FrameToProtoTest, StatisticsArePerFrameAndZeroFramesIsNotADivisionByZero) {
  SessionStatistics statistics;
  statistics.frames = 200;
  statistics.segments = 2;
  statistics.cloud_seconds = 0.4;
  statistics.path_seconds = 0.2;
  statistics.pose_seconds = 1.0;
  statistics.post_seconds = 0.1;
  v1::SessionSummary summary;
  ToProto(statistics, &summary);
  EXPECT_EQ(summary.frames(), 200);
  EXPECT_EQ(summary.segments(), 2);
  EXPECT_DOUBLE_EQ(summary.cloud_ms_per_frame(), 2.0);
  EXPECT_DOUBLE_EQ(summary.path_ms_per_frame(), 1.0);
  EXPECT_DOUBLE_EQ(summary.pose_ms_per_frame(), 5.0);
  EXPECT_DOUBLE_EQ(summary.cleanup_ms_per_frame(), 0.5);
  statistics = {};
  statistics.cloud_seconds = 1.0;
  ToProto(statistics, &summary);
  EXPECT_EQ(summary.cloud_ms_per_frame(), 0.0);
}

TEST(FrameToProtoTest, TheDatabaseSkeletonIsScaledToThePerformer) {
  const ReconstructionDatabase& database = *SyntheticSetup().database;
  v1::Skeleton plain, tall;
  ToProto(database, PerformerScale{.database_height = 1.7f, .scale = 1.0f}, &plain);
  ToProto(database, PerformerScale{.database_height = 1.7f, .scale = 1.5f}, &tall);
  ASSERT_EQ(plain.joints_size(), database.body().skeleton().num_joints());
  ASSERT_EQ(tall.joints_size(), plain.joints_size());
  for (int j = 0; j < plain.joints_size(); ++j) {
    EXPECT_EQ(tall.joints(j).name(), plain.joints(j).name());
    EXPECT_NEAR(tall.joints(j).offset().y(), 1.5f * plain.joints(j).offset().y(), 1e-5f) << j;
    EXPECT_NE(plain.joints(j).group(), v1::BODY_GROUP_UNSPECIFIED) << j;
  }
  EXPECT_EQ(plain.landmarks().left_wrist(), database.body().rig().topology.landmarks.left_wrist);
}

// ---- Target rigs

TEST(TargetRigFromProtoTest, AnalysesABvhOrJointsAndRefusesWhatIsNotARig) {
  const BvhClip clip = testing::MakeWalkingClip({}, 10);
  v1::TargetRig rig;
  rig.set_bvh(FormatBvh(clip));
  auto from_bvh = FromProto(rig);
  ASSERT_TRUE(from_bvh.ok()) << from_bvh.status();
  EXPECT_EQ(from_bvh->skeleton.num_joints(), clip.skeleton.num_joints());

  v1::TargetRig joints;
  joints.set_unit("cm");
  for (const Joint& joint : clip.skeleton.joints()) {
    v1::TargetJoint* entry = joints.mutable_joints()->add_joints();
    entry->set_name(joint.name);
    entry->set_parent(joint.parent);
    Set(entry->mutable_offset(), joint.offset.x(), joint.offset.y(), joint.offset.z());
    if (joint.end_site) Set(entry->mutable_end_site(), joint.end_site->x(), joint.end_site->y(), joint.end_site->z());
  }
  auto from_joints = FromProto(joints);
  ASSERT_TRUE(from_joints.ok()) << from_joints.status();
  EXPECT_EQ(from_joints->skeleton.num_joints(), clip.skeleton.num_joints());
  v1::Skeleton skeleton;
  ToProto(*from_joints, &skeleton);
  ASSERT_EQ(skeleton.joints_size(), clip.skeleton.num_joints());
  EXPECT_EQ(skeleton.landmarks().pelvis(), from_joints->topology.landmarks.pelvis);

  struct Case {
    std::string what, named;
    std::function<void(v1::TargetRig&)> edit;
  };
  const std::vector<Case> cases = {
      {"neither", "neither", [](auto& r) { r.clear_rig(); }},
      {"bad unit", "target_rig.unit", [](auto& r) { r.set_unit("furlong"); }},
      {"oversized bvh", "bytes", [](auto& r) { r.set_bvh(std::string(kMaxTargetRigBvhBytes + 1, 'x')); }},
      {"non-finite offset", "not finite",
       [](auto& r) { r.mutable_joints()->mutable_joints(2)->mutable_offset()->set_x(kNaN); }},
      {"parent after child", "target_rig.joints",
       [](auto& r) { r.mutable_joints()->mutable_joints(1)->set_parent(5); }},
      {"two roots", "target_rig.joints", [](auto& r) { r.mutable_joints()->mutable_joints(3)->set_parent(-1); }},
      {"too many joints", "joints",
       [](auto& r) {
         auto* list = r.mutable_joints()->mutable_joints();
         while (list->size() <= kMaxTargetJoints) {
           v1::TargetJoint* extra = list->Add();
           extra->set_name("extra" + std::to_string(list->size()));
           extra->set_parent(0);
         }
       }},
  };
  for (const Case& c : cases) {
    v1::TargetRig bad = joints;
    c.edit(bad);
    auto refused = FromProto(bad);
    EXPECT_EQ(refused.status().code(), absl::StatusCode::kInvalidArgument) << c.what << ": " << refused.status();
    EXPECT_NE(refused.status().message().find(c.named), std::string::npos) << c.what << ": " << refused.status();
  }
  v1::TargetRig garbage;
  garbage.set_bvh("HIERARCHY\nROOT");
  EXPECT_FALSE(FromProto(garbage).ok());
}

}  // namespace
}  // namespace reconstruction_convert_test
}  // namespace mocap

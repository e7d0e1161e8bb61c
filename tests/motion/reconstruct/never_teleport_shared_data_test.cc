// Issue #22, "never teleport", on real data: a few bandai-namco-1 clips (other performers than the
// database's; standing, waving and walking) with their wrists degraded as devices send them —
// a controller's 20 cm step in one frame; a 72 Hz VR controller quantised to 1 cm that repeats
// about half its rows; phone-AR jitter of 2–3 cm; a 1 s gap — reconstructed against a part of
// bandai-namco-2 in every mode (lag 0, 5, 15; sub-intervals of 50; the whole clip). The output
// pelvis never moves faster than a database body does (the motion guard's bound; before issue #22
// it reached 14–93 m/s on such input). The target — never faster than max(2 × the
// capture's fastest, its fastest + 1 m/s) — is printed per run and counted; it is met on the walk
// but not yet on the standing clips (bow, bye: up to ~1.4–2.2 m/s against 1.06–1.17 allowed),
// which the guard's bounds (the database's) cannot tell apart from a body that starts to walk.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "motion/bvh/bvh_reader.h"
#include "motion/preprocess/clip_labels.h"
#include "motion/preprocess/clip_preprocessor.h"
#include "motion/reconstruct/plausibility.h"
#include "motion/reconstruct/reconstruction_session.h"
#include "motion/skeleton/forward_kinematics.h"
#include "tests/support/shared_data.h"

namespace mocap {
namespace {

struct Degradation {
  std::string name;
  std::function<std::vector<WristSample>(const std::vector<WristSample>&)> apply;
};

// The clean samples at `rate` Hz (linear interpolation between the clip's frames).
std::vector<WristSample> Resampled(const std::vector<WristSample>& clean, double rate) {
  std::vector<WristSample> out;
  const double end = clean.back().time;
  size_t i = 0;
  for (double t = clean.front().time; t <= end; t += 1.0 / rate) {
    while (i + 1 < clean.size() && clean[i + 1].time < t) ++i;
    const WristSample& a = clean[i];
    const WristSample& b = clean[std::min(i + 1, clean.size() - 1)];
    const float u = b.time > a.time ? static_cast<float>((t - a.time) / (b.time - a.time)) : 0.0f;
    out.push_back({t, a.left + u * (b.left - a.left), a.right + u * (b.right - a.right)});
  }
  return out;
}

std::vector<Degradation> Degradations() {
  return {
      {"clean (0.5 cm noise)", [](const std::vector<WristSample>& s) { return s; }},
      {"20 cm controller step",
       [](std::vector<WristSample> s) {
         for (size_t i = s.size() / 2; i < s.size(); ++i) s[i].right += Eigen::Vector3f(0.2f, 0.0f, 0.0f);
         return s;
       }},
      {"72 Hz, 1 cm, half repeated",
       [](const std::vector<WristSample>& clean) {
         std::vector<WristSample> s = Resampled(clean, 72.0);
         std::mt19937 random(72);
         std::bernoulli_distribution repeat(0.5);
         for (size_t i = 1; i < s.size(); ++i) {
           if (repeat(random)) {
             s[i].left = s[i - 1].left;
             s[i].right = s[i - 1].right;
           } else {
             for (Eigen::Vector3f* p : {&s[i].left, &s[i].right}) *p = (*p * 100.0f).array().round().matrix() / 100.0f;
           }
         }
         return s;
       }},
      {"2-3 cm jitter",
       [](std::vector<WristSample> s) {
         std::mt19937 random(3);
         std::normal_distribution<float> noise(0.0f, 0.015f);
         for (WristSample& w : s) {
           for (Eigen::Vector3f* p : {&w.left, &w.right})
             *p += Eigen::Vector3f(noise(random), noise(random), noise(random));
         }
         return s;
       }},
      {"1 s gap",
       [](const std::vector<WristSample>& clean) {
         std::vector<WristSample> s;
         const double middle = 0.5 * (clean.front().time + clean.back().time);
         for (const WristSample& w : clean) {
           if (w.time < middle - 0.5 || w.time >= middle + 0.5) s.push_back(w);
         }
         return s;
       }},
  };
}

// Issue #25's put-down state: a walk whose left controller is set down after 2 s (its input stays
// where it was, within 3 mm of noise) while the right hand walks on: flagged within 3 s, then let
// go, so the body walks on with the right hand, the left carried along; put down, never tracked.
void put_down_walk(const std::shared_ptr<const ReconstructionDatabase>& database, const std::filesystem::path& file,
                   const RigModel& rig) {
  if (!std::filesystem::exists(file)) return;
  auto clip = ReadBvhFile(file);
  ASSERT_TRUE(clip.ok()) << clip.status();
  auto prepared = PrepareClip(*clip, rig, {});
  ASSERT_TRUE(prepared.ok()) << prepared.status();
  const GlobalPoses truth = ForwardKinematics(prepared->skeleton, prepared->motion);
  const BodyLandmarks& l = rig.topology.landmarks;
  const double dt = prepared->motion.frame_time;
  constexpr double kSetDown = 2.0;
  std::mt19937 random(25);
  std::normal_distribution<float> noise(0.0f, 0.003f);
  std::vector<WristSample> samples;
  Eigen::Vector3f table = Eigen::Vector3f::Zero();
  for (int f = 0; f < truth.num_frames(); ++f) {
    const double t = f * dt;
    if (t <= kSetDown) table = truth.position(f, l.left_wrist);
    WristSample s{t, t <= kSetDown ? truth.position(f, l.left_wrist) : table, truth.position(f, l.right_wrist)};
    for (Eigen::Vector3f* p : {&s.left, &s.right}) *p += Eigen::Vector3f(noise(random), noise(random), noise(random));
    samples.push_back(s);
  }
  ReconstructionOptions options;
  options.mode = StreamMode::kFixedLag;
  options.lag = 5;
  auto out = ReconstructOffline(database, options, samples);
  ASSERT_TRUE(out.ok()) << out.status();
  std::optional<double> flagged_at;
  long tracked_after = 0, after = 0;
  for (const ReconstructedFrame& f : *out) {
    if (!flagged_at && f.hand_state[0] == TrackingState::kPutDown) flagged_at = f.time;
    if (flagged_at) {
      ++after;
      tracked_after += f.hand_state[0] == TrackingState::kTracked;
    }
  }
  ASSERT_TRUE(flagged_at) << "the set-down controller was never flagged";
  // Once the hand is let go and its guess has caught up with the body, the body walks on with the
  // right hand: its pelvis where the capture's is, not held back by the controller on the table.
  double pelvis_error = 0.0;
  long caught_up = 0;
  for (const ReconstructedFrame& f : *out) {
    const int frame = static_cast<int>(std::lround(f.time / dt));
    if (f.time < *flagged_at + OneHandBridge::kCatchUpSeconds + 0.5 || frame >= truth.num_frames()) continue;
    pelvis_error += (f.pelvis_position - truth.position(frame, l.pelvis)).norm();
    ++caught_up;
  }
  ASSERT_GT(caught_up, 0) << "the walk ends before the let-go hand has caught up";
  pelvis_error /= static_cast<double>(caught_up);
  std::printf(
      "a controller set down at %.1f s is flagged put down at %.2f s; %ld of %ld frames after it tracked; "
      "pelvis %.1f cm from the capture's over the %ld frames after the hand caught up\n",
      kSetDown, *flagged_at, tracked_after, after, 100.0 * pelvis_error, caught_up);
  EXPECT_LE(*flagged_at - kSetDown, 3.0);
  EXPECT_EQ(tracked_after, 0);
  EXPECT_LT(pelvis_error, 0.4) << "the body stayed with the controller on the table (2.3 m behind when it did)";

  // The left controller held 1.5 m out to the side of where the wrist is: no arm reaches it.
  for (WristSample& s : samples) s.left = s.right + 1.5f * (s.left - s.right).normalized();
  out = ReconstructOffline(database, options, samples);
  ASSERT_TRUE(out.ok()) << out.status();
  long out_of_reach = 0;
  for (const ReconstructedFrame& f : *out) out_of_reach += f.hand_state[0] == TrackingState::kOutOfReach;
  std::printf("wrists held 1.5 m apart: the left hand out of reach in %ld of %zu frames\n", out_of_reach, out->size());
  EXPECT_GE(out_of_reach, static_cast<long>(out->size()) * 9 / 10);
}

TEST(NeverTeleportSharedDataTest, DeviceLikeInputOfOtherPerformersInEveryMode) {
  MOCAP_REQUIRE_SHARED_DATA(database_folder, "bandai-namco-2");
  MOCAP_REQUIRE_SHARED_DATA(test_folder, "bandai-namco-1");
  const auto database_files = testing::BvhFilesIn(database_folder);
  auto first = ReadBvhFile(database_files.front());
  ASSERT_TRUE(first.ok()) << first.status();
  auto rig = BuildRigModel(*first, {});
  ASSERT_TRUE(rig.ok()) << rig.status();
  std::vector<DatabaseClip> clips;
  for (size_t i = 0; i < database_files.size(); i += 4) {  // a quarter of the set keeps the test short
    auto clip = ReadBvhFile(database_files[i]);
    ASSERT_TRUE(clip.ok()) << clip.status();
    auto prepared = PrepareClip(*clip, *rig, {});
    ASSERT_TRUE(prepared.ok()) << prepared.status();
    clips.push_back({prepared->features, EncodePoses(prepared->motion, *rig)});
  }
  auto database = ReconstructionDatabase::Build(*rig, clips);
  ASSERT_TRUE(database.ok()) << database.status();
  const MotionLimits& limits = (*database)->motion_limits();
  std::printf(
      "database: %d frames; pelvis ≤ %.2f m/s (p99 %.2f), ≤ %.1f m/s²; off the wrists ≤ %.2f m/s; "
      "wrists ≤ %.2f m/s, ≤ %.1f m/s² (p99 %.1f)\n",
      (*database)->num_frames(), limits.pelvis_speed_max, limits.pelvis_speed_p99, limits.pelvis_acceleration_max,
      limits.pelvis_speed_beyond_hands_max, limits.wrist_speed_max, limits.wrist_acceleration_max,
      limits.wrist_acceleration_p99);

  const BodyLandmarks& l = rig->topology.landmarks;
  struct Mode {
    const char* name;
    StreamMode mode;
    int value;
  };
  const Mode modes[] = {{"lag 0", StreamMode::kFixedLag, 0},
                        {"lag 5", StreamMode::kFixedLag, 5},
                        {"lag 15", StreamMode::kFixedLag, 15},
                        {"window 50", StreamMode::kSubInterval, 50},
                        {"whole clip", StreamMode::kSubInterval, 0}};
  int clips_tested = 0, runs = 0, misses = 0;
  for (const char* name :
       {"dataset-1_bow_normal_001.bvh", "dataset-1_bye_normal_001.bvh", "dataset-1_walk_normal_001.bvh"}) {
    const std::filesystem::path file = test_folder / name;
    if (!std::filesystem::exists(file)) continue;
    auto clip = ReadBvhFile(file);
    ASSERT_TRUE(clip.ok()) << clip.status();
    auto prepared = PrepareClip(*clip, *rig, {});
    ASSERT_TRUE(prepared.ok()) << prepared.status();
    const GlobalPoses truth = ForwardKinematics(prepared->skeleton, prepared->motion);
    const double dt = prepared->motion.frame_time;
    const int frames = std::min(truth.num_frames(), 300);
    float own_max = 0;
    for (int f = 1; f < frames; ++f)
      own_max = std::max(
          own_max, (truth.position(f, l.pelvis) - truth.position(f - 1, l.pelvis)).norm() / static_cast<float>(dt));
    std::mt19937 random(1);
    std::normal_distribution<float> noise(0.0f, 0.005f);
    std::vector<WristSample> clean;
    for (int f = 0; f < frames; ++f) {
      WristSample s{f * dt, truth.position(f, l.left_wrist), truth.position(f, l.right_wrist)};
      for (Eigen::Vector3f* p : {&s.left, &s.right}) *p += Eigen::Vector3f(noise(random), noise(random), noise(random));
      clean.push_back(s);
    }
    const float allowed = AllowedSpeed(own_max);
    ++clips_tested;
    for (const Degradation& degradation : Degradations()) {
      const std::vector<WristSample> samples = degradation.apply(clean);
      for (const Mode& mode : modes) {
        ReconstructionOptions options;
        options.mode = mode.mode;
        (mode.mode == StreamMode::kFixedLag ? options.lag : options.window) = mode.value;
        auto out = ReconstructOffline(*database, options, samples);
        ASSERT_TRUE(out.ok()) << out.status();
        std::vector<PlausibilityFrame> measured;
        long implausible = 0, limited = 0, out_of_reach = 0, put_down = 0;
        for (const ReconstructedFrame& f : *out) {
          for (TrackingState state : f.hand_state) {
            out_of_reach += state == TrackingState::kOutOfReach;
            put_down += state == TrackingState::kPutDown;
          }
          PlausibilityFrame p;
          p.time = f.time;
          p.segment = f.segment;
          p.pelvis = f.pelvis_position;
          measured.push_back(p);
          implausible += f.implausible_input();
          limited += f.motion_limited;
        }
        const float fastest = MeasurePlausibility(measured, 0.0f, 0.0f).pelvis_speed.max();
        std::printf(
            "%-32s %-28s %-10s pelvis ≤ %6.2f m/s (capture %.2f, allowed %.2f); %ld implausible, "
            "%ld guarded of %zu frames; hands out of reach %ld, put down %ld\n",
            name, degradation.name.c_str(), mode.name, fastest, own_max, allowed, implausible, limited, out->size(),
            out_of_reach, put_down);
        if (degradation.name.starts_with("clean")) {  // a continuous capture: every hand tracked
          EXPECT_EQ(put_down, 0) << name << ", " << mode.name;
          EXPECT_LE(out_of_reach, static_cast<long>(out->size()) / 100) << name << ", " << mode.name;
        }
        const float guard_bound = limits.pelvis_speed_max * options.motion_guard.speed_margin;
        EXPECT_LE(fastest, std::max(allowed, guard_bound) + 1e-3f)
            << name << ", " << degradation.name << ", " << mode.name;
        ++runs;
        misses += fastest > allowed;
      }
    }
  }
  std::printf("issue #22 target (pelvis ≤ max(2 × capture's, capture's + 1 m/s)) missed in %d of %d runs\n", misses,
              runs);
  put_down_walk(*database, test_folder / "dataset-1_walk_normal_001.bvh", *rig);
  if (clips_tested == 0) GTEST_SKIP() << "none of the chosen bandai-namco-1 clips is in " << test_folder;
}

}  // namespace
}  // namespace mocap

#include "motion/reconstruct/footskate_cleanup.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "motion/core/gaussian_kernel.h"
#include "motion/core/low_pass_kernel.h"

#include "tests/support/synthetic_database.h"

namespace mocap {
namespace {

BodyPose PoseOfRow(const ReconstructionDatabase& db, int row) {
  const Eigen::VectorXf m = db.pose_feature(row).transpose();
  return db.body().Pose(Eigen::Quaternionf::Identity(), Eigen::Vector3f(0, 0.9f, 0), m.data() + 2);
}

TEST(FootskateCleanupTest, LegIkReachesTheTargetAndKeepsTheFootOrientation) {
  const auto setup = testing::MakeSyntheticReconstructionSetup({}, 40);
  const ReconstructionDatabase& db = *setup.database;
  const int ankle = setup.rig.topology.landmarks.left_ankle;
  std::vector<Eigen::Quaternionf> r0, r1;
  std::vector<Eigen::Vector3f> p0, p1;
  for (const Eigen::Vector3f& move : {Eigen::Vector3f(0.05f, 0.0f, 0.0f), Eigen::Vector3f(0.0f, 0.08f, -0.04f)}) {
    BodyPose pose = PoseOfRow(db, 20);
    db.body().WorldTransforms(pose, &r0, &p0);
    const Eigen::Vector3f target = p0[ankle] + move;
    SolveLegIk(db.body(), ankle, target, &pose);
    db.body().WorldTransforms(pose, &r1, &p1);
    EXPECT_LT((p1[ankle] - target).norm(), 1e-4f);
    EXPECT_LT(r1[ankle].angularDistance(r0[ankle]), 1e-3f);
    const int knee = db.body().skeleton().parent(ankle);
    EXPECT_NEAR((p1[knee] - p1[ankle]).norm(), (p0[knee] - p0[ankle]).norm(), 1e-5f);  // bones keep their lengths
    EXPECT_LT((p1[setup.rig.topology.landmarks.right_ankle] - p0[setup.rig.topology.landmarks.right_ankle]).norm(),
              1e-6f);
  }
}

TEST(FootskateCleanupTest, ALegBentOverItsPinKeepsItsKneeAboveTheFloor) {
  const auto setup = testing::MakeSyntheticReconstructionSetup({}, 40);
  const ReconstructionDatabase& db = *setup.database;
  const int ankle = setup.rig.topology.landmarks.left_ankle;
  const int knee = db.body().skeleton().parent(ankle);
  std::vector<Eigen::Quaternionf> rotations;
  std::vector<Eigen::Vector3f> positions;
  // The leg bent (the foot lifted forward), then sent back to where it stood: its knee goes down
  // from `bent` to `straight` on the way.
  BodyPose start = PoseOfRow(db, 20);
  db.body().WorldTransforms(start, &rotations, &positions);
  const Eigen::Vector3f stood = positions[ankle];
  const float straight = positions[knee].y();
  SolveLegIk(db.body(), ankle, stood + Eigen::Vector3f(0.0f, 0.25f, 0.15f), &start);
  db.body().WorldTransforms(start, &rotations, &positions);
  const Eigen::Vector3f from = positions[ankle];
  const float bent = positions[knee].y();
  ASSERT_GT(bent, straight + 0.05f);

  // A floor under the straight leg's knee: the pin is reached.
  BodyPose pose = start;
  EXPECT_EQ(SolveLegIkKneeAboveFloor(db.body(), ankle, stood, straight - 0.01f, &pose), 1.0f);
  db.body().WorldTransforms(pose, &rotations, &positions);
  EXPECT_LT((positions[ankle] - stood).norm(), 1e-4f);

  // A floor halfway up: the foot goes part of the way, as far as keeps the knee on or above it.
  const float floor = 0.5f * (straight + bent);
  pose = start;
  const float part = SolveLegIkKneeAboveFloor(db.body(), ankle, stood, floor, &pose);
  EXPECT_GT(part, 0.0f);
  EXPECT_LT(part, 1.0f);
  db.body().WorldTransforms(pose, &rotations, &positions);
  EXPECT_GE(positions[knee].y(), floor - 1e-5f);
  EXPECT_LT(positions[knee].y(), floor + 0.05f * (bent - straight));  // not short of it by more than the bisection
  EXPECT_LT((positions[ankle] - (from + part * (stood - from))).norm(), 1e-4f);

  // A knee already under the floor goes no lower, and may stay where it is.
  pose = start;
  EXPECT_EQ(SolveLegIkKneeAboveFloor(db.body(), ankle, stood, bent + 0.1f, &pose), 0.0f);
  db.body().WorldTransforms(pose, &rotations, &positions);
  EXPECT_NEAR(positions[knee].y(), bent, 1e-5f);
}

TEST(FootskateCleanupTest, APlantedFootStaysWhereItLandedAndIsReleasedSmoothly) {
  const auto setup = testing::MakeSyntheticReconstructionSetup({}, 40);
  const ReconstructionDatabase& db = *setup.database;
  FootskateCleaner cleaner(db.body(), db.planted_ankle_height(), db.frame_time(), {});
  const int ankle = setup.rig.topology.landmarks.left_ankle;
  std::vector<Eigen::Quaternionf> rotations;
  std::vector<Eigen::Vector3f> positions;
  // The estimated left ankle rests on the ground while the solved pose drifts forward 1 cm/frame:
  // the cleanup holds the foot at its first planted position.
  std::optional<Eigen::Vector3f> pinned;
  for (int f = 0; f < 10; ++f) {
    BodyPose pose = PoseOfRow(db, 20);
    pose.root_position.z() += 0.01f * f;
    const std::array<Eigen::Vector3f, 2> estimate = {Eigen::Vector3f(0.1f, db.planted_ankle_height(), 0.0f),
                                                     Eigen::Vector3f(-0.1f, 0.5f, 0.0f)};
    const auto contact = cleaner.Process(estimate, nullptr, &pose);
    db.body().WorldTransforms(pose, &rotations, &positions);
    if (f == 0) continue;  // no speed yet
    EXPECT_TRUE(contact[0]);
    EXPECT_FALSE(contact[1]);  // high above the ground
    if (!pinned) pinned = positions[ankle];
    EXPECT_LT((positions[ankle] - *pinned).norm(), 1e-4f) << f;
  }
  // The estimate lifts off: the correction fades over the release frames, without a jump.
  float previous_offset = 1e9f;
  for (int f = 10; f < 16; ++f) {
    BodyPose pose = PoseOfRow(db, 20);
    pose.root_position.z() += 0.01f * f;
    BodyPose free = pose;
    const auto contact =
        cleaner.Process({Eigen::Vector3f(0.1f, 0.4f, 0.0f), Eigen::Vector3f(-0.1f, 0.5f, 0.0f)}, nullptr, &pose);
    EXPECT_FALSE(contact[0]);
    db.body().WorldTransforms(pose, &rotations, &positions);
    std::vector<Eigen::Quaternionf> free_rotations;
    std::vector<Eigen::Vector3f> free_positions;
    db.body().WorldTransforms(free, &free_rotations, &free_positions);
    const float offset = (positions[ankle] - free_positions[ankle]).norm();
    EXPECT_TRUE(offset < previous_offset || offset < 1e-6f) << offset << " after " << previous_offset;
    previous_offset = offset;
  }
  EXPECT_LT(previous_offset, 1e-5f);
}

// A contact breaks for a frame (the estimate lifts and lands again) while the solve under the
// planted foot has drifted 2 cm a frame: the new contact begins where the released foot is, part
// of the way back to the solve, not at the solve a step's length away (a slide along the ground
// in one frame, the foot skate of the contact breaks that fixed lags see).
TEST(FootskateCleanupTest, AContactThatResumesDuringAReleaseBeginsWhereTheFootIs) {
  const auto setup = testing::MakeSyntheticReconstructionSetup({}, 40);
  const ReconstructionDatabase& db = *setup.database;
  const FootskateOptions options;
  FootskateCleaner cleaner(db.body(), db.planted_ankle_height(), db.frame_time(), options);
  const int ankle = setup.rig.topology.landmarks.left_ankle;
  const Eigen::Vector3f ground(0.1f, db.planted_ankle_height(), 0.0f);
  const Eigen::Vector3f lifted(0.1f, 0.4f, 0.0f);
  const Eigen::Vector3f high(-0.1f, 0.5f, 0.0f);
  std::vector<Eigen::Quaternionf> rotations;
  std::vector<Eigen::Vector3f> positions;
  auto step = [&](int f, const Eigen::Vector3f& estimate, Eigen::Vector3f* solved) {
    BodyPose pose = PoseOfRow(db, 20);
    pose.root_position.z() += 0.02f * static_cast<float>(f);
    db.body().WorldTransforms(pose, &rotations, &positions);
    *solved = positions[ankle];
    const bool contact = cleaner.Process({estimate, high}, nullptr, &pose)[0];
    db.body().WorldTransforms(pose, &rotations, &positions);
    return std::pair{contact, positions[ankle]};
  };
  Eigen::Vector3f solved;
  Eigen::Vector3f pin;
  for (int f = 0; f < 10; ++f) pin = step(f, ground, &solved).second;
  const float drift = (solved - pin).norm();
  ASSERT_GT(drift, 0.15f);
  const auto [lifted_contact, released] = step(10, lifted, &solved);  // the release's first step
  ASSERT_FALSE(lifted_contact);
  const auto [landed_contact, landed] = step(11, ground, &solved);
  ASSERT_TRUE(landed_contact);
  // One more release step from where it was (a fifth of the offset, with the body's 2 cm), not the
  // rest of the way to the solve.
  EXPECT_LT((landed - released).norm(), 0.5f * drift);
  EXPECT_GT((landed - solved).norm(), 0.5f * drift);
  // And it stays there while the contact lasts.
  for (int f = 12; f < 16; ++f) EXPECT_LT((step(f, ground, &solved).second - landed).norm(), 1e-4f) << f;
}

// A stream's planted foot: its estimate wobbles 2 cm back and forth along the ground every frame
// (0.6 m/s from one frame to the next at 30 fps, twice the contact speed) about where it stands.
// Whole-clip rules end the contact at every wobble; a stream's hold the contact through it and
// pin the foot at the wobble's mean, and end it within the hold span once the foot really moves.
TEST(FootskateCleanupTest, AStreamHoldsAWobblingPlantedFootAtItsMeanAndReleasesARealStep) {
  const auto setup = testing::MakeSyntheticReconstructionSetup({}, 40);
  const ReconstructionDatabase& db = *setup.database;
  const int ankle = setup.rig.topology.landmarks.left_ankle;
  const float ground = db.planted_ankle_height();
  const FootskateOptions options;
  ASSERT_GT(0.02f / static_cast<float>(db.frame_time()), options.contact_speed);
  auto wobble = [&](int f) { return Eigen::Vector3f(0.1f, ground, f % 2 == 0 ? 0.0f : 0.02f); };
  const Eigen::Vector3f high(-0.1f, 0.5f, 0.0f);
  std::vector<Eigen::Quaternionf> rotations;
  std::vector<Eigen::Vector3f> positions;
  for (const bool streaming : {false, true}) {
    SCOPED_TRACE(streaming ? "stream" : "whole clip");
    FootskateCleaner cleaner(db.body(), ground, db.frame_time(), options, streaming);
    // Frame 0 has no speed; frame 1 steps 2 cm; the wobble starts after two still frames.
    std::vector<Eigen::Vector3f> estimates = {wobble(0), wobble(0), wobble(0)};
    for (int f = 0; f < 20; ++f) estimates.push_back(wobble(f + 1));
    int contacts = 0;
    Eigen::Vector3f last_ankle = Eigen::Vector3f::Zero();
    for (size_t f = 0; f < estimates.size(); ++f) {
      BodyPose pose = PoseOfRow(db, 20);
      const auto contact = cleaner.Process({estimates[f], high}, nullptr, &pose);
      db.body().WorldTransforms(pose, &rotations, &positions);
      if (f >= 3) contacts += contact[0] ? 1 : 0;
      last_ankle = positions[ankle];
    }
    if (!streaming) {
      EXPECT_EQ(contacts, 0);  // every frame's step is above the contact speed
      continue;
    }
    EXPECT_EQ(contacts, 20);
    // The pin moved from where the contact began (z = 0) towards the wobble's mean (z = 1 cm).
    BodyPose unpinned = PoseOfRow(db, 20);
    std::vector<Eigen::Quaternionf> r0;
    std::vector<Eigen::Vector3f> p0;
    db.body().WorldTransforms(unpinned, &r0, &p0);
    EXPECT_NEAR(last_ankle.z() - p0[ankle].z(), 0.01f * 20.0f / 22.0f, 2e-3f);
    // A real step: 1.5 cm a frame (0.45 m/s) along the ground, steadily. The contact ends within
    // the hold span (0.1 s) plus a frame.
    const int hold = static_cast<int>(std::lround(options.stream_hold_seconds / db.frame_time()));
    int released_after = -1;
    for (int f = 1; f <= 10 && released_after < 0; ++f) {
      BodyPose pose = PoseOfRow(db, 20);
      const Eigen::Vector3f step(0.1f, ground, 0.01f + 0.015f * static_cast<float>(f));
      if (!cleaner.Process({step, high}, nullptr, &pose)[0]) released_after = f;
    }
    EXPECT_GE(released_after, 1);
    EXPECT_LE(released_after, hold + 1);
  }
}

TEST(FootskateCleanupTest, ContactsCanComeFromTheChosenDatabaseFrame) {
  const auto setup = testing::MakeSyntheticReconstructionSetup({}, 40);
  const ReconstructionDatabase& db = *setup.database;
  const FootskateOptions options;
  // A captured frame whose left foot rests on the ground and whose right foot swings.
  DatabaseFrame frame{};
  frame.ankle_position[0][1] = db.planted_ankle_height();
  frame.ankle_velocity[0][0] = 0.05f;
  frame.ankle_position[1][1] = db.planted_ankle_height() + 0.01f;
  frame.ankle_velocity[1][2] = 1.2f;
  EXPECT_EQ(PlantedFeet(frame, db.planted_ankle_height(), options), (std::array<bool, 2>{true, false}));
  frame.ankle_position[0][1] = db.planted_ankle_height() + options.contact_height + 0.01f;  // lifted
  EXPECT_FALSE(PlantedFeet(frame, db.planted_ankle_height(), options)[0]);
  frame.ankle_position[0][1] = db.planted_ankle_height();

  // The estimate races along (no contact by its own speed), but the database frame says planted:
  // the database source pins the foot, the estimate source does not, and both (the default) need
  // both to say so.
  EXPECT_EQ(FootskateOptions{}.contact_source, ContactSource::kBoth);
  for (ContactSource source : {ContactSource::kDatabaseFrame, ContactSource::kEstimatedAnkles, ContactSource::kBoth}) {
    FootskateCleaner cleaner(db.body(), db.planted_ankle_height(), db.frame_time(), {.contact_source = source});
    std::array<bool, 2> contact{};
    for (int f = 0; f < 3; ++f) {
      BodyPose pose = PoseOfRow(db, 20);
      const std::array<Eigen::Vector3f, 2> estimate = {Eigen::Vector3f(0.1f, db.planted_ankle_height(), 0.1f * f),
                                                       Eigen::Vector3f(-0.1f, 0.5f, 0.0f)};
      contact = cleaner.Process(estimate, &frame, &pose);
    }
    EXPECT_EQ(contact[0], source == ContactSource::kDatabaseFrame);
    EXPECT_FALSE(contact[1]);
  }
}

// The left estimate swings in high for 6 frames, stands `contact` frames wandering about z = 0.03
// slowly enough to count as planted, then swings off for `after` frames; the right one stays in
// the air throughout.
std::vector<AnklePair> StepEstimates(const ReconstructionDatabase& db, int contact, int after, float* mean_z) {
  const float slow = 0.3f * FootskateOptions{}.contact_speed * static_cast<float>(db.frame_time());
  const float wander[8] = {-slow, 0.5f * slow, slow, 0.25f * slow, -0.5f * slow, -slow, 0.75f * slow, 0.1f * slow};
  const Eigen::Vector3f right(-0.1f, 0.5f, 0);
  std::vector<AnklePair> estimates;
  // (the last swing frame right above the landing, so that the landing's step counts as planted)
  for (int f = 0; f < 6; ++f) estimates.push_back({Eigen::Vector3f(0.1f, 0.3f, 0.03f - slow - 0.05f * (5 - f)), right});
  float sum = 0;
  for (int f = 0; f < contact; ++f) {
    estimates.push_back({Eigen::Vector3f(0.1f, db.planted_ankle_height(), 0.03f + wander[f % 8]), right});
    sum += estimates.back()[0].z();
  }
  for (int f = 0; f < after; ++f) estimates.push_back({Eigen::Vector3f(0.1f, 0.3f, 0.1f + 0.05f * f), right});
  *mean_z = sum / static_cast<float>(contact);
  return estimates;
}

TEST(FootskateCleanupTest, AWholeContactIsPlantedAtItsMeanAndEasedInAndOut) {
  const auto setup = testing::MakeSyntheticReconstructionSetup({}, 40);
  const ReconstructionDatabase& db = *setup.database;
  const FootskateOptions options;
  const int contact = static_cast<int>(std::ceil(options.plant_min_seconds / db.frame_time())) + 3;
  float mean_z = 0;
  const std::vector<AnklePair> estimates = StepEstimates(db, contact, 6, &mean_z);
  std::vector<AnklePair> planted = estimates;
  PlantAnkleContacts(planted, nullptr, false, db.planted_ankle_height(), db.frame_time(), options);
  for (int f = 6; f < 6 + contact; ++f) {
    EXPECT_NEAR(planted[f][0].z(), mean_z, 1e-6f) << f;
    EXPECT_NEAR(planted[f][0].y(), db.planted_ankle_height(), 1e-6f) << f;
  }
  // Eased: the offset towards the mean shrinks frame by frame away from the contact, to none.
  const float landing = planted[6][0].z() - estimates[6][0].z(),
              lift = planted[5 + contact][0].z() - estimates[5 + contact][0].z();
  ASSERT_GT(std::abs(landing), 1e-4f);
  ASSERT_GT(std::abs(lift), 1e-4f);
  for (int k = 1; k <= options.release_frames; ++k) {
    const float fraction =
        static_cast<float>(options.release_frames + 1 - k) / static_cast<float>(options.release_frames + 1);
    EXPECT_NEAR(planted[6 - k][0].z() - estimates[6 - k][0].z(), fraction * landing, 1e-6f) << k;
    EXPECT_NEAR(planted[5 + contact + k][0].z() - estimates[5 + contact + k][0].z(), fraction * lift, 1e-6f) << k;
  }
  EXPECT_EQ(planted[0][0], estimates[0][0]);
  for (size_t f = 0; f < estimates.size(); ++f) EXPECT_EQ(planted[f][1], estimates[f][1]) << f;  // in the air
}

TEST(FootskateCleanupTest, ContactsNotSeenWholeOrShortAreLeftAsTheyAre) {
  const auto setup = testing::MakeSyntheticReconstructionSetup({}, 40);
  const ReconstructionDatabase& db = *setup.database;
  const FootskateOptions options;
  const int contact = static_cast<int>(std::ceil(options.plant_min_seconds / db.frame_time())) + 3;
  auto plant = [&](std::vector<AnklePair> ankles, const AnklePair* before, bool segment_ends) {
    PlantAnkleContacts(ankles, before, segment_ends, db.planted_ankle_height(), db.frame_time(), options);
    return ankles;
  };
  float mean_z = 0;
  // Too short.
  const std::vector<AnklePair> brief = StepEstimates(db, 4, 6, &mean_z);
  EXPECT_EQ(plant(brief, nullptr, true), brief);
  // Going on past the stretch: left unless the segment ends there.
  const std::vector<AnklePair> standing = StepEstimates(db, contact, 0, &mean_z);
  EXPECT_EQ(plant(standing, nullptr, false), standing);
  EXPECT_NEAR(plant(standing, nullptr, true).back()[0].z(), mean_z, 1e-6f);
  // Begun before the stretch (the frame before it stands there too).
  const std::vector<AnklePair> landed = StepEstimates(db, contact, 6, &mean_z);
  const std::vector<AnklePair> rest(landed.begin() + 6, landed.end());
  EXPECT_EQ(plant(rest, &landed[5], true),
            rest);  // frame 5 swings: the contact begins inside, but its ease would not fit
  const AnklePair standing_before = {rest.front()[0], rest.front()[1]};
  EXPECT_EQ(plant(rest, &standing_before, true), rest);
  // Off: nothing planted.
  FootskateOptions off = options;
  off.plant_min_seconds = 0;
  std::vector<AnklePair> unchanged = landed;
  PlantAnkleContacts(unchanged, nullptr, true, db.planted_ankle_height(), db.frame_time(), off);
  EXPECT_EQ(unchanged, landed);
}

// StepEstimates with a second contact after the first: the left ankle slides 20 cm forward over
// `slide` frames (the last one there), `lift` above the planted height at the slide's middle, then
// stands again.
std::vector<AnklePair> SlideEstimates(const ReconstructionDatabase& db, int contact, int slide, float lift) {
  float unused = 0;
  std::vector<AnklePair> estimates = StepEstimates(db, contact, 0, &unused);
  const std::vector<AnklePair> second = StepEstimates(db, contact, 6, &unused);
  const AnklePair last = estimates.back();
  for (int f = 1; f <= slide; ++f) {
    AnklePair frame = last;
    frame[0].z() += 0.2f * static_cast<float>(f) / static_cast<float>(slide);
    if (f == (slide + 1) / 2) frame[0].y() += lift;
    estimates.push_back(frame);
  }
  for (size_t f = 6; f < second.size(); ++f) {
    AnklePair frame = second[f];
    frame[0].z() += 0.2f;
    estimates.push_back(frame);
  }
  return estimates;
}

TEST(FootskateCleanupTest, AFootThatSlidesWithoutLiftingWhileTheBodyStandsIsOneContact) {
  const auto setup = testing::MakeSyntheticReconstructionSetup({}, 40);
  const ReconstructionDatabase& db = *setup.database;
  const FootskateOptions options;
  const int contact = static_cast<int>(std::ceil(options.plant_min_seconds / db.frame_time())) + 3, slide = 5;
  const float standing_speed = 0.25f;
  auto plant = [&](const std::vector<AnklePair>& estimates, float hands_speed) {
    std::vector<Eigen::Vector2f> hands;  // the wrists' midpoint travelling forward at hands_speed
    for (size_t f = 0; f < estimates.size(); ++f) {
      hands.emplace_back(0.0f, hands_speed * static_cast<float>(f * db.frame_time()));
    }
    std::vector<AnklePair> planted = estimates;
    PlantAnkleContacts(planted, nullptr, true, db.planted_ankle_height(), db.frame_time(), options,
                       {hands, standing_speed});
    return planted;
  };
  const int first = 6, last = first + 2 * contact + slide;  // the two contacts and the slide between
  auto mean_z = [&](const std::vector<AnklePair>& ankles, int begin, int end) {
    float sum = 0;
    for (int f = begin; f < end; ++f) sum += ankles[f][0].z();
    return sum / static_cast<float>(end - begin);
  };
  // Standing hands, a foot that never lifts: one contact, planted at the mean of all its frames.
  const std::vector<AnklePair> slid = SlideEstimates(db, contact, slide, 0.0f);
  const std::vector<AnklePair> held = plant(slid, 0.0f);
  const float whole_mean = mean_z(slid, first, last);
  for (int f = first; f < last; ++f) EXPECT_NEAR(held[f][0].z(), whole_mean, 1e-5f) << f;
  // The hands travel (a walk): two contacts, each at its own mean; the slide is eased between them.
  const std::vector<AnklePair> walked = plant(slid, 4.0f * standing_speed);
  EXPECT_NEAR(walked[first][0].z(), mean_z(slid, first, first + contact), 1e-5f);
  EXPECT_NEAR(walked[last - 1][0].z(), mean_z(slid, last - contact, last), 1e-5f);
  // The foot lifts between them (a step): two contacts too.
  const std::vector<AnklePair> stepped = SlideEstimates(db, contact, slide, 2.0f * options.contact_height);
  const std::vector<AnklePair> steps = plant(stepped, 0.0f);
  EXPECT_NEAR(steps[first][0].z(), mean_z(stepped, first, first + contact), 1e-5f);
  EXPECT_NEAR(steps[last - 1][0].z(), mean_z(stepped, last - contact, last), 1e-5f);
  // No hands given: never joined.
  std::vector<AnklePair> alone = slid;
  PlantAnkleContacts(alone, nullptr, true, db.planted_ankle_height(), db.frame_time(), options);
  EXPECT_NEAR(alone[first][0].z(), mean_z(slid, first, first + contact), 1e-5f);
}

// The feet's pins as a filter that looks ahead eases them (issue #25): a contact's pin whole
// inside it, a fraction about its ends that rises and falls smoothly, never past the pin.
std::vector<std::optional<EasedPin>> EasedPinsOf(const std::vector<float>& kernel,
                                                 const std::vector<std::optional<Eigen::Vector3f>>& track) {
  const int radius = static_cast<int>(kernel.size()) / 2, n = static_cast<int>(track.size());
  std::vector<std::optional<EasedPin>> eased;
  std::vector<std::optional<Eigen::Vector3f>> pins(kernel.size());
  for (int f = 0; f < n; ++f) {
    for (int i = -radius; i <= radius; ++i) pins[i + radius] = track[std::clamp(f + i, 0, n - 1)];
    eased.push_back(EasePin(kernel, pins));
  }
  return eased;
}

TEST(FootskateCleanupTest, AFilterEasesAFootOnAndOffItsPinWithoutOvershoot) {
  // Free for 20 frames, planted at A for 20, free for 10, planted at B for 20.
  const Eigen::Vector3f a(0.1f, 0.05f, 0.3f), b(0.1f, 0.05f, 0.9f);
  std::vector<std::optional<Eigen::Vector3f>> track(70);
  for (int f = 20; f < 40; ++f) track[f] = a;
  for (int f = 50; f < 70; ++f) track[f] = b;
  for (const std::vector<float>& kernel : {GaussianKernel(1.0f), LowPassKernel(1.0f), LowPassKernel(2.0f)}) {
    const int radius = static_cast<int>(kernel.size()) / 2;
    const auto eased = EasedPinsOf(kernel, track);
    for (int f = 0; f < 20 - radius; ++f) EXPECT_FALSE(eased[f]) << "free, no contact in reach: frame " << f;
    for (int f = 20 + radius; f < 40 - radius; ++f) {  // the whole kernel inside the contact: its pin, all the way
      ASSERT_TRUE(eased[f]);
      EXPECT_EQ(eased[f]->weight, 1.0f);
      EXPECT_LT((eased[f]->target - a).norm(), 1e-6f);
    }
    for (int f = 0; f < 70; ++f) {
      if (!eased[f]) continue;
      EXPECT_GT(eased[f]->weight, 0.0f);
      EXPECT_LE(eased[f]->weight, 1.0f);
      // Between the two pins, on the segment joining them: no negative lobe pushes it past either.
      const Eigen::Vector3f& t = eased[f]->target;
      EXPECT_LT(std::abs(t.x() - a.x()) + std::abs(t.y() - a.y()), 1e-6f) << "frame " << f;
      EXPECT_GE(t.z(), a.z() - 1e-6f);
      EXPECT_LE(t.z(), b.z() + 1e-6f);
    }
    // Onto A and off it the weight rises, then falls, a frame at a time, without steps: the most
    // one frame changes it is the kernel's largest weight.
    const float largest = *std::max_element(kernel.begin(), kernel.end()) / [&] {
      float positive = 0;
      for (const float w : kernel) positive += std::max(0.0f, w);
      return positive;
    }();
    float previous = 0;
    for (int f = 0; f < 30; ++f) {
      const float weight = eased[f] ? eased[f]->weight : 0.0f;
      EXPECT_GE(weight, previous - 1e-6f) << "frame " << f;
      EXPECT_LE(weight - previous, largest + 1e-6f) << "frame " << f;
      previous = weight;
    }
    ASSERT_TRUE(eased[20] && eased[39]);  // a contact's first and last frames: on their way
    EXPECT_GT(eased[20]->weight, 0.4f);
    EXPECT_LT(eased[20]->weight, 1.0f);
    EXPECT_GT(eased[39]->weight, 0.4f);
    EXPECT_LT(eased[39]->weight, 1.0f);
  }
}

TEST(FootskateCleanupTest, AOneFramePlantIsATugNotAStop) {
  // The cleaner planted a foot for one frame: the filtered foot goes a kernel's centre weight of
  // the way to it, not onto it and off again (a jerk of metres per second cubed).
  std::vector<std::optional<Eigen::Vector3f>> track(21);
  track[10] = Eigen::Vector3f(0.0f, 0.05f, 0.5f);
  const std::vector<float> kernel = GaussianKernel(1.0f);
  const auto eased = EasedPinsOf(kernel, track);
  ASSERT_TRUE(eased[10]);
  EXPECT_NEAR(eased[10]->weight, kernel[kernel.size() / 2], 1e-6f);
  EXPECT_LT(eased[10]->weight, 0.5f);
  EXPECT_LT((eased[10]->target - *track[10]).norm(), 1e-6f);
  EXPECT_FALSE(EasePin(kernel, std::vector<std::optional<Eigen::Vector3f>>(kernel.size())));
}

}  // namespace
}  // namespace mocap

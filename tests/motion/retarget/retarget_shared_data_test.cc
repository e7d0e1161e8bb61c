// Issue #12's figures on real data: held-out bandai-namco-2 clips reconstructed from noisy wrists
// (a database of every 3rd clip of the standard split's database part, to keep the test short),
// then retargeted onto the cmu-cc rig (100 joints, cm, every bone along +Y at rest) and onto rigs
// made from the database's own (renamed with a split bone and other proportions; Z up in inches).
// Per target: landmark error against the database-rig result after normalising by leg length, and
// foot skate on the reconstruction's contacts beside the database-rig output's. With
// MOCAP_RETARGET_OUT set, the BVH files are written there (to view them, or import them in Blender).
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <random>

#include <gtest/gtest.h>

#include "motion/bvh/bvh_reader.h"
#include "motion/bvh/bvh_writer.h"
#include "motion/preprocess/clip_labels.h"
#include "motion/reconstruct/reconstruction_export.h"
#include "motion/reconstruct/reconstruction_session.h"
#include "motion/retarget/retarget_export.h"
#include "motion/retarget/retargeter.h"
#include "motion/skeleton/forward_kinematics.h"
#include "tests/support/rig_variants.h"
#include "tests/support/shared_data.h"

namespace mocap {
namespace {

int TakeOf(const std::string& file_name) {
  const std::string take = LabelValue(ParseClipLabels(file_name), "take");
  return take.empty() ? -1 : std::stoi(take);
}

// The clip's world turned Z up (the root's channels carry the turn), as a Z-up exporter writes it.
void TurnZUp(BvhClip& clip) {
  LocalMotion motion = MotionFromChannels(clip.skeleton, clip.channels, clip.frame_time);
  RotateWorld(motion, Eigen::Quaternionf(Eigen::AngleAxisf(static_cast<float>(M_PI) / 2, Eigen::Vector3f::UnitX())));
  clip.channels = ChannelsFromMotion(clip.skeleton, motion);
}

struct Figures {
  double landmark_error[4] = {0, 0, 0, 0};    // wrists, ankles, head, pelvis: leg lengths
  double skate_source = 0, skate_target = 0;  // cm per contact frame, at the database's scale
  long frames = 0, contact_frames = 0;
};

TEST(RetargetSharedDataTest, HeldOutClipsOnTheCmuRigAndOnReRiggedCopies) {
  MOCAP_REQUIRE_SHARED_DATA(bandai, "bandai-namco-2");
  MOCAP_REQUIRE_SHARED_DATA(cmu, "cmu-cc");
  const auto files = testing::BvhFilesIn(bandai);
  auto first = ReadBvhFile(files.front());
  ASSERT_TRUE(first.ok()) << first.status();
  auto rig = BuildRigModel(*first, {});
  ASSERT_TRUE(rig.ok()) << rig.status();
  std::vector<DatabaseClip> clips;
  std::vector<std::filesystem::path> queries;
  int kept = 0;
  for (const auto& file : files) {
    const std::string name = file.filename().string();
    if (TakeOf(name) % 10 == 3) {
      for (const char* content : {"_walk_", "_run_", "_raise-up-both-hands_"}) {
        if (name.find(content) != std::string::npos && queries.size() < 3 &&
            std::none_of(queries.begin(), queries.end(),
                         [&](const auto& q) { return q.filename().string().find(content) != std::string::npos; })) {
          queries.push_back(file);
        }
      }
      continue;
    }
    if (kept++ % 3 != 0) continue;
    auto clip = ReadBvhFile(file);
    ASSERT_TRUE(clip.ok()) << clip.status();
    auto prepared = PrepareClip(*clip, *rig, {});
    ASSERT_TRUE(prepared.ok()) << prepared.status();
    clips.push_back({prepared->features, EncodePoses(prepared->motion, *rig)});
  }
  auto database = ReconstructionDatabase::Build(*rig, clips);
  ASSERT_TRUE(database.ok()) << database.status();
  const BodyModel& body = (*database)->body();
  auto source = SourceRigOf(*rig, body.skeleton());
  ASSERT_TRUE(source.ok()) << source.status();

  // Targets: the cmu-cc rig, and the database's rig re-rigged two ways.
  std::vector<std::pair<std::string, std::string>> targets;  // name, BVH text
  {
    std::ifstream in(testing::BvhFilesIn(cmu).front());
    targets.emplace_back("cmu-cc", std::string(std::istreambuf_iterator<char>(in), {}));
    BvhClip renamed = *first;
    testing::ScaleProportions(renamed, rig->topology, {.legs = 1.15f, .arms = 0.85f, .spine = 1.1f, .head = 1.0f});
    ASSERT_TRUE(testing::SplitBone(renamed, rig->topology.landmarks.left_wrist, "split").ok());
    testing::RenameJoints(renamed);
    targets.emplace_back("renamed-split-proportions", FormatBvh(renamed));
    BvhClip z_up = *first;
    TurnZUp(z_up);
    testing::ScaleLengths(z_up, 1.0f / 2.54f);
    targets.emplace_back("z-up-inches", FormatBvh(z_up));
  }
  const char* out_dir = std::getenv("MOCAP_RETARGET_OUT");

  std::mt19937 random(12);
  std::normal_distribution<float> noise(0.0f, 0.005f);
  std::vector<Figures> figures(targets.size());
  for (const auto& query : queries) {
    auto clip = ReadBvhFile(query);
    ASSERT_TRUE(clip.ok());
    auto prepared = PrepareClip(*clip, *rig, {});
    ASSERT_TRUE(prepared.ok());
    const GlobalPoses truth = ForwardKinematics(prepared->skeleton, prepared->motion);
    std::vector<WristSample> samples;
    for (int f = 0; f < truth.num_frames(); ++f) {
      WristSample sample;
      sample.time = f * prepared->motion.frame_time;
      sample.left = truth.position(f, rig->topology.landmarks.left_wrist) +
                    Eigen::Vector3f(noise(random), noise(random), noise(random));
      sample.right = truth.position(f, rig->topology.landmarks.right_wrist) +
                     Eigen::Vector3f(noise(random), noise(random), noise(random));
      samples.push_back(sample);
    }
    auto frames = ReconstructOffline(*database, {}, samples);
    ASSERT_TRUE(frames.ok()) << frames.status();
    const std::string stem = query.stem().string();
    if (out_dir) {
      std::ofstream(std::filesystem::path(out_dir) / (stem + "_database-rig.bvh"))
          << FormatBvh(ReconstructionToBvh(**database, *frames));
    }
    for (size_t t = 0; t < targets.size(); ++t) {
      auto target = TargetRigFromBvh(targets[t].second);
      ASSERT_TRUE(target.ok()) << targets[t].first << ": " << target.status();
      auto retargeter = Retargeter::Create(*source, *target);
      ASSERT_TRUE(retargeter.ok()) << retargeter.status();
      const BodyLandmarks& sl = source->topology.landmarks;
      const BodyLandmarks& tl = target->topology.landmarks;
      const std::array<std::array<int, 2>, 4> source_marks{{{sl.left_wrist, sl.right_wrist},
                                                            {sl.left_ankle, sl.right_ankle},
                                                            {sl.head, sl.head},
                                                            {sl.pelvis, sl.pelvis}}};
      const std::array<std::array<int, 2>, 4> target_marks{{{tl.left_wrist, tl.right_wrist},
                                                            {tl.left_ankle, tl.right_ankle},
                                                            {tl.head, tl.head},
                                                            {tl.pelvis, tl.pelvis}}};
      const float k = retargeter->scale();
      std::vector<BodyPose> poses;
      std::vector<Eigen::Quaternionf> rotations;
      std::vector<Eigen::Vector3f> positions, previous_source, previous_target;
      Figures& fig = figures[t];
      for (size_t f = 0; f < frames->size(); ++f) {
        const ReconstructedFrame& frame = (*frames)[f];
        body.WorldTransforms(frame.pose, &rotations, &positions);
        BodyPose pose;
        retargeter->Retarget(rotations, positions, &pose);
        poses.push_back(pose);
        const std::vector<Eigen::Vector3f>& target_positions = retargeter->world_positions();
        for (int m = 0; m < 4; ++m) {
          for (int side = 0; side < 2; ++side) {
            // In leg lengths from the floor point both are scaled about.
            const Eigen::Vector3f anchor = *retargeter->anchor();
            fig.landmark_error[m] += 0.5 * ((target_positions[target_marks[m][side]] - anchor) / target->leg_length -
                                            (positions[source_marks[m][side]] - anchor) / source->leg_length)
                                               .norm();
          }
        }
        ++fig.frames;
        // Skate: ground-plane ankle travel between frames where the reconstruction plants the foot.
        if (f > 0) {
          const ReconstructedFrame& before = (*frames)[f - 1];
          for (int side = 0; side < 2; ++side) {
            if (!frame.diagnostics.contact[side] || !before.diagnostics.contact[side] ||
                frame.segment != before.segment)
              continue;
            auto ground = [](const Eigen::Vector3f& v) { return Eigen::Vector2f(v.x(), v.z()); };
            fig.skate_source +=
                100 *
                (ground(positions[source_marks[1][side]]) - ground(previous_source[source_marks[1][side]])).norm();
            fig.skate_target +=
                100 / k *
                (ground(target_positions[target_marks[1][side]]) - ground(previous_target[target_marks[1][side]]))
                    .norm();
            ++fig.contact_frames;
          }
        }
        previous_source = positions;
        previous_target = target_positions;
      }
      if (out_dir) {
        std::ofstream(std::filesystem::path(out_dir) / (stem + "_" + targets[t].first + ".bvh"))
            << FormatBvh(RetargetedToBvh(*target, poses, (*database)->frame_time()));
      }
    }
  }
  ASSERT_EQ(queries.size(), 3u);
  for (size_t t = 0; t < targets.size(); ++t) {
    Figures& fig = figures[t];
    for (double& e : fig.landmark_error) e /= static_cast<double>(fig.frames);
    const double contacts = std::max<long>(1, fig.contact_frames);
    std::cout << "[figures] target " << targets[t].first
              << ": landmark error in leg lengths (database-rig result): wrists " << fig.landmark_error[0]
              << ", ankles " << fig.landmark_error[1] << ", head " << fig.landmark_error[2] << ", pelvis "
              << fig.landmark_error[3] << "; foot skate on " << fig.contact_frames << " contact frames: target "
              << fig.skate_target / contacts << " cm/frame vs database rig " << fig.skate_source / contacts
              << " cm/frame (" << fig.frames << " frames)\n";
    // Ankles and pelvis follow exactly (scaled), hands to the reach scaled by arm length.
    EXPECT_LT(fig.landmark_error[1], 0.01) << targets[t].first;
    EXPECT_LT(fig.landmark_error[3], 0.01) << targets[t].first;
    EXPECT_LT(fig.landmark_error[0], 0.15) << targets[t].first;
    EXPECT_LT(fig.landmark_error[2], 0.15) << targets[t].first;
    // No new skating: at most a tenth of a millimetre per contact frame more than the source.
    EXPECT_LT(fig.skate_target / contacts, fig.skate_source / contacts + 0.01) << targets[t].first;
  }
}

}  // namespace
}  // namespace mocap

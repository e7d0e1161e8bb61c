// A1 features on real captured walks: the reference frame and its quantities mean what docs/method.md
// says (wrist frame x from right to left wrist, z forward, heights above the ground).
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "motion/bvh/bvh_reader.h"
#include "motion/preprocess/clip_preprocessor.h"
#include "tests/support/shared_data.h"

namespace mocap {
namespace {

float Median(std::vector<float> values) {
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

class RealDataFeaturesTest : public ::testing::TestWithParam<std::pair<const char*, const char*>> {};

TEST_P(RealDataFeaturesTest, WalkFeaturesArePlausible) {
  MOCAP_REQUIRE_SHARED_DATA(folder, GetParam().first);
  auto clip = ReadBvhFile(folder / GetParam().second);
  ASSERT_TRUE(clip.ok()) << clip.status();
  auto rig = BuildRigModel(*clip, {});
  ASSERT_TRUE(rig.ok()) << rig.status();
  auto prepared = PrepareClip(*clip, *rig, {});
  ASSERT_TRUE(prepared.ok()) << prepared.status();
  ASSERT_NEAR(prepared->motion.frame_time, 1.0 / 30.0, 1e-9);

  std::vector<float> left_x, right_x, forward_speed, ankle_height, pelvis_height, tilt;
  for (const FrameFeatures& f : prepared->features) {
    left_x.push_back(f.wrist_position[0][0]);
    right_x.push_back(f.wrist_position[1][0]);
    forward_speed.push_back(0.5f * (f.wrist_velocity[0][2] + f.wrist_velocity[1][2]));
    ankle_height.push_back(std::min(f.ankle_position[0][1], f.ankle_position[1][1]));
    pelvis_height.push_back(f.pelvis_height);
    tilt.push_back(f.pelvis_tilt);
    // Wrists are symmetric about the frame's origin on x, and z is 0 for both by construction.
    EXPECT_NEAR(f.wrist_position[0][0], -f.wrist_position[1][0], 1e-4f);
    EXPECT_NEAR(f.wrist_position[0][2], 0.0f, 1e-4f);
  }
  EXPECT_GT(Median(left_x), 0.1f);  // x axis points from the right wrist to the left one
  EXPECT_LT(Median(right_x), -0.1f);
  EXPECT_GT(Median(forward_speed), 0.5f);  // walking forward: +z in the wrist frame, m/s
  EXPECT_LT(Median(forward_speed), 2.5f);
  EXPECT_GT(Median(ankle_height), 0.03f);  // metres above the ground
  EXPECT_LT(Median(ankle_height), 0.15f);
  EXPECT_GT(Median(pelvis_height), 0.8f);
  EXPECT_LT(Median(pelvis_height), 1.15f);
  EXPECT_LT(Median(tilt), 0.35f);  // radians: upright walk
}

INSTANTIATE_TEST_SUITE_P(Walks, RealDataFeaturesTest,
                         ::testing::Values(std::pair{"bandai-namco-2", "dataset-2_walk_normal_001.bvh"},
                                           std::pair{"bandai-namco-2", "dataset-2_walk_elderly_005.bvh"},
                                           std::pair{"bandai-namco-1", "dataset-1_walk_normal_001.bvh"},
                                           std::pair{"cmu-cc", "002_01.bvh"},  // Z-up root, 60 fps
                                           std::pair{"cmu-cc", "007_01.bvh"}));

}  // namespace
}  // namespace mocap

// Wrist trajectories for the client tools: CSV samples and a BVH clip's forward kinematics.
#include "client/wrist_input/wrist_source.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <string>

#include "motion/bvh/bvh_reader.h"
#include "motion/bvh/bvh_writer.h"
#include "motion/skeleton/forward_kinematics.h"
#include "motion/skeleton/local_motion.h"
#include "tests/support/synthetic_clip.h"
#include "tests/support/temp_dir.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;

class WristSourceTest : public ::testing::Test {
 protected:
  fs::path Write(const std::string& name, const std::string& text) {
    const fs::path path = temp_.path() / name;
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }
  fs::path WriteClip(const std::string& name, const testing::SyntheticRigOptions& options, int frames = 60) {
    const fs::path path = temp_.path() / name;
    EXPECT_TRUE(WriteBvhFile(testing::MakeWalkingClip(options, frames), path).ok());
    return path;
  }
  testing::ScopedTempDir temp_;
};

constexpr char kHeader[] = "time,left_x,left_y,left_z,right_x,right_y,right_z\n";
constexpr char kHeaderWithConfidence[] =
    "time,left_x,left_y,left_z,right_x,right_y,right_z,left_confidence,right_confidence\n";

TEST_F(WristSourceTest, CsvReadsSamplesInFileOrder) {
  const fs::path path = Write("w.csv", std::string("# tracker export\n") + kHeader +
                                           "0.0, 0.2,1.0,0.1, -0.2,1.0,0.1\r\n"
                                           "\n"
                                           "0.033,0.21,1.01,0.12,-0.19,0.99,+0.13\n");
  auto samples = WristsFromCsv(path);
  ASSERT_TRUE(samples.ok()) << samples.status();
  ASSERT_EQ(samples->size(), 2u);
  const v1::WristSample& s = (*samples)[1];
  EXPECT_DOUBLE_EQ(s.time(), 0.033);
  EXPECT_FLOAT_EQ(s.left().x(), 0.21f);
  EXPECT_FLOAT_EQ(s.left().y(), 1.01f);
  EXPECT_FLOAT_EQ(s.left().z(), 0.12f);
  EXPECT_FLOAT_EQ(s.right().x(), -0.19f);
  EXPECT_FLOAT_EQ(s.right().y(), 0.99f);
  EXPECT_FLOAT_EQ(s.right().z(), 0.13f);
  EXPECT_FALSE(s.has_left_confidence());
  EXPECT_FALSE(s.has_right_confidence());
}

TEST_F(WristSourceTest, CsvAcceptsNanAndConfidences) {
  const fs::path path = Write("w.csv", std::string(kHeaderWithConfidence) +
                                           "0.0,NaN,1,0,-0.2,1,0,0.5,\n"
                                           "0.1,0.2,inf,0,-0.2,-INF,0,,1\n");
  auto samples = WristsFromCsv(path);
  ASSERT_TRUE(samples.ok()) << samples.status();
  ASSERT_EQ(samples->size(), 2u);
  EXPECT_TRUE(std::isnan((*samples)[0].left().x()));
  EXPECT_FLOAT_EQ((*samples)[0].left_confidence(), 0.5f);
  EXPECT_FALSE((*samples)[0].has_right_confidence());
  EXPECT_TRUE(std::isinf((*samples)[1].left().y()));
  EXPECT_TRUE(std::isinf((*samples)[1].right().y()));
  EXPECT_FALSE((*samples)[1].has_left_confidence());
  EXPECT_FLOAT_EQ((*samples)[1].right_confidence(), 1.0f);
}

TEST_F(WristSourceTest, CsvReadsTrackedDevicesOrientations) {
  const fs::path path =
      Write("w.csv", std::string(kHeaderWithConfidence).substr(0, std::strlen(kHeaderWithConfidence) - 1) +
                         ",left_qw,left_qx,left_qy,left_qz,right_qw,right_qx,right_qy,right_qz\n"
                         "0.0,0,1,0,0.4,1,0,,,0.7071,0,0.7071,0,1,0,0,0\n"
                         "0.1,0,1,0,0.4,1,0,,,,,,,,,,\n");
  auto samples = WristsFromCsv(path);
  ASSERT_TRUE(samples.ok()) << samples.status();
  ASSERT_EQ(samples->size(), 2u);
  EXPECT_FLOAT_EQ((*samples)[0].left_orientation().w(), 0.7071f);
  EXPECT_FLOAT_EQ((*samples)[0].left_orientation().y(), 0.7071f);
  EXPECT_FLOAT_EQ((*samples)[0].right_orientation().w(), 1.0f);
  EXPECT_FALSE((*samples)[1].has_left_orientation());  // the server refuses it for a tracked device
  // A quaternion is not a confidence: no 0..1 limit.
  EXPECT_TRUE(WristsFromCsv(Write("q.csv",
                                  "time,left_x,left_y,left_z,right_x,right_y,right_z,left_confidence,"
                                  "right_confidence,left_qw,left_qx,left_qy,left_qz,right_qw,right_qx,right_qy,"
                                  "right_qz\n0,0,1,0,0,1,0,,,-1,0,0,0,-1,0,0,0\n"))
                  .ok());
}

// Each bad input names the file and the line, and says what was expected.
TEST_F(WristSourceTest, CsvErrorsNameTheLine) {
  struct Case {
    std::string text;
    std::string expected;  // substring of the message
  };
  const std::vector<Case> cases = {
      {"t,lx,ly,lz,rx,ry,rz\n0,0,0,0,0,0,0\n", "w.csv:1: expected the header time,left_x"},
      {"time,left_x,left_y,left_z,right_x,right_y\n", "w.csv:1: expected the header"},
      // Found while writing the CSV fuzz target: a header longer than the known columns was read past them.
      {std::string("time,left_x,left_y,left_z,right_x,right_y,right_z,left_confidence,right_confidence,x,y\n"),
       "w.csv:1: expected the header"},
      {std::string(kHeader) + "0,0,1,0,0,1,0\n0.1,0,1,0,0,1\n", "w.csv:3: expected 7 fields as in the header, found 6"},
      {std::string(kHeader) + "0,0,1,0,0,1,0,1\n", "w.csv:2: expected 7 fields"},
      {std::string(kHeader) + "\n0,0,1,0,0,abc,0\n", "w.csv:3: right_y is not a number: \"abc\""},
      {std::string(kHeader) + "0,0,1,0,0,,0\n", "w.csv:2: right_y is not a number"},
      {std::string(kHeader) + "0,0,1.0.0,0,0,1,0\n", "w.csv:2: left_y is not a number"},
      {std::string(kHeaderWithConfidence) + "0,0,1,0,0,1,0,1.5,1\n", "w.csv:2: left_confidence must lie in 0..1"},
      {std::string(kHeader), "no samples after the header"},
      {"\n# only a comment\n", "empty file"},
  };
  for (const Case& c : cases) {
    auto samples = WristsFromCsv(Write("w.csv", c.text));
    ASSERT_FALSE(samples.ok()) << c.text;
    EXPECT_EQ(samples.status().code(), absl::StatusCode::kInvalidArgument) << c.text;
    EXPECT_NE(samples.status().message().find(c.expected), std::string::npos)
        << "input:\n"
        << c.text << "message: " << samples.status().message();
  }
}

TEST_F(WristSourceTest, CsvMissingFileIsNotFound) {
  EXPECT_EQ(WristsFromCsv(temp_.path() / "absent.csv").status().code(), absl::StatusCode::kNotFound);
}

// The plain synthetic rig is Y up in centimetres: the samples are its hand joints' positions by
// forward kinematics, in metres, one per frame at the clip's rate.
TEST_F(WristSourceTest, BvhGivesTheWristJointsInMetres) {
  const fs::path path = WriteClip("walk.bvh", {}, 60);
  auto samples = WristsFromBvh(path, 0.0, 1);
  ASSERT_TRUE(samples.ok()) << samples.status();
  ASSERT_EQ(samples->size(), 60u);

  auto clip = ReadBvhFile(path);
  ASSERT_TRUE(clip.ok());
  const GlobalPoses truth =
      ForwardKinematics(clip->skeleton, MotionFromChannels(clip->skeleton, clip->channels, clip->frame_time));
  const int left = clip->skeleton.Find("LeftHand");
  const int right = clip->skeleton.Find("RightHand");
  ASSERT_GE(left, 0);
  ASSERT_GE(right, 0);
  for (int f = 0; f < 60; ++f) {
    const v1::WristSample& s = (*samples)[f];
    EXPECT_NEAR(s.time(), f * clip->frame_time, 1e-9);
    const Eigen::Vector3f l = truth.position(f, left) / 100.0f;
    const Eigen::Vector3f r = truth.position(f, right) / 100.0f;
    EXPECT_NEAR(s.left().x(), l.x(), 1e-4) << "frame " << f;
    EXPECT_NEAR(s.left().y(), l.y(), 1e-4) << "frame " << f;
    EXPECT_NEAR(s.left().z(), l.z(), 1e-4) << "frame " << f;
    EXPECT_NEAR(s.right().x(), r.x(), 1e-4) << "frame " << f;
    EXPECT_NEAR(s.right().y(), r.y(), 1e-4) << "frame " << f;
    EXPECT_NEAR(s.right().z(), r.z(), 1e-4) << "frame " << f;
    EXPECT_GT(s.left().x(), s.right().x());  // left side at +X
    EXPECT_GT(s.left().y(), 0.5f);           // hanging hands, metres above the floor
    EXPECT_LT(s.left().y(), 1.2f);
  }
}

// Whatever the file's units, up axis and extra nodes, the same motion gives the same samples.
TEST_F(WristSourceTest, BvhUnitsAndUpAxisDoNotMatter) {
  auto plain = WristsFromBvh(WriteClip("plain.bvh", {}), 0.0, 1);
  ASSERT_TRUE(plain.ok()) << plain.status();
  for (const testing::SyntheticRigOptions& options :
       {testing::SyntheticRigOptions{.z_up = true},
        testing::SyntheticRigOptions{.extra_root = true, .position_channels_everywhere = true},
        testing::SyntheticRigOptions{.length_scale = 0.01}}) {
    auto other = WristsFromBvh(WriteClip("other.bvh", options), 0.0, 1);
    ASSERT_TRUE(other.ok()) << other.status();
    ASSERT_EQ(other->size(), plain->size());
    for (size_t f = 0; f < plain->size(); ++f) {
      const v1::WristSample& a = (*plain)[f];
      const v1::WristSample& b = (*other)[f];
      EXPECT_NEAR(a.left().x(), b.left().x(), 1e-4);
      EXPECT_NEAR(a.left().y(), b.left().y(), 1e-4);
      EXPECT_NEAR(a.left().z(), b.left().z(), 1e-4);
      EXPECT_NEAR(a.right().x(), b.right().x(), 1e-4);
      EXPECT_NEAR(a.right().y(), b.right().y(), 1e-4);
      EXPECT_NEAR(a.right().z(), b.right().z(), 1e-4);
    }
  }
}

TEST_F(WristSourceTest, BvhNoiseIsGaussianAndSeeded) {
  const fs::path path = WriteClip("walk.bvh", {}, 90);
  auto clean = WristsFromBvh(path, 0.0, 1);
  auto noisy = WristsFromBvh(path, 0.5, 7);
  auto again = WristsFromBvh(path, 0.5, 7);
  auto other = WristsFromBvh(path, 0.5, 8);
  ASSERT_TRUE(clean.ok() && noisy.ok() && again.ok() && other.ok());
  double sum_squares = 0.0;
  int count = 0;
  bool differs_by_seed = false;
  for (size_t f = 0; f < clean->size(); ++f) {
    const v1::WristSample& c = (*clean)[f];
    const v1::WristSample& n = (*noisy)[f];
    EXPECT_EQ(n.SerializeAsString(), (*again)[f].SerializeAsString());
    differs_by_seed |= n.left().x() != (*other)[f].left().x();
    EXPECT_DOUBLE_EQ(n.time(), c.time());
    for (double d : {n.left().x() - c.left().x(), n.left().y() - c.left().y(), n.left().z() - c.left().z(),
                     n.right().x() - c.right().x(), n.right().y() - c.right().y(), n.right().z() - c.right().z()}) {
      sum_squares += d * d;
      ++count;
    }
  }
  EXPECT_TRUE(differs_by_seed);
  const double sigma_cm = 100.0 * std::sqrt(sum_squares / count);
  EXPECT_GT(sigma_cm, 0.4);  // 540 draws of σ = 0.5 cm
  EXPECT_LT(sigma_cm, 0.6);
}

TEST_F(WristSourceTest, BvhErrors) {
  EXPECT_EQ(WristsFromBvh(temp_.path() / "absent.bvh", 0.0, 1).status().code(), absl::StatusCode::kNotFound);
  const fs::path bad = Write("bad.bvh", "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0\n}\n");
  auto parsed = WristsFromBvh(bad, 0.0, 1);
  ASSERT_FALSE(parsed.ok());
  EXPECT_EQ(parsed.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(parsed.status().message().find("bad.bvh:5: expected a finite number for OFFSET"), std::string::npos)
      << parsed.status();
  EXPECT_EQ(WristsFromBvh(WriteClip("walk.bvh", {}), -1.0, 1).status().code(), absl::StatusCode::kInvalidArgument);
}

// --recenter: one offset for every sample, from the first finite one, the height kept.
TEST(RecenterTest, MovesTheFirstFiniteSamplesWristsToTheOriginOnTheGround) {
  auto sample = [](double t, double x, double y, double z) {
    v1::WristSample s;
    s.set_time(t);
    s.mutable_left()->set_x(x - 0.3);
    s.mutable_left()->set_y(y);
    s.mutable_left()->set_z(z);
    s.mutable_right()->set_x(x + 0.3);
    s.mutable_right()->set_y(y + 0.1);
    s.mutable_right()->set_z(z);
    return s;
  };
  std::vector<v1::WristSample> samples = {sample(0, std::nan(""), 1, 2), sample(1, 12000, 1.0, -5000),
                                          sample(2, 12001, 1.2, -5000)};
  const std::array<double, 3> offset = RecenterHorizontally(&samples, 1);  // Y up
  EXPECT_NEAR(offset[0], 12000, 2e-3);
  EXPECT_DOUBLE_EQ(offset[1], 0);  // heights kept
  EXPECT_NEAR(offset[2], -5000, 1e-3);
  EXPECT_NEAR(samples[1].left().x(), -0.3, 2e-3);  // positions are floats: 1 mm at 12 km
  EXPECT_NEAR(samples[1].right().y(), 1.1, 1e-6);
  EXPECT_NEAR(samples[2].left().x(), 0.7, 2e-3);
  EXPECT_NEAR(samples[2].left().z(), 0, 2e-3);
  // Z up (Blender, Unreal): X and Y move, Z stays.
  std::vector<v1::WristSample> z_up = {sample(0, 100, 200, 1.3)};
  const std::array<double, 3> z_offset = RecenterHorizontally(&z_up, 2);
  EXPECT_NEAR(z_offset[1], 200.05, 1e-4);
  EXPECT_DOUBLE_EQ(z_offset[2], 0);
  EXPECT_FLOAT_EQ(z_up[0].left().z(), 1.3f);
}

}  // namespace
}  // namespace mocap

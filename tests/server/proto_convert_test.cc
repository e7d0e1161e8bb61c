// Store types -> mocap.v1 messages (server/proto_convert.h): summaries field by field, a rig's
// skeleton in metres whatever its unit with groups shifted past UNSPECIFIED, clips with their
// labels, import totals with every outcome.
#include "server/proto_convert.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "motion/core/units.h"
#include "tests/support/synthetic_clip.h"
#include "tests/support/temp_dir.h"

namespace mocap {
// Named, so that helpers do not meet other files' in a unity batch.
namespace proto_convert_test {
namespace {

TEST(ProtoConvertTest, DatabaseSummaryCarriesEveryFieldAndNoUnitWithoutARig) {
  // Only a store makes a database's ref (its name); the other fields are set here.
  testing::ScopedTempDir temp;
  auto store = std::move(MotionStore::Open(temp.path() / "mocap.db")).value();
  DatabaseSummary summary = store->CreateEmptyDatabase("walks", 30.0).value();
  summary.frame_rate = 30.0;
  summary.has_rig = true;
  summary.unit = LengthUnit::kInch;
  summary.num_joints = 22;
  summary.num_clips = 3;
  summary.num_frames = 360;
  v1::DatabaseSummary out;
  ToProto(summary, &out);
  EXPECT_EQ(out.name(), "walks");
  EXPECT_EQ(out.frame_rate(), 30.0);
  EXPECT_EQ(out.source_unit(), "in");
  EXPECT_EQ(out.joint_count(), 22);
  EXPECT_EQ(out.clip_count(), 3);
  EXPECT_EQ(out.frame_count(), 360);
  EXPECT_DOUBLE_EQ(out.duration_seconds(), 12.0);

  DatabaseSummary empty = store->CreateEmptyDatabase("new", 30.0).value();
  empty.frame_rate = 0.0;  // not yet known
  v1::DatabaseSummary empty_out;
  ToProto(empty, &empty_out);
  EXPECT_EQ(empty_out.source_unit(), "");  // no rig: no unit, although `unit` has a default
  EXPECT_EQ(empty_out.duration_seconds(), 0.0);
}

TEST(ProtoConvertTest, RigSkeletonsAreInMetresWhateverTheRigsUnit) {
  for (const auto& [unit, scale] : {std::pair{LengthUnit::kCentimetre, 1.0}, std::pair{LengthUnit::kMetre, 0.01},
                                    std::pair{LengthUnit::kInch, 1.0 / 2.54}}) {
    auto rig = BuildRigModel(testing::MakeWalkingClip({.length_scale = scale}, 30), {.unit = unit});
    ASSERT_TRUE(rig.ok()) << rig.status();
    ASSERT_EQ(rig->unit, unit);
    v1::Skeleton out;
    ToProto(*rig, &out);
    ASSERT_EQ(out.joints_size(), rig->skeleton.num_joints());
    const float metres = static_cast<float>(MetresPerUnit(unit));
    const int hips = rig->skeleton.Find("Hips");
    ASSERT_GE(hips, 0);
    // The synthetic Hips offset is 96 cm, whatever unit the file was written in.
    EXPECT_NEAR(out.joints(hips).offset().y(), 0.96f, 1e-4f) << UnitName(unit);
    for (int j = 0; j < out.joints_size(); ++j) {
      const Joint& joint = rig->skeleton.joint(j);
      EXPECT_EQ(out.joints(j).name(), joint.name);
      EXPECT_EQ(out.joints(j).parent(), joint.parent);
      EXPECT_FLOAT_EQ(out.joints(j).offset().x(), joint.offset.x() * metres);
      EXPECT_FLOAT_EQ(out.joints(j).offset().z(), joint.offset.z() * metres);
      EXPECT_EQ(out.joints(j).has_end_site(), joint.end_site.has_value());
      if (joint.end_site) {
        EXPECT_FLOAT_EQ(out.joints(j).end_site().y(), joint.end_site->y() * metres);
      }
      // BodyGroup kSpine (0) is BODY_GROUP_SPINE (1): UNSPECIFIED never appears for a known group.
      EXPECT_EQ(static_cast<int>(out.joints(j).group()), static_cast<int>(rig->topology.group_of_joint[j]) + 1);
    }
    const BodyLandmarks& l = rig->topology.landmarks;
    EXPECT_EQ(out.landmarks().pelvis(), l.pelvis);
    EXPECT_EQ(out.landmarks().head(), l.head);
    EXPECT_EQ(out.landmarks().left_wrist(), l.left_wrist);
    EXPECT_EQ(out.landmarks().right_wrist(), l.right_wrist);
    EXPECT_EQ(out.landmarks().left_ankle(), l.left_ankle);
    EXPECT_EQ(out.landmarks().right_ankle(), l.right_ankle);
    EXPECT_EQ(out.joints(l.left_wrist).group(), v1::BODY_GROUP_LEFT_ARM);
    EXPECT_EQ(out.joints(l.right_ankle).group(), v1::BODY_GROUP_RIGHT_LEG);
  }
}

TEST(ProtoConvertTest, JointsWithoutAGroupAreLeftUnspecified) {
  RigModel rig;
  rig.unit = LengthUnit::kMetre;
  rig.skeleton = Skeleton({Joint{"a", -1, {0, 1, 0}, {}, std::nullopt}, Joint{"b", 0, {0, 0.5f, 0}, {}, std::nullopt}});
  rig.topology.group_of_joint = {BodyGroup::kHead};  // one group for two joints
  v1::Skeleton out;
  ToProto(rig, &out);
  ASSERT_EQ(out.joints_size(), 2);
  EXPECT_EQ(out.joints(0).group(), v1::BODY_GROUP_HEAD);
  EXPECT_EQ(out.joints(1).group(), v1::BODY_GROUP_UNSPECIFIED);
  EXPECT_FALSE(out.joints(1).has_end_site());
}

TEST(ProtoConvertTest, ClipsCarryTheirLabels) {
  ClipSummary clip;
  clip.id = 42;
  clip.source_name = "dataset-2_walk_happy_01.bvh";
  clip.content_hash = "abc123";
  clip.num_frames = 90;
  clip.source_frame_rate = 120.0;
  clip.source_frames = 360;
  clip.labels = {{"content", "walk"}, {"style", "happy"}, {"take", "01"}};
  v1::Clip out;
  ToProto(clip, &out);
  EXPECT_EQ(out.id(), 42);
  EXPECT_EQ(out.source_name(), clip.source_name);
  EXPECT_EQ(out.content_hash(), "abc123");
  EXPECT_EQ(out.frame_count(), 90);
  EXPECT_EQ(out.source_frame_rate(), 120.0);
  EXPECT_EQ(out.source_frame_count(), 360);
  ASSERT_EQ(out.labels_size(), 3);
  EXPECT_EQ(out.labels().at("style"), "happy");
  EXPECT_EQ(out.labels().at("take"), "01");
}

TEST(ProtoConvertTest, ImportTotalsKeepEveryFileInOrderWithItsOutcome) {
  ImportTotals totals;
  totals.created_database = true;
  totals.imported = 1;
  totals.duplicates = 1;
  totals.failed = 1;
  totals.frames = 90;
  totals.source_frames = 360;
  using Outcome = ImportFileResult::Outcome;
  totals.files = {{"a.bvh", Outcome::kImported, 7, 90, 360, ""},
                  {"b.bvh", Outcome::kDuplicate, 7, 0, 0, "same content as a.bvh"},
                  {"c.bvh", Outcome::kFailed, 0, 0, 0, "line 3: expected ROOT"}};
  v1::ImportBvhResponse out;
  ToProto("walks", totals, &out);
  EXPECT_EQ(out.database(), "walks");
  EXPECT_TRUE(out.created_database());
  EXPECT_EQ(out.imported_count(), 1);
  EXPECT_EQ(out.duplicate_count(), 1);
  EXPECT_EQ(out.failed_count(), 1);
  EXPECT_EQ(out.frame_count(), 90);
  EXPECT_EQ(out.source_frame_count(), 360);
  ASSERT_EQ(out.files_size(), 3);
  EXPECT_EQ(out.files(0).file_name(), "a.bvh");
  EXPECT_EQ(out.files(0).outcome(), v1::FileResult::OUTCOME_IMPORTED);
  EXPECT_EQ(out.files(0).clip_id(), 7);
  EXPECT_EQ(out.files(0).frame_count(), 90);
  EXPECT_EQ(out.files(1).outcome(), v1::FileResult::OUTCOME_DUPLICATE);
  EXPECT_EQ(out.files(1).clip_id(), 7);
  EXPECT_EQ(out.files(1).error(), "same content as a.bvh");
  EXPECT_EQ(out.files(2).outcome(), v1::FileResult::OUTCOME_FAILED);
  EXPECT_EQ(out.files(2).error(), "line 3: expected ROOT");
}

}  // namespace
}  // namespace proto_convert_test
}  // namespace mocap

// The tunables' table (proto/convert/method_overrides.h): every MethodOverrides field has its row,
// the defaults are within range, and overrides go in, are checked and come back out unchanged.
#include "proto/convert/method_overrides.h"

#include <set>
#include <string>

#include <gtest/gtest.h>

namespace mocap {
namespace {

using google::protobuf::FieldDescriptor;

TEST(MethodOverridesTest, EveryOverrideFieldHasOneRowAndEveryRowAField) {
  std::set<std::string> rows;
  for (const MethodTunable& t : MethodTunables()) {
    EXPECT_TRUE(rows.insert(std::string(t.field)).second) << t.field << " has two rows";
    const FieldDescriptor* field = v1::MethodOverrides::descriptor()->FindFieldByName(std::string(t.field));
    ASSERT_NE(field, nullptr) << t.field << " is not a MethodOverrides field";
    EXPECT_TRUE(field->has_presence()) << t.field << ": an unset override must be told from zero";
    EXPECT_NE(field->cpp_type(), FieldDescriptor::CPPTYPE_ENUM) << t.field;
    EXPECT_LE(t.min, t.max) << t.field;
    EXPECT_FALSE(t.help.empty()) << t.field;
    if (!t.flag.empty()) {
      EXPECT_EQ(t.flag.substr(0, 2), "--") << t.field;
    }
  }
  const google::protobuf::Descriptor* message = v1::MethodOverrides::descriptor();
  for (int i = 0; i < message->field_count(); ++i) {
    const FieldDescriptor* field = message->field(i);
    if (field->cpp_type() == FieldDescriptor::CPPTYPE_ENUM) continue;  // foot_contacts: converted apart
    EXPECT_TRUE(rows.count(field->name())) << "MethodOverrides." << field->name() << " has no row in the table";
  }
}

TEST(MethodOverridesTest, TheDefaultsAreWithinTheirRangesAndComeBackUnchanged) {
  const ReconstructionOptions defaults;
  ReconstructionOptions options;
  ASSERT_TRUE(ApplyMethodOverrides(v1::MethodOverrides(), &options).ok());
  v1::MethodOverrides written;
  WriteMethodOverrides(defaults, &written);
  ReconstructionOptions read;
  ASSERT_TRUE(ApplyMethodOverrides(written, &read).ok());
  for (const MethodTunable& t : MethodTunables()) {
    EXPECT_EQ(t.get(options), t.get(defaults)) << t.field;
    EXPECT_EQ(t.get(read), t.get(defaults)) << t.field;
  }
}

TEST(MethodOverridesTest, AnOverrideSetsItsOptionAndAnotherLeavesTheRest) {
  v1::MethodOverrides overrides;
  overrides.set_pose_neighbours(25);
  overrides.set_joint_smoothing_frames(2.5f);
  overrides.set_footskate_cleanup(false);
  overrides.set_max_gap_seconds(0.5);
  ReconstructionOptions options;
  ASSERT_TRUE(ApplyMethodOverrides(overrides, &options).ok());
  EXPECT_EQ(options.pose_neighbours, 25);
  EXPECT_FLOAT_EQ(options.joint_smoothing_sigma, 2.5f);
  EXPECT_FALSE(options.footskate.enabled);
  EXPECT_DOUBLE_EQ(options.max_gap_seconds, 0.5);
  EXPECT_EQ(options.ankle_candidates, ReconstructionOptions().ankle_candidates);

  // The CLI's way in: a flag's value set through the table.
  v1::MethodOverrides by_flag;
  for (const MethodTunable& t : MethodTunables()) {
    if (t.flag == "--k1") SetMethodOverride(t, 800.0, &by_flag);
  }
  ASSERT_TRUE(by_flag.has_ankle_candidates());
  EXPECT_EQ(by_flag.ankle_candidates(), 800);
}

TEST(MethodOverridesTest, AValueOutOfRangeIsRefusedNamingItsField) {
  v1::MethodOverrides overrides;
  overrides.set_ankle_candidates(kMaxAnkleCandidates + 1);
  ReconstructionOptions options;
  const absl::Status status = ApplyMethodOverrides(overrides, &options);
  EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(std::string(status.message()).find("overrides.ankle_candidates must be in [1, 5000]"), std::string::npos)
      << status;
  overrides.Clear();
  overrides.set_wrist_smoothing(1.5f);
  ReconstructionOptions fresh;
  EXPECT_NE(std::string(ApplyMethodOverrides(overrides, &fresh).message()).find("overrides.wrist_smoothing"),
            std::string::npos);
}

}  // namespace
}  // namespace mocap

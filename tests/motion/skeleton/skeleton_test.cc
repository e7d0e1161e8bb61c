// Skeleton::Validate on names a hostile file or request can send (issue #24).
#include "motion/skeleton/skeleton.h"

#include <string>

#include <gtest/gtest.h>

namespace mocap {
namespace {

Skeleton OneJoint(std::string name) { return Skeleton({Joint{.name = std::move(name), .parent = -1}}); }

TEST(SkeletonTest, NamesWithControlCharactersOrWhiteSpaceAreRefusedWithoutEchoingThem) {
  for (const std::string& name :
       {std::string("a\x01"
                    "b"),
        std::string("a\x1b[31mb"), std::string("a b"), std::string("a\x7f"), std::string("")}) {
    const absl::Status status = OneJoint(name).Validate();
    EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument) << name;
    for (const char c : status.message()) EXPECT_FALSE(static_cast<unsigned char>(c) < ' ') << status;
  }
  EXPECT_TRUE(OneJoint("mixamorig:Hips").Validate().ok());
  EXPECT_TRUE(OneJoint("Hüfte").Validate().ok());  // UTF-8 is a name like any other
}

TEST(SkeletonTest, OverlongNamesAreRefusedByTheirSize) {
  EXPECT_TRUE(OneJoint(std::string(kMaxJointNameBytes, 'a')).Validate().ok());
  const absl::Status status = OneJoint(std::string(3 << 20, 'a')).Validate();
  EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_LT(status.message().size(), 200u);
}

}  // namespace
}  // namespace mocap

// Where `mocap reconstruct -o OUTPUT` writes (client/cli/output_paths.h).
#include <gtest/gtest.h>

#include "client/cli/output_paths.cc"  // NOLINT(build/include): OutputPathsOf

namespace mocap::cli {
namespace {

TEST(OutputPathsTest, APrefixGetsBothExtensions) {
  const ReconstructionOutputPaths paths = OutputPathsOf("out/walk");
  EXPECT_EQ(paths.bvh, "out/walk.bvh");
  EXPECT_EQ(paths.json, "out/walk.json");
}

TEST(OutputPathsTest, ANamedBvhOrJsonIsNotDoubled) {
  EXPECT_EQ(OutputPathsOf("walk.bvh").bvh, "walk.bvh");
  EXPECT_EQ(OutputPathsOf("walk.bvh").json, "walk.json");
  EXPECT_EQ(OutputPathsOf("Walk.BVH").bvh, "Walk.bvh");
  EXPECT_EQ(OutputPathsOf("walk.json").bvh, "walk.bvh");
  EXPECT_EQ(OutputPathsOf("walk.json").json, "walk.json");
}

TEST(OutputPathsTest, OtherDotsStay) {
  EXPECT_EQ(OutputPathsOf("take.2").bvh, "take.2.bvh");
  EXPECT_EQ(OutputPathsOf("walk.bvh.v2").bvh, "walk.bvh.v2.bvh");
  EXPECT_EQ(OutputPathsOf("dir.bvh/walk").json, "dir.bvh/walk.json");
}

TEST(OutputPathsTest, AFileNamedOnlyByItsExtensionKeepsIt) {
  EXPECT_EQ(OutputPathsOf(".bvh").bvh, ".bvh.bvh");
  EXPECT_EQ(OutputPathsOf("out/.json").json, "out/.json.json");
}

}  // namespace
}  // namespace mocap::cli

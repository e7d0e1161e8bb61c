// ReconstructionDatabases::Load (server/reconstruction_databases.h): a store database becomes the
// query-ready database the sessions search, with its travelling frames also played backwards unless the
// server was told not to (mocapd serve --no-reversed-motion).
#include "server/reconstruction_databases.h"

#include <gtest/gtest.h>

#include "tests/support/synthetic_clip.h"
#include "tests/support/temp_dir.h"

namespace mocap {
namespace reconstruction_databases_test {
namespace {

TEST(ReconstructionDatabasesTest, LoadsEveryStoredClipWithOrWithoutItsReversedCopy) {
  testing::ScopedTempDir temp;
  auto store = MotionStore::Open(temp.path() / "mocap.db");
  ASSERT_TRUE(store.ok()) << store.status();
  const RigModel rig = *BuildRigModel(testing::MakeWalkingClip({}, 90), {});
  auto database = (*store)->CreateDatabase("walks", rig, 30.0);
  ASSERT_TRUE(database.ok()) << database.status();
  int frames = 0;
  for (int length : {90, 61}) {
    auto prepared = PrepareClip(testing::MakeWalkingClip({}, length), rig, {});
    ASSERT_TRUE(prepared.ok()) << prepared.status();
    ASSERT_TRUE((*store)->InsertClip(database->ref, "walk.bvh", std::to_string(length), {}, *prepared, rig).ok());
    frames += prepared->num_frames();
  }
  auto stamp = (*store)->ContentStamp(database->ref);
  ASSERT_TRUE(stamp.ok()) << stamp.status();
  const ReconstructionDatabases::Key key{.database = database->ref, .content_stamp = *stamp, .frame_rate = 30.0};

  auto with_copies = ReconstructionDatabases::Load(**store, key);
  ASSERT_TRUE(with_copies.ok()) << with_copies.status();
  EXPECT_EQ((*with_copies)->num_frames(), frames);  // what the session's Started reports
  EXPECT_EQ((*with_copies)->num_rows(), 2 * frames);

  auto captured_only = ReconstructionDatabases::Load(**store, key, /*time_reversed_copies=*/false);
  ASSERT_TRUE(captured_only.ok()) << captured_only.status();
  EXPECT_EQ((*captured_only)->num_frames(), frames);
  EXPECT_EQ((*captured_only)->num_rows(), frames);
}

}  // namespace
}  // namespace reconstruction_databases_test
}  // namespace mocap

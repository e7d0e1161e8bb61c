#include "storage/motion_store.h"

#include <filesystem>
#include <fstream>

#include <SQLiteCpp/Database.h>
#include <gtest/gtest.h>

#include "motion/preprocess/clip_preprocessor.h"
#include "storage/schema.h"
#include "tests/support/synthetic_clip.h"
#include "tests/support/temp_dir.h"

namespace mocap {
namespace {

class MotionStoreTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = temp_.path() / "nested" / "store.db";
    clip_ = testing::MakeWalkingClip({}, 60, 1.0 / 60.0);
    auto rig = BuildRigModel(clip_, {});
    ASSERT_TRUE(rig.ok()) << rig.status();
    rig_ = *rig;
    auto prepared = PrepareClip(clip_, rig_, {});
    ASSERT_TRUE(prepared.ok()) << prepared.status();
    prepared_ = *prepared;
  }
  testing::ScopedTempDir temp_;
  std::filesystem::path path_;
  BvhClip clip_;
  RigModel rig_;
  PreparedClip prepared_;
};

TEST_F(MotionStoreTest, CreatesFileAndFolderAndMigrates) {
  auto store = MotionStore::Open(path_);
  ASSERT_TRUE(store.ok()) << store.status();
  EXPECT_TRUE(std::filesystem::exists(path_));
  auto databases = (*store)->ListDatabases();
  ASSERT_TRUE(databases.ok());
  EXPECT_TRUE(databases->empty());
  SQLite::Database raw(path_.string());
  EXPECT_EQ(storage::SchemaVersion(raw), storage::kSchemaVersion);
  EXPECT_EQ(raw.execAndGet("PRAGMA journal_mode").getString(), "wal");
}

TEST_F(MotionStoreTest, OpenMissingWithoutCreateIsNotFound) {
  auto store = MotionStore::Open(path_, {.create_if_missing = false});
  EXPECT_EQ(store.status().code(), absl::StatusCode::kNotFound);
}

TEST_F(MotionStoreTest, RefusesNewerSchema) {
  { ASSERT_TRUE(MotionStore::Open(path_).ok()); }
  {
    SQLite::Database raw(path_.string(), SQLite::OPEN_READWRITE);
    raw.exec("PRAGMA user_version = 99");
  }
  auto store = MotionStore::Open(path_);
  EXPECT_EQ(store.status().code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_NE(store.status().message().find("newer"), std::string_view::npos);
}

TEST_F(MotionStoreTest, RefusesAFileThatIsNotAStore) {
  std::filesystem::create_directories(path_.parent_path());
  std::ofstream(path_) << "this is not a database, just some text that is long enough to be a header......";
  auto store = MotionStore::Open(path_);
  EXPECT_FALSE(store.ok());
  EXPECT_EQ(store.status().code(), absl::StatusCode::kDataLoss) << store.status();
}

TEST_F(MotionStoreTest, StoresAndLoadsClipsExactly) {
  auto store = std::move(MotionStore::Open(path_)).value();
  auto batch = std::move(store->BeginWrite()).value();
  auto database = store->CreateDatabase("walks", rig_, 30.0);
  ASSERT_TRUE(database.ok()) << database.status();
  auto id = store->InsertClip(database->id, "walk.bvh", "abc", {{"content", "walk"}}, prepared_, rig_);
  ASSERT_TRUE(id.ok()) << id.status();
  ASSERT_TRUE(batch->Commit().ok());

  auto summary = store->FindDatabase("walks");
  ASSERT_TRUE(summary.ok());
  EXPECT_EQ(summary->num_clips, 1);
  EXPECT_EQ(summary->num_frames, prepared_.num_frames());
  EXPECT_EQ(summary->num_joints, clip_.skeleton.num_joints());

  auto rig = store->LoadRig(database->id);
  ASSERT_TRUE(rig.ok()) << rig.status();
  EXPECT_EQ(rig->topology.landmarks.left_wrist, rig_.topology.landmarks.left_wrist);
  EXPECT_TRUE(rig->skeleton.SameRigAs(rig_.skeleton));

  auto loaded = store->LoadClip(*id, *rig);
  ASSERT_TRUE(loaded.ok()) << loaded.status();
  EXPECT_EQ(loaded->summary.source_name, "walk.bvh");
  ASSERT_EQ(loaded->summary.labels.size(), 1u);
  EXPECT_EQ(loaded->summary.labels[0].second, "walk");
  ASSERT_EQ(loaded->motion.num_frames(), prepared_.num_frames());
  ASSERT_EQ(loaded->features.size(), prepared_.features.size());
  EXPECT_EQ(loaded->features[10].wrist_position[0][1], prepared_.features[10].wrist_position[0][1]);
  for (int f = 0; f < prepared_.num_frames(); f += 7) {
    for (int j = 0; j < clip_.skeleton.num_joints(); ++j) {
      const float dot = std::abs(loaded->motion.rotation(f, j).dot(prepared_.motion.rotation(f, j)));
      EXPECT_NEAR(dot, 1.0f, 1e-5f) << "frame " << f << " joint " << j;
      EXPECT_LT((loaded->motion.translation(f, j) - prepared_.motion.translation(f, j)).norm(), 1e-5f);
    }
  }
}

TEST_F(MotionStoreTest, UncommittedBatchLeavesStoreUnchanged) {
  auto store = std::move(MotionStore::Open(path_)).value();
  {
    auto batch = std::move(store->BeginWrite()).value();
    ASSERT_TRUE(store->CreateDatabase("walks", rig_, 30.0).ok());
    // Destroyed without Commit: rolled back.
  }
  EXPECT_EQ(store->FindDatabase("walks").status().code(), absl::StatusCode::kNotFound);
}

TEST_F(MotionStoreTest, DuplicateNamesAndHashesAreDetected) {
  auto store = std::move(MotionStore::Open(path_)).value();
  auto database = store->CreateDatabase("walks", rig_, 30.0);
  ASSERT_TRUE(database.ok());
  EXPECT_EQ(store->CreateDatabase("walks", rig_, 30.0).status().code(), absl::StatusCode::kAlreadyExists);
  EXPECT_EQ(store->CreateDatabase("", rig_, 30.0).status().code(), absl::StatusCode::kInvalidArgument);
  ASSERT_TRUE(store->InsertClip(database->id, "a.bvh", "hash-1", {}, prepared_, rig_).ok());
  auto found = store->FindClipByHash(database->id, "hash-1");
  ASSERT_TRUE(found.ok());
  EXPECT_TRUE(found->has_value());
  EXPECT_FALSE(store->InsertClip(database->id, "b.bvh", "hash-1", {}, prepared_, rig_).ok());
  EXPECT_FALSE(store->FindClipByHash(database->id, "hash-2")->has_value());
}

TEST_F(MotionStoreTest, CorruptBlobIsDataLoss) {
  std::int64_t database_id, clip_id;
  {
    auto store = std::move(MotionStore::Open(path_)).value();
    database_id = store->CreateDatabase("walks", rig_, 30.0)->id;
    clip_id = *store->InsertClip(database_id, "a.bvh", "h", {}, prepared_, rig_);
  }
  {
    SQLite::Database raw(path_.string(), SQLite::OPEN_READWRITE);
    raw.exec("UPDATE clips SET poses = x'00112233'");
  }
  auto store = std::move(MotionStore::Open(path_)).value();
  auto loaded = store->LoadClip(clip_id, rig_);
  EXPECT_EQ(loaded.status().code(), absl::StatusCode::kDataLoss);
  EXPECT_EQ(store->LoadClip(clip_id + 100, rig_).status().code(), absl::StatusCode::kNotFound);
}

TEST_F(MotionStoreTest, DeletingADatabaseRemovesItsClips) {
  auto store = std::move(MotionStore::Open(path_)).value();
  auto database = store->CreateDatabase("walks", rig_, 30.0);
  ASSERT_TRUE(store->InsertClip(database->id, "a.bvh", "h", {{"k", "v"}}, prepared_, rig_).ok());
  ASSERT_TRUE(store->DeleteDatabase(database->id).ok());
  SQLite::Database raw(path_.string());
  EXPECT_EQ(raw.execAndGet("SELECT COUNT(*) FROM clips").getInt(), 0);
  EXPECT_EQ(raw.execAndGet("SELECT COUNT(*) FROM clip_labels").getInt(), 0);
  EXPECT_EQ(store->DeleteDatabase(database->id).code(), absl::StatusCode::kNotFound);
}

}  // namespace
}  // namespace mocap

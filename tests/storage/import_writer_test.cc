// ImportWriter against databases that change under an open import (issue #24, finding 1): work
// that outlives its database ends NotFound and never lands in a database created after it.
#include "storage/import_writer.h"

#include <SQLiteCpp/Database.h>
#include <gtest/gtest.h>

#include "motion/bvh/bvh_writer.h"
#include "storage/tenant_directory.h"
#include "tests/support/synthetic_clip.h"
#include "tests/support/temp_dir.h"

namespace mocap {
namespace {

class ImportWriterTest : public ::testing::TestWithParam<bool> {
 protected:
  void SetUp() override {
    store_ = std::move(MotionStore::Open(temp_.path() / "store.db")).value();
    auto acme = TenantDirectory(*store_).CreateTenant("acme");
    ASSERT_TRUE(acme.ok());
    acme_ = acme->id;
  }
  // A synthetic walk as file bytes; `frames` makes each file's content distinct.
  static std::string ClipBytes(int frames) { return FormatBvh(testing::MakeWalkingClip({}, frames)); }

  std::unique_ptr<ImportWriter> StartImport(TenantId tenant) {
    auto writer = ImportWriter::Start(*store_, {.tenant = tenant, .database = "walks", .buffer_batch = GetParam()});
    EXPECT_TRUE(writer.ok()) << writer.status();
    return std::move(*writer);
  }
  absl::Status AddClip(ImportWriter& writer, int frames) {
    BvhClip parsed;
    PreparedFile file = PrepareBvhBytes(ClipBytes(frames), "f.bvh", writer.rig(), writer.preprocess(), &parsed);
    if (writer.rig() == nullptr) {
      if (absl::Status status = writer.SetRigFrom(parsed, "f.bvh"); !status.ok()) return status;
      file = PrepareBvhBytes(ClipBytes(frames), "f.bvh", writer.rig(), writer.preprocess());
    }
    return writer.Add("f" + std::to_string(frames) + ".bvh", std::move(file), {});
  }

  ::mocap::testing::ScopedTempDir temp_;
  std::unique_ptr<MotionStore> store_;
  TenantId acme_ = 0;
};

// The reported interleaving: the default tenant's import is open on its database; the database
// is deleted; another tenant creates one; the import ends.
TEST_P(ImportWriterTest, ImportIntoADeletedDatabaseEndsNotFoundAndTouchesNoOther) {
  {
    auto seed = StartImport(kDefaultTenantId);
    ASSERT_TRUE(AddClip(*seed, 40).ok());
    ASSERT_TRUE(seed->Finish().ok());
  }
  auto import = StartImport(kDefaultTenantId);
  ASSERT_TRUE(import->database_exists());
  if (GetParam()) {
    // Buffered (the RPC's mode): held in memory, written when the batch commits. (A direct batch
    // holds the store's write lock from its first clip, so the delete could not come between.)
    ASSERT_TRUE(AddClip(*import, 41).ok());
  }
  const DatabaseRef old = store_->FindDatabase("walks")->ref;
  ASSERT_TRUE(store_->DeleteDatabase(old).ok());
  auto theirs = store_->CreateEmptyDatabase("walks", 30.0, acme_);
  ASSERT_TRUE(theirs.ok());
  EXPECT_NE(theirs->ref.id(), old.id());

  absl::Status status = AddClip(*import, 43);
  if (status.ok()) status = import->Finish();
  EXPECT_EQ(status.code(), absl::StatusCode::kNotFound) << status;
  EXPECT_NE(status.message().find("no longer exists"), std::string_view::npos) << status;
  auto after = store_->FindDatabase("walks", acme_);
  ASSERT_TRUE(after.ok());
  EXPECT_EQ(after->num_clips, 0);
  EXPECT_FALSE(after->has_rig);
  EXPECT_EQ(store_->FindDatabase("walks").status().code(), absl::StatusCode::kNotFound);
}

// An import whose database is deleted between two batches: the first batch is gone with the
// database, the second is refused.
TEST_P(ImportWriterTest, DatabaseDeletedBetweenBatchesEndsTheImport) {
  auto import = StartImport(kDefaultTenantId);
  ASSERT_TRUE(AddClip(*import, 40).ok());
  ASSERT_TRUE(import->Finish().ok());  // created with its first clip
  ASSERT_TRUE(store_->DeleteDatabase(store_->FindDatabase("walks")->ref).ok());
  ASSERT_TRUE(store_->CreateEmptyDatabase("walks", 30.0, acme_).ok());
  absl::Status status = AddClip(*import, 41);
  if (status.ok()) status = import->Finish();
  EXPECT_EQ(status.code(), absl::StatusCode::kNotFound) << status;
  EXPECT_EQ(store_->FindDatabase("walks", acme_)->num_clips, 0);
}

INSTANTIATE_TEST_SUITE_P(BufferedAndDirect, ImportWriterTest, ::testing::Bool(),
                         [](const auto& info) { return info.param ? "Buffered" : "Direct"; });

}  // namespace
}  // namespace mocap

#include "storage/motion_store.h"

#include <filesystem>
#include <fstream>
#include <type_traits>

#include <SQLiteCpp/Database.h>
#include <SQLiteCpp/Statement.h>
#include <gtest/gtest.h>

#include "motion/preprocess/clip_preprocessor.h"
#include "storage/schema.h"
#include "storage/tenant_directory.h"
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
  auto id = store->InsertClip(database->ref, "walk.bvh", "abc", {{"content", "walk"}}, prepared_, rig_);
  ASSERT_TRUE(id.ok()) << id.status();
  ASSERT_TRUE(batch->Commit().ok());

  auto summary = store->FindDatabase("walks");
  ASSERT_TRUE(summary.ok());
  EXPECT_EQ(summary->num_clips, 1);
  EXPECT_EQ(summary->num_frames, prepared_.num_frames());
  EXPECT_EQ(summary->num_joints, clip_.skeleton.num_joints());

  auto rig = store->LoadRig(database->ref);
  ASSERT_TRUE(rig.ok()) << rig.status();
  EXPECT_EQ(rig->topology.landmarks.left_wrist, rig_.topology.landmarks.left_wrist);
  EXPECT_TRUE(rig->skeleton.SameRigAs(rig_.skeleton));

  auto loaded = store->LoadClip(database->ref, *id, *rig);
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
  ASSERT_TRUE(store->InsertClip(database->ref, "a.bvh", "hash-1", {}, prepared_, rig_).ok());
  auto found = store->FindClipByHash(database->ref, "hash-1");
  ASSERT_TRUE(found.ok());
  EXPECT_TRUE(found->has_value());
  EXPECT_FALSE(store->InsertClip(database->ref, "b.bvh", "hash-1", {}, prepared_, rig_).ok());
  EXPECT_FALSE(store->FindClipByHash(database->ref, "hash-2")->has_value());
}

TEST_F(MotionStoreTest, CorruptBlobIsDataLoss) {
  std::int64_t clip_id;
  {
    auto store = std::move(MotionStore::Open(path_)).value();
    clip_id = *store->InsertClip(store->CreateDatabase("walks", rig_, 30.0)->ref, "a.bvh", "h", {}, prepared_, rig_);
  }
  {
    SQLite::Database raw(path_.string(), SQLite::OPEN_READWRITE);
    raw.exec("UPDATE clips SET poses = x'00112233'");
  }
  auto store = std::move(MotionStore::Open(path_)).value();
  const DatabaseRef walks = store->FindDatabase("walks")->ref;
  auto loaded = store->LoadClip(walks, clip_id, rig_);
  EXPECT_EQ(loaded.status().code(), absl::StatusCode::kDataLoss);
  EXPECT_EQ(store->LoadClip(walks, clip_id + 100, rig_).status().code(), absl::StatusCode::kNotFound);
}

TEST_F(MotionStoreTest, DeletingADatabaseRemovesItsClips) {
  auto store = std::move(MotionStore::Open(path_)).value();
  auto database = store->CreateDatabase("walks", rig_, 30.0);
  ASSERT_TRUE(store->InsertClip(database->ref, "a.bvh", "h", {{"k", "v"}}, prepared_, rig_).ok());
  ASSERT_TRUE(store->DeleteDatabase(database->ref).ok());
  SQLite::Database raw(path_.string());
  EXPECT_EQ(raw.execAndGet("SELECT COUNT(*) FROM clips").getInt(), 0);
  EXPECT_EQ(raw.execAndGet("SELECT COUNT(*) FROM clip_labels").getInt(), 0);
  EXPECT_EQ(store->DeleteDatabase(database->ref).code(), absl::StatusCode::kNotFound);
}

// The content stamp keys the server's indices: it must change with every change of a database's
// clips, whichever connection (or process) made it, and stay put otherwise.
TEST_F(MotionStoreTest, ContentStampChangesWithTheClipsFromAnyConnection) {
  auto store = std::move(MotionStore::Open(path_)).value();
  auto other = std::move(MotionStore::Open(path_)).value();  // another connection: another server
  auto walks = store->CreateDatabase("walks", rig_, 30.0);
  auto runs = store->CreateDatabase("runs", rig_, 30.0);
  ASSERT_TRUE(walks.ok() && runs.ok());
  ASSERT_TRUE(store->InsertClip(walks->ref, "a.bvh", "hash-a", {}, prepared_, rig_).ok());
  auto stamp = [](MotionStore& s, const DatabaseRef& database) { return s.ContentStamp(database).value(); };
  const std::string empty_runs = stamp(*store, runs->ref);
  const std::string one = stamp(*store, walks->ref);
  EXPECT_EQ(stamp(*store, walks->ref), one);  // nothing changed
  EXPECT_EQ(stamp(*other, walks->ref), one);  // the same on every connection

  // This connection's own import.
  auto b = store->InsertClip(walks->ref, "b.bvh", "hash-b", {}, prepared_, rig_);
  ASSERT_TRUE(b.ok());
  const std::string two = stamp(*store, walks->ref);
  EXPECT_NE(two, one);
  EXPECT_EQ(stamp(*other, walks->ref), two);
  EXPECT_EQ(stamp(*store, runs->ref), empty_runs);  // another database's stamp stays

  // Another connection deletes the newest clip and imports another file, which takes its id.
  ASSERT_TRUE(other->DeleteClip(walks->ref, *b).ok());
  EXPECT_EQ(stamp(*store, walks->ref), one);
  auto c = other->InsertClip(walks->ref, "c.bvh", "hash-c", {}, prepared_, rig_);
  ASSERT_TRUE(c.ok());
  EXPECT_GT(*c, *b);  // ids are never reused (schema 3)
  const std::string reused = stamp(*store, walks->ref);
  EXPECT_NE(reused, two);
  EXPECT_NE(reused, one);

  // A third process's write through plain SQLite.
  {
    SQLite::Database raw(path_.string(), SQLite::OPEN_READWRITE);
    raw.exec("DELETE FROM clips WHERE id = " + std::to_string(*c));
  }
  EXPECT_EQ(stamp(*store, walks->ref), one);
}

// A store written by schema version 1 (one namespace of databases) opens as the current version with its
// databases, clips and labels in the 'default' tenant.
TEST_F(MotionStoreTest, MigratesVersionOneStoreToTheDefaultTenant) {
  std::filesystem::create_directories(path_.parent_path());
  {
    SQLite::Database raw(path_.string(), SQLite::OPEN_READWRITE | SQLite::OPEN_CREATE);
    ASSERT_TRUE(storage::MigrateSchema(raw, 1).ok());
    raw.exec("PRAGMA foreign_keys = ON");
    raw.exec("INSERT INTO databases (id, name, frame_rate, unit, rig) VALUES (7, 'walks', 30, 'cm', '{}')");
    raw.exec(R"sql(INSERT INTO clips (id, database_id, source_name, content_hash, source_frame_rate, source_frames,
                                       num_frames, offsets, poses, features) VALUES (3, 7, 'a.bvh', 'h', 30, 2, 2,
                                       x'', x'', x''))sql");
    raw.exec("INSERT INTO clip_labels (clip_id, key, value) VALUES (3, 'content', 'walk')");
  }
  {
    auto store = MotionStore::Open(path_);
    ASSERT_TRUE(store.ok()) << store.status();
  }
  SQLite::Database raw(path_.string());
  EXPECT_EQ(storage::SchemaVersion(raw), storage::kSchemaVersion);
  EXPECT_EQ(raw.execAndGet("SELECT tenant_id FROM databases WHERE id = 7").getInt(), kDefaultTenantId);
  EXPECT_EQ(raw.execAndGet("SELECT name FROM tenants WHERE id = 1").getString(), "default");
  EXPECT_EQ(raw.execAndGet("SELECT COUNT(*) FROM clips WHERE database_id = 7").getInt(), 1);
  EXPECT_EQ(raw.execAndGet("SELECT COUNT(*) FROM clip_labels").getInt(), 1);
  EXPECT_FALSE(SQLite::Statement(raw, "PRAGMA foreign_key_check").executeStep());
}

// Isolation as a type (issue #24): nothing but the store makes a DatabaseRef, so no id from a
// request or another tenant's lookup can name a database to the calls that read or write one.
static_assert(!std::is_constructible_v<DatabaseRef, std::int64_t, TenantId, std::string>);
static_assert(!std::is_convertible_v<std::int64_t, DatabaseRef>);
static_assert(!std::is_invocable_v<decltype(&MotionStore::ListClips), MotionStore&, std::int64_t>);

// Issue #24 finding 1: an id freed by a delete must never name a database (or clip) created
// later, or work that still holds it (an open import, a cached index) lands in the new one.
TEST_F(MotionStoreTest, DatabaseAndClipIdsAreNeverReused) {
  auto store = std::move(MotionStore::Open(path_)).value();
  auto acme = TenantDirectory(*store).CreateTenant("acme");
  ASSERT_TRUE(acme.ok());
  auto first = store->CreateDatabase("private", rig_, 30.0);
  ASSERT_TRUE(first.ok());
  auto clip = store->InsertClip(first->ref, "a.bvh", "h", {}, prepared_, rig_);
  ASSERT_TRUE(clip.ok());
  ASSERT_TRUE(store->DeleteDatabase(first->ref).ok());  // the highest ids are free again
  auto second = store->CreateDatabase("walks", rig_, 30.0, acme->id);
  ASSERT_TRUE(second.ok());
  EXPECT_GT(second->ref.id(), first->ref.id());
  auto second_clip = store->InsertClip(second->ref, "b.bvh", "h", {}, prepared_, rig_);
  ASSERT_TRUE(second_clip.ok());
  EXPECT_GT(*second_clip, *clip);
  // Holders of the old ref are told it is gone, by every call.
  EXPECT_EQ(store->CheckDatabaseExists(first->ref).code(), absl::StatusCode::kNotFound);
  EXPECT_TRUE(store->CheckDatabaseExists(second->ref).ok());
  EXPECT_EQ(store->LoadClip(first->ref, *clip, rig_).status().code(), absl::StatusCode::kNotFound);
  EXPECT_EQ(store->InsertClip(first->ref, "c.bvh", "h2", {}, prepared_, rig_).status().code(),
            absl::StatusCode::kNotFound);
  EXPECT_EQ(store->LoadRig(first->ref).status().code(), absl::StatusCode::kNotFound);
  EXPECT_EQ(store->ContentStamp(first->ref).status().code(), absl::StatusCode::kNotFound);
  EXPECT_EQ(store->DeleteDatabase(first->ref).code(), absl::StatusCode::kNotFound);
  // A clip id is read only through its own database's ref.
  EXPECT_EQ(store->LoadClip(second->ref, *clip, rig_).status().code(), absl::StatusCode::kNotFound);
  EXPECT_EQ(store->FindClip(first->ref, *second_clip).status().code(), absl::StatusCode::kNotFound);
  EXPECT_TRUE(store->LoadClip(second->ref, *second_clip, rig_).ok());
}

// Schema 2 stores (ids reusable) keep their ids through the migration, and from then on the
// highest id ever used is remembered.
TEST_F(MotionStoreTest, MigratingVersionTwoKeepsIdsAndStopsReuse) {
  std::filesystem::create_directories(path_.parent_path());
  {
    SQLite::Database raw(path_.string(), SQLite::OPEN_READWRITE | SQLite::OPEN_CREATE);
    ASSERT_TRUE(storage::MigrateSchema(raw, 2).ok());
    raw.exec(
        "INSERT INTO databases (id, tenant_id, name, frame_rate, unit, rig) VALUES (7, 1, 'walks', 30, 'cm', NULL)");
    raw.exec(R"sql(INSERT INTO clips (id, database_id, source_name, content_hash, source_frame_rate, source_frames,
                                       num_frames, offsets, poses, features) VALUES (3, 7, 'a.bvh', 'h', 30, 2, 2,
                                       x'', x'', x''))sql");
    raw.exec("INSERT INTO clip_labels (clip_id, key, value) VALUES (3, 'content', 'walk')");
  }
  // A read-only server may still serve the old version (its tables read the same).
  ASSERT_TRUE(MotionStore::Open(path_, {.read_only = true}).ok());
  auto store = std::move(MotionStore::Open(path_)).value();
  {
    SQLite::Database raw(path_.string());
    EXPECT_EQ(storage::SchemaVersion(raw), storage::kSchemaVersion);
    EXPECT_EQ(raw.execAndGet("SELECT name FROM databases WHERE id = 7").getString(), "walks");
    EXPECT_EQ(raw.execAndGet("SELECT COUNT(*) FROM clip_labels WHERE clip_id = 3").getInt(), 1);
    EXPECT_FALSE(SQLite::Statement(raw, "PRAGMA foreign_key_check").executeStep());
    EXPECT_EQ(raw.execAndGet("PRAGMA integrity_check").getString(), "ok");
  }
  ASSERT_TRUE(store->DeleteDatabase(store->FindDatabase("walks")->ref).ok());
  SQLite::Database raw(path_.string());
  EXPECT_EQ(raw.execAndGet("SELECT COUNT(*) FROM clip_labels").getInt(), 0);  // cascades still hold
  EXPECT_GT(store->CreateDatabase("runs", rig_, 30.0)->ref.id(), 7);
}

// Issue #24: every session's start reads its database's clip count, frame total and content
// stamp. A clip's row is a page or more (its motion blobs), so these must come from an index
// alone: through the table they read every clip's page (9.5 MB for a 2,316-clip database).
TEST_F(MotionStoreTest, ClipCountsFrameTotalsAndStampsAreReadFromIndexesAlone) {
  std::filesystem::create_directories(path_.parent_path());
  {
    SQLite::Database raw(path_.string(), SQLite::OPEN_READWRITE | SQLite::OPEN_CREATE);
    ASSERT_TRUE(storage::MigrateSchema(raw, 3).ok());  // a store written before the index
  }
  auto store = std::move(MotionStore::Open(path_)).value();
  auto walks = store->CreateDatabase("walks", rig_, 30.0);
  ASSERT_TRUE(walks.ok());
  ASSERT_TRUE(store->InsertClip(walks->ref, "a.bvh", "h1", {}, prepared_, rig_).ok());
  ASSERT_TRUE(store->InsertClip(walks->ref, "b.bvh", "h2", {}, prepared_, rig_).ok());
  auto summary = store->FindDatabase("walks");
  ASSERT_TRUE(summary.ok());
  EXPECT_EQ(summary->num_clips, 2);
  EXPECT_EQ(summary->num_frames, 2 * prepared_.num_frames());
  SQLite::Database raw(path_.string());
  auto plan = [&](const std::string& sql) {
    SQLite::Statement explain(raw, "EXPLAIN QUERY PLAN " + sql);
    std::string details;
    while (explain.executeStep()) details += explain.getColumn(3).getString() + "\n";
    return details;
  };
  for (const std::string sql : {"SELECT COUNT(*), COALESCE(SUM(num_frames), 0) FROM clips WHERE database_id = 1",
                                "SELECT id, content_hash FROM clips WHERE database_id = 1 ORDER BY id"}) {
    const std::string details = plan(sql);
    EXPECT_NE(details.find("COVERING INDEX"), std::string::npos) << sql << ":\n" << details;
  }
}

// Issue #24 finding 2: the content stamp keys the server's indices, which carry database and
// file names. Even where an id did repeat (a store from before schema 3), the stamp of another
// tenant's database must differ.
TEST_F(MotionStoreTest, ContentStampNamesTheDatabasesOwner) {
  auto store = std::move(MotionStore::Open(path_)).value();
  auto acme = TenantDirectory(*store).CreateTenant("acme");
  ASSERT_TRUE(acme.ok());
  auto mine = store->CreateDatabase("acme_private", rig_, 30.0);
  ASSERT_TRUE(mine.ok());
  const std::string before = store->ContentStamp(mine->ref).value();
  ASSERT_TRUE(store->DeleteDatabase(mine->ref).ok());
  EXPECT_EQ(store->ContentStamp(mine->ref).status().code(), absl::StatusCode::kNotFound);
  {  // an id reused behind the store's back, as schema 2 did
    SQLite::Database raw(path_.string(), SQLite::OPEN_READWRITE);
    raw.exec("INSERT INTO databases (id, tenant_id, name, frame_rate) VALUES (" + std::to_string(mine->ref.id()) +
             ", " + std::to_string(acme->id) + ", 'walks', 30)");
  }
  // The old ref does not reach the new row; the new row's own stamp is another.
  EXPECT_EQ(store->ContentStamp(mine->ref).status().code(), absl::StatusCode::kNotFound);
  auto theirs = store->FindDatabase("walks", acme->id);
  ASSERT_TRUE(theirs.ok());
  EXPECT_EQ(theirs->ref.id(), mine->ref.id());
  EXPECT_NE(store->ContentStamp(theirs->ref).value(), before);
}

TEST_F(MotionStoreTest, DatabaseNamesAreUniquePerTenant) {
  auto store = std::move(MotionStore::Open(path_)).value();
  TenantDirectory tenants(*store);
  auto acme = tenants.CreateTenant("acme");
  ASSERT_TRUE(acme.ok()) << acme.status();
  ASSERT_TRUE(store->CreateDatabase("walks", rig_, 30.0).ok());
  auto theirs = store->CreateDatabase("walks", rig_, 30.0, acme->id);
  ASSERT_TRUE(theirs.ok()) << theirs.status();
  EXPECT_EQ(theirs->ref.tenant(), acme->id);
  EXPECT_EQ(store->ListDatabases(acme->id)->size(), 1u);
  EXPECT_EQ(store->ListDatabases()->size(), 1u);
  EXPECT_NE(store->FindDatabase("walks", acme->id)->ref, store->FindDatabase("walks")->ref);
  EXPECT_EQ(store->FindDatabase("walks", acme->id + 1).status().code(), absl::StatusCode::kNotFound);
}

TEST_F(MotionStoreTest, EmptyDatabaseGetsItsRigOnce) {
  auto store = std::move(MotionStore::Open(path_)).value();
  auto empty = store->CreateEmptyDatabase("later", 60.0);
  ASSERT_TRUE(empty.ok()) << empty.status();
  EXPECT_FALSE(empty->has_rig);
  EXPECT_EQ(empty->num_joints, 0);
  EXPECT_EQ(store->LoadRig(empty->ref).status().code(), absl::StatusCode::kFailedPrecondition);
  ASSERT_TRUE(store->SetRig(empty->ref, rig_).ok());
  EXPECT_EQ(store->SetRig(empty->ref, rig_).code(), absl::StatusCode::kFailedPrecondition);
  auto found = store->FindDatabase("later");
  ASSERT_TRUE(found.ok());
  EXPECT_TRUE(found->has_rig);
  EXPECT_EQ(found->num_joints, rig_.skeleton.num_joints());
  EXPECT_EQ(found->frame_rate, 60.0);
}

TEST_F(MotionStoreTest, ClipsAreFoundAndDeletedOnlyInTheirDatabase) {
  auto store = std::move(MotionStore::Open(path_)).value();
  auto walks = store->CreateDatabase("walks", rig_, 30.0);
  auto other = store->CreateDatabase("other", rig_, 30.0);
  auto id = store->InsertClip(walks->ref, "a.bvh", "h", {}, prepared_, rig_);
  ASSERT_TRUE(id.ok());
  EXPECT_EQ(store->FindClip(walks->ref, *id)->source_name, "a.bvh");
  EXPECT_EQ(store->FindClip(other->ref, *id).status().code(), absl::StatusCode::kNotFound);
  EXPECT_EQ(store->DeleteClip(other->ref, *id).code(), absl::StatusCode::kNotFound);
  ASSERT_TRUE(store->DeleteClip(walks->ref, *id).ok());
  EXPECT_EQ(store->FindDatabase("walks")->num_clips, 0);
}

TEST_F(MotionStoreTest, ApiKeysAuthenticateUntilRevokedAndAreStoredHashed) {
  auto store = std::move(MotionStore::Open(path_)).value();
  TenantDirectory tenants(*store);
  auto acme = tenants.CreateTenant("acme");
  ASSERT_TRUE(acme.ok());
  EXPECT_EQ(tenants.CreateTenant("acme").status().code(), absl::StatusCode::kAlreadyExists);
  EXPECT_EQ(tenants.CreateTenant("no spaces").status().code(), absl::StatusCode::kInvalidArgument);
  auto key = tenants.AddKey(acme->id);
  ASSERT_TRUE(key.ok()) << key.status();
  EXPECT_EQ(key->key.substr(0, 11), key->key_id);
  auto other_key = tenants.AddKey(acme->id);
  ASSERT_TRUE(other_key.ok());
  EXPECT_NE(key->key, other_key->key);

  auto who = tenants.Authenticate(key->key);
  ASSERT_TRUE(who.ok()) << who.status();
  EXPECT_EQ(who->name, "acme");
  EXPECT_EQ(who->active_keys, 2);
  EXPECT_EQ(tenants.Authenticate(key->key + "x").status().code(), absl::StatusCode::kUnauthenticated);
  EXPECT_EQ(tenants.Authenticate("").status().code(), absl::StatusCode::kUnauthenticated);
  {
    SQLite::Database raw(path_.string());
    SQLite::Statement keys(raw, "SELECT key_sha256 FROM api_keys");
    while (keys.executeStep()) {
      EXPECT_EQ(keys.getColumn(0).getString().size(), 64u);
      EXPECT_NE(keys.getColumn(0).getString(), key->key);
    }
  }
  ASSERT_TRUE(tenants.RevokeKey(acme->id, key->key_id).ok());
  EXPECT_EQ(tenants.RevokeKey(acme->id, key->key_id).code(), absl::StatusCode::kNotFound);
  EXPECT_EQ(tenants.Authenticate(key->key).status().code(), absl::StatusCode::kUnauthenticated);
  EXPECT_TRUE(tenants.Authenticate(other_key->key).ok());
  auto listed = tenants.ListKeys(acme->id);
  ASSERT_TRUE(listed.ok());
  ASSERT_EQ(listed->size(), 2u);
  EXPECT_TRUE((*listed)[0].revoked_at.has_value());
  EXPECT_EQ(*ResolveTenant(*store, "acme"), acme->id);
  EXPECT_EQ(*ResolveTenant(*store, ""), kDefaultTenantId);
  EXPECT_EQ(ResolveTenant(*store, "nobody").status().code(), absl::StatusCode::kNotFound);
}

}  // namespace
}  // namespace mocap

#include "storage/import_pipeline.h"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include <gtest/gtest.h>

#include "motion/bvh/bvh_writer.h"
#include "storage/motion_store.h"
#include "tests/support/shared_data.h"
#include "tests/support/synthetic_clip.h"
#include "tests/support/temp_dir.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;

class ImportPipelineTest : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::create_directories(dir_ / "clips");
    store_ = dir_ / "store.db";
  }

  // Writes a synthetic walk; `frames` makes each file's content distinct.
  fs::path WriteClip(const std::string& name, int frames, const testing::SyntheticRigOptions& rig = {}) {
    const fs::path path = dir_ / "clips" / name;
    EXPECT_TRUE(WriteBvhFile(testing::MakeWalkingClip(rig, frames), path).ok());
    return path;
  }
  fs::path WriteText(const std::string& name, const std::string& text) {
    const fs::path path = dir_ / "clips" / name;
    std::ofstream(path) << text;
    return path;
  }
  ImportOptions Options(std::vector<std::string> inputs) {
    ImportOptions options;
    options.store = store_;
    options.database = "walks";
    options.inputs = std::move(inputs);
    options.threads = 2;
    return options;
  }
  std::int64_t ClipCount() {
    auto store = MotionStore::Open(store_);
    EXPECT_TRUE(store.ok());
    auto database = (*store)->FindDatabase("walks");
    return database.ok() ? database->num_clips : -1;
  }

  testing::ScopedTempDir temp_;
  const fs::path& dir_ = temp_.path();
  fs::path store_;
};

TEST_F(ImportPipelineTest, ImportsFolderAndDetectsDuplicates) {
  for (int i = 0; i < 5; ++i) WriteClip("walk_" + std::to_string(i) + ".bvh", 40 + i);
  auto summary = RunImport(Options({(dir_ / "clips").string()}));
  ASSERT_TRUE(summary.ok()) << summary.status();
  EXPECT_TRUE(summary->created_database);
  EXPECT_EQ(summary->imported, 5);
  EXPECT_EQ(summary->frames, 40 + 41 + 42 + 43 + 44);
  EXPECT_EQ(ClipCount(), 5);

  WriteClip("walk_5.bvh", 50);
  fs::copy_file(dir_ / "clips" / "walk_0.bvh", dir_ / "clips" / "copy_of_walk_0.bvh");
  auto again = RunImport(Options({(dir_ / "clips").string()}));
  ASSERT_TRUE(again.ok()) << again.status();
  EXPECT_FALSE(again->created_database);
  EXPECT_EQ(again->imported, 1);
  EXPECT_EQ(again->duplicates, 6);
  EXPECT_EQ(ClipCount(), 6);
}

TEST_F(ImportPipelineTest, BadFileRollsBackTheBatchAndNamesTheFile) {
  WriteClip("a.bvh", 40);
  ASSERT_TRUE(RunImport(Options({(dir_ / "clips" / "a.bvh").string()})).ok());
  const fs::path b = WriteClip("b.bvh", 41);
  const fs::path bad = WriteText("c_bad.bvh", "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 0\n");
  const fs::path d = WriteClip("d.bvh", 43);
  auto summary = RunImport(Options({b.string(), bad.string(), d.string()}));
  ASSERT_FALSE(summary.ok());
  EXPECT_EQ(summary.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(summary.status().message().find("c_bad.bvh:"), std::string_view::npos) << summary.status();
  EXPECT_NE(summary.status().message().find("nothing from this batch was stored"), std::string_view::npos);
  EXPECT_EQ(ClipCount(), 1);  // only the earlier import
}

TEST_F(ImportPipelineTest, EarlierBatchesAreKept) {
  std::vector<std::string> inputs;
  for (int i = 0; i < 4; ++i) inputs.push_back(WriteClip("w" + std::to_string(i) + ".bvh", 40 + i).string());
  inputs.push_back(WriteText("w4.bvh", "not a bvh file").string());
  ImportOptions options = Options(inputs);
  options.batch_size = 2;
  auto summary = RunImport(options);
  ASSERT_FALSE(summary.ok());
  EXPECT_NE(summary.status().message().find("w4.bvh"), std::string_view::npos);
  EXPECT_NE(summary.status().message().find("2 earlier batch(es) with 4 clips were kept"), std::string_view::npos)
      << summary.status();
  EXPECT_EQ(ClipCount(), 4);
}

TEST_F(ImportPipelineTest, KeepGoingSkipsBadFiles) {
  WriteClip("a.bvh", 40);
  WriteText("b.bvh", "HIERARCHY\n");
  WriteClip("c.bvh", 42);
  ImportOptions options = Options({(dir_ / "clips").string()});
  options.keep_going = true;
  auto summary = RunImport(options);
  ASSERT_TRUE(summary.ok()) << summary.status();
  EXPECT_EQ(summary->imported, 2);
  EXPECT_EQ(summary->failed, 1);
  ASSERT_EQ(summary->problems.size(), 1u);
  EXPECT_NE(summary->problems[0].find("b.bvh"), std::string::npos);
}

TEST_F(ImportPipelineTest, KeepGoingWithOnlyBadFilesCreatesNoDatabase) {
  // A one-frame clip: its rig reads, but it is too short to store, so nothing is imported.
  const fs::path single = WriteClip("single_frame.bvh", 1);
  ImportOptions options = Options({single.string()});
  options.keep_going = true;
  auto summary = RunImport(options);
  ASSERT_TRUE(summary.ok()) << summary.status();
  EXPECT_EQ(summary->imported, 0);
  EXPECT_EQ(summary->failed, 1);
  EXPECT_FALSE(summary->created_database);
  auto store = MotionStore::Open(store_);
  ASSERT_TRUE(store.ok());
  EXPECT_EQ((*store)->FindDatabase("walks").status().code(), absl::StatusCode::kNotFound);
}

TEST_F(ImportPipelineTest, RefusesAnotherRig) {
  WriteClip("plain.bvh", 40);
  ASSERT_TRUE(RunImport(Options({(dir_ / "clips" / "plain.bvh").string()})).ok());
  const fs::path other = WriteClip("fingers.bvh", 40, {.fingers_and_toes = true});
  auto summary = RunImport(Options({other.string()}));
  ASSERT_FALSE(summary.ok());
  EXPECT_EQ(summary.status().code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_NE(summary.status().message().find("fingers.bvh"), std::string_view::npos);
  EXPECT_NE(summary.status().message().find("rig differs"), std::string_view::npos) << summary.status();
  EXPECT_EQ(ClipCount(), 1);
}

// Issue #22: databases built from several rigs. Asked to, the import retargets clips of other rigs
// (fingers and twist bones, a Z-up hierarchy in metres) onto the database's rig.
TEST_F(ImportPipelineTest, RetargetsAnotherRigWhenAsked) {
  WriteClip("plain.bvh", 40);
  ASSERT_TRUE(RunImport(Options({(dir_ / "clips" / "plain.bvh").string()})).ok());
  const fs::path fingers = WriteClip("fingers.bvh", 41, {.fingers_and_toes = true, .twist_bones = true});
  const fs::path z_up = WriteClip("z_up.bvh", 42, {.z_up = true, .length_scale = 0.01});
  ImportOptions options = Options({fingers.string(), z_up.string()});
  options.retarget_other_rigs = true;
  auto summary = RunImport(options);
  ASSERT_TRUE(summary.ok()) << summary.status();
  EXPECT_EQ(summary->imported, 2);
  EXPECT_TRUE(summary->rig_source.empty());  // the database had its rig
  ASSERT_EQ(ClipCount(), 3);
  // The retargeted walks move like the original: same pelvis height and travel within 2 cm.
  auto store = std::move(MotionStore::Open(store_)).value();
  auto database = store->FindDatabase("walks");
  auto rig = store->LoadRig(database->ref);
  ASSERT_TRUE(rig.ok());
  const auto clips = store->ListClips(database->ref).value();
  auto plain = store->LoadClip(database->ref, clips[0].id, *rig);
  ASSERT_TRUE(plain.ok());
  for (size_t c = 1; c < clips.size(); ++c) {
    auto other = store->LoadClip(database->ref, clips[c].id, *rig);
    ASSERT_TRUE(other.ok()) << other.status();
    const int frames = std::min(plain->motion.num_frames(), other->motion.num_frames());
    for (int f = 0; f < frames; ++f) {
      const Eigen::Vector3f a = plain->motion.translation(f, 0), b = other->motion.translation(f, 0);
      EXPECT_LT((a - b).norm(), 0.02f) << clips[c].source_name << " frame " << f;
    }
  }
}

// Issue #23: `mocapd import FILES...` takes a new database's rig from the first file named, not the
// first in path order, and says which file set it.
TEST_F(ImportPipelineTest, RigComesFromTheFirstFileNamed) {
  const fs::path z = WriteClip("z.bvh", 40);                              // the plain rig
  const fs::path a = WriteClip("a.bvh", 41, {.fingers_and_toes = true});  // another rig, first in path order
  ImportOptions options = Options({z.string(), a.string()});
  options.retarget_other_rigs = true;
  auto summary = RunImport(options);
  ASSERT_TRUE(summary.ok()) << summary.status();
  EXPECT_TRUE(summary->created_database);
  EXPECT_EQ(summary->rig_source, z.string());
  EXPECT_EQ(summary->imported, 2);  // a.bvh retargeted onto z.bvh's rig
  {
    auto store = std::move(MotionStore::Open(store_)).value();
    auto database = store->FindDatabase("walks");
    ASSERT_TRUE(database.ok()) << database.status();
    auto rig = store->LoadRig(database->ref);
    ASSERT_TRUE(rig.ok()) << rig.status();
    EXPECT_EQ(rig->skeleton.num_joints(), testing::MakeWalkingClip({}, 2).skeleton.num_joints());
    EXPECT_LT(rig->skeleton.Find("LeftHandIndex1"), 0);  // not a.bvh's fingers
  }

  // Named the other way round, a.bvh sets the rig and z.bvh (another rig, no --retarget) is skipped.
  ImportOptions reverse = Options({a.string(), z.string()});
  reverse.database = "reverse";
  reverse.keep_going = true;
  auto reversed = RunImport(reverse);
  ASSERT_TRUE(reversed.ok()) << reversed.status();
  EXPECT_EQ(reversed->rig_source, a.string());
  EXPECT_EQ(reversed->imported, 1);
  EXPECT_EQ(reversed->failed, 1);
  ASSERT_EQ(reversed->problems.size(), 1u);
  EXPECT_NE(reversed->problems[0].find("z.bvh"), std::string::npos) << reversed->problems[0];
  auto store = std::move(MotionStore::Open(store_)).value();
  auto database = store->FindDatabase("reverse");
  ASSERT_TRUE(database.ok()) << database.status();
  auto rig = store->LoadRig(database->ref);
  ASSERT_TRUE(rig.ok()) << rig.status();
  EXPECT_GE(rig->skeleton.Find("LeftHandIndex1"), 0);
}

// Issue #23: every file's body is checked against the database's unit, not only the one that sets
// the rig: a later file of the same rig exported at twice scale, or in metres into a centimetre
// database, is refused with its name and the fix (--units), and nothing of the batch is stored.
TEST_F(ImportPipelineTest, RefusesALaterFileAtAnotherScaleAndNamesIt) {
  const fs::path first = WriteClip("a.bvh", 40);
  const fs::path twice = WriteClip("b_twice.bvh", 41, {.length_scale = 2.0});
  auto summary = RunImport(Options({first.string(), twice.string()}));
  ASSERT_FALSE(summary.ok());
  EXPECT_EQ(summary.status().code(), absl::StatusCode::kInvalidArgument) << summary.status();
  EXPECT_NE(summary.status().message().find("b_twice.bvh:"), std::string_view::npos) << summary.status();
  EXPECT_NE(summary.status().message().find("--units"), std::string_view::npos) << summary.status();
  EXPECT_EQ(ClipCount(), -1);  // the database was to be created with that batch

  // Into an existing centimetre database: a file in metres.
  ASSERT_TRUE(RunImport(Options({first.string()})).ok());
  const fs::path metres = WriteClip("c_metres.bvh", 42, {.length_scale = 0.01});
  auto later = RunImport(Options({metres.string()}));
  ASSERT_FALSE(later.ok());
  EXPECT_NE(later.status().message().find("c_metres.bvh:"), std::string_view::npos) << later.status();
  EXPECT_NE(later.status().message().find("--units"), std::string_view::npos) << later.status();
  EXPECT_EQ(ClipCount(), 1);
}

// With --keep-going such files are skipped and listed, wherever they are named: a first file at
// twice scale does not set the rig, and is not imported afterwards against the next file's rig.
TEST_F(ImportPipelineTest, KeepGoingSkipsFilesAtAnotherScale) {
  const fs::path big = WriteClip("big.bvh", 39, {.length_scale = 2.0});
  const fs::path a = WriteClip("a.bvh", 40);
  const fs::path twice = WriteClip("b_twice.bvh", 41, {.length_scale = 2.0});
  const fs::path c = WriteClip("c.bvh", 42);
  ImportOptions options = Options({big.string(), a.string(), twice.string(), c.string()});
  options.keep_going = true;
  auto summary = RunImport(options);
  ASSERT_TRUE(summary.ok()) << summary.status();
  EXPECT_EQ(summary->rig_source, a.string());
  EXPECT_EQ(summary->imported, 2);
  EXPECT_EQ(summary->failed, 2);
  ASSERT_EQ(summary->problems.size(), 2u);
  EXPECT_NE(summary->problems[0].find("big.bvh"), std::string::npos) << summary->problems[0];
  EXPECT_NE(summary->problems[1].find("b_twice.bvh"), std::string::npos) << summary->problems[1];
  for (const std::string& problem : summary->problems) {
    EXPECT_NE(problem.find("--units"), std::string::npos) << problem;
  }
  EXPECT_EQ(ClipCount(), 2);
}

TEST_F(ImportPipelineTest, MissingInputsAreClearErrors) {
  EXPECT_EQ(RunImport(Options({(dir_ / "nope").string()})).status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(RunImport(Options({(dir_ / "clips").string()})).status().code(), absl::StatusCode::kInvalidArgument);
}

TEST_F(ImportPipelineTest, ResamplesOtherRatesAndConvertsUnits) {
  const fs::path path = dir_ / "clips" / "fast.bvh";
  ASSERT_TRUE(WriteBvhFile(testing::MakeWalkingClip({.length_scale = 1.0 / 2.54}, 121, 1.0 / 60.0), path).ok());
  auto summary = RunImport(Options({path.string()}));
  ASSERT_TRUE(summary.ok()) << summary.status();
  EXPECT_EQ(summary->frames, 61);
  EXPECT_EQ(summary->source_frames, 121);
  auto store = std::move(MotionStore::Open(store_)).value();
  auto database = store->FindDatabase("walks");
  ASSERT_TRUE(database.ok());
  EXPECT_EQ(database->unit, LengthUnit::kInch);
  auto rig = store->LoadRig(database->ref);
  auto clips = store->ListClips(database->ref);
  ASSERT_TRUE(clips.ok());
  auto clip = store->LoadClip(database->ref, clips->front().id, *rig);
  ASSERT_TRUE(clip.ok()) << clip.status();
  // Pelvis height in metres, whatever the file's unit.
  EXPECT_NEAR(clip->features[0].pelvis_height, 0.92, 0.06);
}

// kill -9 in the middle of a large import leaves the store exactly as it was.
TEST_F(ImportPipelineTest, KillDuringImportLeavesStoreIntact) {
  MOCAP_REQUIRE_SHARED_DATA(bandai1, "bandai-namco-1");
  MOCAP_REQUIRE_SHARED_DATA(bandai2, "bandai-namco-2");
  ImportOptions first = Options({bandai1.string()});
  first.database = "first";
  auto before = RunImport(first);
  ASSERT_TRUE(before.ok()) << before.status();

  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    const std::string store = store_.string();
    const std::string data = bandai2.string();
    execl(MOCAPD_PATH, MOCAPD_PATH, "import", "--quiet", "--store", store.c_str(), "--database", "second", data.c_str(),
          static_cast<char*>(nullptr));
    _exit(127);
  }
  // Kill once the import has written a good part of its batch to the WAL (not a timing guess: we
  // watch the file), or give up when it finished first.
  const fs::path wal = store_.string() + "-wal";
  bool killed = false;
  for (int i = 0; i < 60000; ++i) {
    std::error_code error;
    if (fs::exists(wal, error) && fs::file_size(wal, error) > 32u * 1024 * 1024) {
      kill(child, SIGKILL);
      killed = true;
      break;
    }
    int status;
    if (waitpid(child, &status, WNOHANG) == child) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  if (killed) waitpid(child, nullptr, 0);
  ASSERT_TRUE(killed) << "the import finished before it could be killed";

  auto store = MotionStore::Open(store_);
  ASSERT_TRUE(store.ok()) << store.status();
  auto databases = (*store)->ListDatabases();
  ASSERT_TRUE(databases.ok());
  ASSERT_EQ(databases->size(), 1u);
  EXPECT_EQ(databases->front().ref.name(), "first");
  EXPECT_EQ(databases->front().num_clips, before->imported);
  EXPECT_EQ(databases->front().num_frames, before->frames);
  auto rig = (*store)->LoadRig(databases->front().ref);
  auto clips = (*store)->ListClips(databases->front().ref);
  ASSERT_TRUE(clips.ok());
  EXPECT_TRUE((*store)->LoadClip(databases->front().ref, clips->back().id, *rig).ok());
}

}  // namespace
}  // namespace mocap

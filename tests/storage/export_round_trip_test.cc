// Issue #23: every shared file survives import then export with its joints where they were,
// within 1 mm in its own unit (imported at its own frame rate, so nothing is resampled).
// SharedFilesComeBack...: six hand-picked files, every joint, every frame.
// EveryFileOfEverySharedSet...: every file of every shared set, joints and End Sites, sampled frames.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "motion/bvh/bvh_reader.h"
#include "motion/bvh/bvh_writer.h"
#include "motion/core/str_cat.h"
#include "motion/core/units.h"
#include "motion/skeleton/forward_kinematics.h"
#include "motion/skeleton/local_motion.h"
#include "storage/import_pipeline.h"
#include "storage/motion_store.h"
#include "tests/support/shared_data.h"
#include "tests/support/temp_dir.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;

GlobalPoses WorldPoses(const BvhClip& clip) {
  return ForwardKinematics(clip.skeleton, MotionFromChannels(clip.skeleton, clip.channels, clip.frame_time));
}

TEST(ExportRoundTripTest, SharedFilesComeBackWhereTheyWereInTheirOwnUnit) {
  MOCAP_REQUIRE_SHARED_DATA(bandai, "bandai-namco-1");
  MOCAP_REQUIRE_SHARED_DATA(cmu, "cmu-cc");
  MOCAP_REQUIRE_SHARED_DATA(other, "other-rigs");
  const fs::path files[] = {bandai / "dataset-1_walk_normal_001.bvh",       cmu / "002_01.bvh",
                            other / "pymo_AV_8Walk_Meredith_HVHA_Rep1.bvh", other / "mixamo_test_freebvh.bvh",
                            other / "xia_dme_neutral_01_000.bvh",           other / "perfume_aachan.bvh"};
  testing::ScopedTempDir dir;
  int checked = 0;
  for (const fs::path& file : files) {
    if (!fs::exists(file)) continue;
    SCOPED_TRACE(file.filename().string());
    auto original = ReadBvhFile(file);
    ASSERT_TRUE(original.ok()) << original.status();
    ImportOptions options;
    options.store = dir.path() / (file.stem().string() + ".db");
    options.database = "round-trip";
    options.inputs = {file.string()};
    options.frame_rate = original->frame_rate();
    auto summary = RunImport(options);
    ASSERT_TRUE(summary.ok()) << summary.status();
    auto store = std::move(MotionStore::Open(options.store)).value();
    const DatabaseSummary database = store->FindDatabase("round-trip").value();
    const RigModel rig = store->LoadRig(database.ref).value();
    auto stored = store->LoadClip(database.ref, store->ListClips(database.ref)->front().id, rig);
    ASSERT_TRUE(stored.ok()) << stored.status();
    stored->motion.frame_time = 1.0 / database.frame_rate;
    auto exported = ParseBvh(FormatBvh(ToFileConventions(stored->skeleton, stored->motion, rig)), "exported.bvh");
    ASSERT_TRUE(exported.ok()) << exported.status();
    ASSERT_EQ(exported->num_frames(), original->num_frames());
    EXPECT_NEAR(exported->frame_time, original->frame_time, 1e-6);
    const GlobalPoses before = WorldPoses(*original), after = WorldPoses(*exported);
    const float tolerance = static_cast<float>(0.001 / MetresPerUnit(rig.unit));
    float worst = 0.0f;
    for (int j = 0; j < original->skeleton.num_joints(); ++j) {
      const int k = exported->skeleton.Find(original->skeleton.joint(j).name);
      ASSERT_GE(k, 0);
      for (int f = 0; f < original->num_frames(); ++f) {
        worst = std::max(worst, (after.position(f, k) - before.position(f, j)).norm());
      }
    }
    EXPECT_LT(worst, tolerance) << "in " << UnitName(rig.unit);
    ++checked;
  }
  EXPECT_GE(checked, 4);
}

// Files the importer refuses by design, and how to tell them: a file refused for any other reason
// (or a longer file refused for this one) fails the round trip.
struct DocumentedRoundTripRefusal {
  const char* why;            // printed with each file refused so
  int max_frames;             // only files this short (at their own rate)
  const char* importer_says;  // part of the importer's error
};
constexpr DocumentedRoundTripRefusal kDocumentedRoundTripRefusals[] = {
    {"one-frame pose: the importer stores clips of two frames or more", 1, "shorter than two frames"},
};

// Frames 0, middle, last and every `step`-th one (step 1: every frame), ascending.
std::vector<int> RoundTripFrames(int num_frames, int step) {
  std::vector<int> frames;
  if (num_frames <= 0) return frames;
  for (int f = 0; f < num_frames; f += std::max(step, 1)) frames.push_back(f);
  frames.push_back(num_frames / 2);
  frames.push_back(num_frames - 1);
  std::sort(frames.begin(), frames.end());
  frames.erase(std::unique(frames.begin(), frames.end()), frames.end());
  return frames;
}

// World positions (file units) of every joint ("NAME") and every End Site ("NAME/End Site") of
// `clip` at `frames` (forward kinematics over those frames only), one entry per frame.
std::map<std::string, std::vector<Eigen::Vector3f>> RoundTripSitePositions(const BvhClip& clip,
                                                                           const std::vector<int>& frames) {
  ChannelMatrix rows(static_cast<Eigen::Index>(frames.size()), clip.channels.cols());
  for (size_t i = 0; i < frames.size(); ++i) {
    rows.row(static_cast<Eigen::Index>(i)) = clip.channels.row(frames[i]);
  }
  const GlobalPoses poses = ForwardKinematics(clip.skeleton, MotionFromChannels(clip.skeleton, rows, clip.frame_time));
  std::map<std::string, std::vector<Eigen::Vector3f>> sites;
  for (int j = 0; j < clip.skeleton.num_joints(); ++j) {
    const Joint& joint = clip.skeleton.joint(j);
    std::vector<Eigen::Vector3f>& at_joint = sites[joint.name];
    for (int i = 0; i < static_cast<int>(frames.size()); ++i) at_joint.push_back(poses.position(i, j));
    if (!joint.end_site) continue;
    std::vector<Eigen::Vector3f>& at_end = sites[joint.name + "/End Site"];
    for (int i = 0; i < static_cast<int>(frames.size()); ++i) {
      at_end.push_back(poses.position(i, j) + poses.rotation(i, j).normalized() * *joint.end_site);
    }
  }
  return sites;
}

struct RoundTripFileResult {
  enum class Outcome { kCompared, kRefused, kFailed };
  Outcome outcome = Outcome::kFailed;
  std::string message;  // kRefused: the documented reason and the importer's words; kFailed: what failed
  int frames_compared = 0;
  long long positions_compared = 0;
  LengthUnit unit = LengthUnit::kCentimetre;  // the file's own unit, as the import read it
  float worst = 0.0f;                         // in `unit`
  std::string worst_site;
  int worst_frame = -1;
  double worst_mm() const { return worst * MetresPerUnit(unit) * 1000.0; }
};

// Imports `file` alone into a new database `database` of the open store (its own rig, unit and
// frame rate), exports the stored clip as `mocap export` does, reads it back, and compares every
// joint and End Site position at the chosen frames with the file's own.
RoundTripFileResult RoundTripOneSharedFile(const fs::path& file, MotionStore& store, const fs::path& store_path,
                                           const std::string& database, int frame_step) {
  using Outcome = RoundTripFileResult::Outcome;
  RoundTripFileResult result;
  auto original = ReadBvhFile(file);
  if (!original.ok()) {
    result.message = StrCat("cannot read the file: ", original.status().ToString());
    return result;
  }
  ImportOptions options;
  options.store = store_path;
  options.database = database;
  options.inputs = {file.string()};
  options.frame_rate = original->frame_rate();
  options.threads = 1;
  auto summary = RunImport(options);
  if (!summary.ok()) {
    const std::string error = summary.status().ToString();
    for (const DocumentedRoundTripRefusal& refusal : kDocumentedRoundTripRefusals) {
      if (original->num_frames() <= refusal.max_frames && error.find(refusal.importer_says) != std::string::npos) {
        result.outcome = Outcome::kRefused;
        result.message = StrCat(refusal.why, " (", original->num_frames(), " frame(s); importer: ", error, ")");
        return result;
      }
    }
    result.message = StrCat("import refused (", original->num_frames(), " frames): ", error);
    return result;
  }
  if (summary->imported != 1) {
    result.message = StrCat("import stored ", summary->imported, " clips instead of one");
    return result;
  }
  auto found = store.FindDatabase(database);
  if (!found.ok()) {
    result.message = StrCat("database after import: ", found.status().ToString());
    return result;
  }
  auto rig = store.LoadRig(found->ref);
  if (!rig.ok()) {
    result.message = StrCat("rig after import: ", rig.status().ToString());
    return result;
  }
  result.unit = rig->unit;
  auto clips = store.ListClips(found->ref);
  if (!clips.ok() || clips->size() != 1) {
    result.message =
        StrCat("clips after import: ", clips.ok() ? StrCat(clips->size(), " clips") : clips.status().ToString());
    return result;
  }
  auto stored = store.LoadClip(found->ref, clips->front().id, *rig);
  if (!stored.ok()) {
    result.message = StrCat("loading the stored clip: ", stored.status().ToString());
    return result;
  }
  stored->motion.frame_time = 1.0 / found->frame_rate;
  auto exported = ParseBvh(FormatBvh(ToFileConventions(stored->skeleton, stored->motion, *rig)), "exported.bvh");
  if (!exported.ok()) {
    result.message = StrCat("reading the exported file back: ", exported.status().ToString());
    return result;
  }
  if (exported->num_frames() != original->num_frames()) {
    result.message = StrCat("exported ", exported->num_frames(), " frames of ", original->num_frames());
    return result;
  }
  if (std::abs(exported->frame_time - original->frame_time) > 1e-6) {
    result.message = StrCat("exported frame time ", exported->frame_time, " s instead of ", original->frame_time, " s");
    return result;
  }
  const std::vector<int> frames = RoundTripFrames(original->num_frames(), frame_step);
  const auto before = RoundTripSitePositions(*original, frames);
  const auto after = RoundTripSitePositions(*exported, frames);
  for (const auto& [site, positions] : before) {
    const auto it = after.find(site);
    if (it == after.end()) {
      result.message = StrCat("'", site, "' is missing from the exported file");
      return result;
    }
    for (size_t i = 0; i < positions.size(); ++i) {
      const float distance = (it->second[i] - positions[i]).norm();
      ++result.positions_compared;
      if (!(distance <= result.worst)) {  // NaN counts as worst
        result.worst = std::isnan(distance) ? std::numeric_limits<float>::infinity() : distance;
        result.worst_site = site;
        result.worst_frame = frames[i];
      }
    }
  }
  result.frames_compared = static_cast<int>(frames.size());
  const float tolerance = static_cast<float>(0.001 / MetresPerUnit(rig->unit));
  if (result.worst < tolerance) {
    result.outcome = Outcome::kCompared;
  } else {
    result.message = StrCat("worst '", result.worst_site, "' at frame ", result.worst_frame, ": ", result.worst, " ",
                            UnitName(rig->unit), " (", result.worst_mm(), " mm; tolerance 1 mm)");
  }
  return result;
}

TEST(ExportRoundTripTest, EveryFileOfEverySharedSetComesBackWithinOneMillimetreJointsAndEndSites) {
  MOCAP_REQUIRE_SHARED_DATA(bandai1, "bandai-namco-1");
  MOCAP_REQUIRE_SHARED_DATA(bandai2, "bandai-namco-2");
  MOCAP_REQUIRE_SHARED_DATA(cmu, "cmu-cc");
  MOCAP_REQUIRE_SHARED_DATA(other, "other-rigs");
  struct SharedSet {
    std::string name;
    fs::path folder;
    int frame_step;  // frames 0, middle, last and every frame_step-th: bandai-namco-2's 2,617 files are the bulk
  };
  const SharedSet sets[] = {
      {"bandai-namco-1", bandai1, 1}, {"bandai-namco-2", bandai2, 10}, {"cmu-cc", cmu, 1}, {"other-rigs", other, 1}};
  const auto start = std::chrono::steady_clock::now();
  testing::ScopedTempDir dir;
  // One store for the whole run, a database per file (its own rig, unit and rate), deleted once
  // checked; kept open so that each import's close is not the store's last (no checkpoint per file).
  const fs::path store_path = dir.path() / "round-trip.db";
  auto opened = MotionStore::Open(store_path);
  ASSERT_TRUE(opened.ok()) << opened.status();
  MotionStore& store = **opened;

  int files = 0, compared = 0;
  long long frames = 0, positions = 0;
  std::vector<std::string> refused, failed;
  double worst_mm = 0.0;
  std::string worst_where = "none";
  for (const SharedSet& set : sets) {
    const std::vector<fs::path> set_files = testing::BvhFilesIn(set.folder);
    EXPECT_FALSE(set_files.empty()) << "no .bvh files in " << set.folder;
    for (const fs::path& file : set_files) {
      const std::string name = set.name + "/" + file.filename().string();
      const std::string database = "round-trip-" + std::to_string(files++);
      const RoundTripFileResult result = RoundTripOneSharedFile(file, store, store_path, database, set.frame_step);
      if (auto found = store.FindDatabase(database); found.ok()) store.DeleteDatabase(found->ref).IgnoreError();
      frames += result.frames_compared;
      positions += result.positions_compared;
      if (result.frames_compared > 0 && result.worst_mm() > worst_mm) {
        worst_mm = result.worst_mm();
        worst_where = StrCat(name, " '", result.worst_site, "' frame ", result.worst_frame);
      }
      switch (result.outcome) {
        case RoundTripFileResult::Outcome::kCompared:
          ++compared;
          break;
        case RoundTripFileResult::Outcome::kRefused:
          refused.push_back(StrCat(name, ": ", result.message));
          break;
        case RoundTripFileResult::Outcome::kFailed:
          failed.push_back(StrCat(name, ": ", result.message));
          break;
      }
    }
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  for (const std::string& entry : refused) std::cout << "[ round trip ] refused (documented): " << entry << "\n";
  std::ostringstream line;
  line << "[ round trip ] " << files << " files: " << compared << " within 1 mm, " << refused.size()
       << " refused (documented), " << failed.size() << " failed; " << frames << " frames compared (" << positions
       << " joint and End Site positions); worst " << std::setprecision(3) << worst_mm << " mm (" << worst_where
       << "); " << seconds << " s";
  std::cout << line.str() << std::endl;
  std::string first_failures;
  for (size_t i = 0; i < failed.size() && i < 8; ++i) first_failures += "\n  " + failed[i];
  EXPECT_TRUE(failed.empty()) << failed.size() << " of " << files
                              << " files do not come back from import then export within 1 mm in their own unit"
                              << (failed.size() > 8 ? " (first 8)" : "") << ":" << first_failures;
  EXPECT_EQ(compared + static_cast<int>(refused.size()) + static_cast<int>(failed.size()), files);
  EXPECT_GT(compared, 0);
}

}  // namespace
}  // namespace mocap

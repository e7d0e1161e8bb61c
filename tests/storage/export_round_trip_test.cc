// Issue #23: every shared file survives import then export with its joints where they were,
// within 1 mm in its own unit (imported at its own frame rate, so nothing is resampled).
#include <filesystem>

#include <gtest/gtest.h>

#include "motion/bvh/bvh_reader.h"
#include "motion/bvh/bvh_writer.h"
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
    const RigModel rig = store->LoadRig(database.id).value();
    auto stored = store->LoadClip(store->ListClips(database.id)->front().id, rig);
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

}  // namespace
}  // namespace mocap

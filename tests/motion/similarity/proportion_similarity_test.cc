// Similarity across body proportions on real captures (issue #11): clips of each shared set
// queried as a new user would send them — re-rigged (renamed joints, a split spine bone, XYZ
// rotation order, inches, turned and moved), and the same joint rotations on a differently built
// body (legs, arms, spine and head each x0.8–1.25, or every bone its own factor in that range:
// tests/support/rig_variants.h), then re-rigged.
// The database holds every other clip of the set, the queried clips among them. Counts how often
// the top match (fast path, window 1) is the same pose (±2 frames) of the same clip and a clip of
// the same content, for each ChainScaling (the default bone directions, per-chain, the seed's
// body scale).
#include <gtest/gtest.h>

#include <algorithm>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "motion/bvh/bvh_reader.h"
#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"
#include "motion/preprocess/clip_labels.h"
#include "motion/preprocess/clip_preprocessor.h"
#include "motion/similarity/pose_index.h"
#include "motion/skeleton/forward_kinematics.h"
#include "tests/support/clip_points.h"
#include "tests/support/rig_variants.h"
#include "tests/support/shared_data.h"

namespace mocap {
namespace {

using testing::ChainScalingTestName;
using testing::PointsOf;
using testing::QueryPoints;

constexpr int kVariantDatabaseStride = 2;  // every other clip of a set in its database
constexpr int kQueryStride = 10;           // every 10th clip queried (all of them in the database)
constexpr int kFrameStride = 6;            // query frames

struct Rate {
  int queries = 0, same_pose = 0, same_content = 0;
  double pose() const { return queries ? static_cast<double>(same_pose) / queries : 0.0; }
  double content() const { return queries ? static_cast<double>(same_content) / queries : 0.0; }
  void Add(const Rate& other) {
    queries += other.queries;
    same_pose += other.same_pose;
    same_content += other.same_content;
  }
};

struct SetResult {
  Rate rerigged, proportions, every_bone;
  std::string error;
};

enum class VariantKind { kRerigged, kProportions, kEveryBone };

// The content label of a clip: Bandai's from the file name, CMU's from the descriptions.
std::string ContentOf(const std::filesystem::path& file, const std::map<std::string, std::string>& descriptions) {
  const ClipLabels labels = ParseClipLabels(file.filename().string());
  const std::string content = LabelValue(labels, "content");
  if (!content.empty()) return content;
  const auto it = descriptions.find(TrialKey(labels));
  return it == descriptions.end() ? file.stem().string() : it->second;
}

SetResult MeasureSet(const std::filesystem::path& folder, const BodyPointOptions& options) {
  SetResult result;
  const auto descriptions = std::filesystem::exists(folder / "cmu-descriptions.csv")
                                ? ReadTrialDescriptions(folder / "cmu-descriptions.csv")
                                : std::map<std::string, std::string>{};
  const std::vector<std::filesystem::path> files = testing::BvhFilesIn(folder);
  PoseIndex index(options);
  std::vector<std::string> content;              // per database clip
  std::vector<std::pair<int, BvhClip>> queried;  // database clip index, the clip as read
  std::vector<RigModel> rigs;
  for (size_t i = 0; i < files.size(); i += kVariantDatabaseStride) {
    absl::StatusOr<BvhClip> clip = ReadBvhFile(files[i]);
    if (!clip.ok()) return {.error = clip.status().ToString()};
    auto rig =
        std::find_if(rigs.begin(), rigs.end(), [&](const RigModel& r) { return r.skeleton.SameRigAs(clip->skeleton); });
    if (rig == rigs.end()) {
      absl::StatusOr<RigModel> built = BuildRigModel(*clip, {});
      if (!built.ok()) return {.error = StrCat(files[i].filename().string(), ": ", built.status().ToString())};
      rigs.push_back(*std::move(built));
      rig = rigs.end() - 1;
    }
    absl::StatusOr<ClipPoints> points = PointsOf(*clip, *rig, options);
    if (!points.ok()) return {.error = StrCat(files[i].filename().string(), ": ", points.status().ToString())};
    index.AddClip(*std::move(points));
    content.push_back(ContentOf(files[i], descriptions));
    if (i % kQueryStride == 0) queried.emplace_back(static_cast<int>(content.size()) - 1, *std::move(clip));
  }
  if (absl::Status built = index.Build(); !built.ok()) return {.error = built.ToString()};

  std::mt19937 random(11);
  for (const auto& [clip_index, original] : queried) {
    absl::StatusOr<RigModel> rig = BuildRigModel(original, {});
    if (!rig.ok()) return {.error = rig.status().ToString()};
    const int chest = rig->skeleton.parent(rig->topology.group_top[static_cast<int>(BodyGroup::kLeftArm)]);
    std::uniform_real_distribution<float> yaw(-180.0f, 180.0f), ground(-300.0f, 300.0f);
    for (VariantKind kind : {VariantKind::kRerigged, VariantKind::kProportions, VariantKind::kEveryBone}) {
      BvhClip variant = original;
      if (kind == VariantKind::kProportions)
        testing::ScaleProportions(variant, rig->topology, testing::RandomProportions(random));
      if (kind == VariantKind::kEveryBone) testing::ScaleEveryBone(variant, rig->topology, random);
      if (absl::Status status = testing::Rerig(variant, chest, yaw(random), {ground(random), 0.0f, ground(random)});
          !status.ok()) {
        return {.error = status.ToString()};
      }
      absl::StatusOr<ClipPoints> query = QueryPoints(variant, options);
      if (!query.ok()) return {.error = query.status().ToString()};
      Rate& rate = kind == VariantKind::kRerigged      ? result.rerigged
                   : kind == VariantKind::kProportions ? result.proportions
                                                       : result.every_bone;
      for (int f = 2; f < query->points.rows() - 2; f += kFrameStride) {
        PoseSearchOptions search;
        search.top_k = 1;
        absl::StatusOr<std::vector<PoseMatch>> matches = index.Search(*query, f, search);
        if (!matches.ok()) return {.error = matches.status().ToString()};
        const PoseMatch& best = matches->front();
        ++rate.queries;
        rate.same_pose += best.clip == clip_index && std::abs(best.frame - f) <= 2;
        rate.same_content += content[best.clip] == content[clip_index];
      }
    }
  }
  return result;
}

class ProportionSimilarityTest : public ::testing::TestWithParam<ChainScaling> {};

TEST_P(ProportionSimilarityTest, SamePoseFirstOnRerigsAndOtherProportions) {
  const BodyPointOptions options{.scaling = GetParam()};
  const std::string_view name = ChainScalingName(GetParam());
  Rate rerigged, proportions, every_bone;
  for (const char* set : {"bandai-namco-2", "bandai-namco-1", "cmu-cc"}) {
    MOCAP_REQUIRE_SHARED_DATA(folder, set);
    const SetResult r = MeasureSet(folder, options);
    ASSERT_TRUE(r.error.empty()) << set << ": " << r.error;
    std::cout << std::fixed << std::setprecision(3) << "[ proportions ] " << name << ", " << set << ": re-rigged "
              << r.rerigged.pose() << " same pose, " << r.rerigged.content() << " same content; proportions x0.8-1.25 "
              << r.proportions.pose() << " / " << r.proportions.content() << "; every bone x0.8-1.25 "
              << r.every_bone.pose() << " / " << r.every_bone.content() << " (" << r.proportions.queries
              << " query frames)\n"
              << std::defaultfloat;
    rerigged.Add(r.rerigged);
    proportions.Add(r.proportions);
    every_bone.Add(r.every_bone);
  }
  std::cout << std::fixed << std::setprecision(3) << "[ proportions ] " << name << ", all sets: re-rigged "
            << rerigged.pose() << " / " << rerigged.content() << "; proportions " << proportions.pose() << " / "
            << proportions.content() << "; every bone " << every_bone.pose() << " / " << every_bone.content() << " ("
            << proportions.queries << " query frames)\n"
            << std::defaultfloat;
  // Re-rigging changes no pose: exact under either scaling.
  EXPECT_EQ(rerigged.same_pose, rerigged.queries);
  if (GetParam() != ChainScaling::kBodyScale) {
    // Issue #11's targets: whole groups scaled (both are exact there by construction).
    EXPECT_GE(proportions.pose(), 0.95);
    EXPECT_GE(proportions.content(), 0.98);
  }
  if (GetParam() == ChainScaling::kBoneDirections) {
    // The same targets when every bone has its own factor (measured 0.985 / 0.999; per-chain
    // scaling 0.622 / 0.932, the body scale 0.447 / 0.888).
    EXPECT_GE(every_bone.pose(), 0.95);
    EXPECT_GE(every_bone.content(), 0.98);
  }
}

INSTANTIATE_TEST_SUITE_P(Scalings, ProportionSimilarityTest,
                         ::testing::Values(ChainScaling::kBoneDirections, ChainScaling::kPerChain,
                                           ChainScaling::kBodyScale),
                         [](const auto& info) { return ChainScalingTestName(info.param); });

}  // namespace
}  // namespace mocap

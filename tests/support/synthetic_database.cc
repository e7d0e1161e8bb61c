#include "tests/support/synthetic_database.h"

#include <stdexcept>

namespace mocap::testing {

SyntheticReconstructionSetup MakeSyntheticReconstructionSetup(const SyntheticRigOptions& options, int test_frames) {
  SyntheticReconstructionSetup setup;
  auto rig = BuildRigModel(MakeWalkingClip(options, 90), {});
  if (!rig.ok()) throw std::runtime_error(std::string(rig.status().message()));
  setup.rig = *rig;
  std::vector<DatabaseClip> clips;
  // Clips of several lengths: the same gait, so every phase of the cycle is present many times.
  for (int frames : {90, 61, 47}) {
    auto prepared = PrepareClip(MakeWalkingClip(options, frames), setup.rig, {});
    if (!prepared.ok()) throw std::runtime_error(std::string(prepared.status().message()));
    clips.push_back({prepared->features, EncodePoses(prepared->motion, setup.rig)});
  }
  auto db = ReconstructionDatabase::Build(setup.rig, clips);
  if (!db.ok()) throw std::runtime_error(std::string(db.status().message()));
  setup.database = *db;
  auto test = PrepareClip(MakeWalkingClip(options, test_frames), setup.rig, {});
  if (!test.ok()) throw std::runtime_error(std::string(test.status().message()));
  setup.test_clip = std::move(*test);
  setup.truth = ForwardKinematics(setup.test_clip.skeleton, setup.test_clip.motion);
  return setup;
}

std::vector<WristSample> WristSamplesOf(const SyntheticReconstructionSetup& setup, double start_time) {
  const BodyLandmarks& l = setup.rig.topology.landmarks;
  std::vector<WristSample> samples;
  for (int f = 0; f < setup.truth.num_frames(); ++f) {
    samples.push_back({start_time + f * setup.test_clip.motion.frame_time, setup.truth.position(f, l.left_wrist),
                       setup.truth.position(f, l.right_wrist)});
  }
  return samples;
}

const SyntheticReconstructionSetup& SharedSyntheticReconstructionSetup() {
  static const auto* setup = new SyntheticReconstructionSetup(MakeSyntheticReconstructionSetup({}, 30));
  return *setup;
}

LocalPoseModel LocalModelAtTestFrame(const SyntheticReconstructionSetup& setup, int frame, int neighbours,
                                     int components) {
  const ReconstructionDatabase& db = *setup.database;
  float query[kWristAnkleFeatureDims];
  WristAnkleFeature(setup.test_clip.features[frame], db.wrist_ankle_weights(), query);
  const std::vector<Neighbour> nearest = db.NearestByWristsAndAnkles(query, neighbours).value();
  Eigen::MatrixXf examples(static_cast<Eigen::Index>(nearest.size()), db.pose_feature_size());
  for (size_t i = 0; i < nearest.size(); ++i)
    examples.row(static_cast<Eigen::Index>(i)) = db.pose_feature(nearest[i].row);
  return FitLocalPoseModel(examples, components).value();
}

}  // namespace mocap::testing

#include "eval/evaluation.h"

#include <chrono>
#include <random>

#include "eval/parallel_for.h"
#include "eval/standard_split.h"
#include "motion/bvh/bvh_reader.h"
#include "motion/bvh/bvh_writer.h"
#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"
#include "motion/core/units.h"
#include "motion/preprocess/clip_labels.h"
#include "motion/preprocess/frame_features.h"
#include "motion/reconstruct/reconstruction_export.h"
#include "motion/reconstruct/wrist_reach.h"
#include "motion/skeleton/forward_kinematics.h"
#include "motion/skeleton/local_motion.h"

namespace mocap::eval {

namespace {

absl::StatusOr<std::pair<RigModel, std::vector<DatabaseClip>>> LoadDatabaseClips(
    const std::vector<std::filesystem::path>& files) {
  if (files.empty()) return absl::InvalidArgumentError("no database files");
  MOCAP_ASSIGN_OR_RETURN(BvhClip first, ReadBvhFile(files.front()));
  MOCAP_ASSIGN_OR_RETURN(RigModel rig, BuildRigModel(first, {}));
  std::vector<DatabaseClip> clips(files.size());
  MOCAP_RETURN_IF_ERROR(PrepareAll(files, rig, [&](size_t i, PreparedClip&& prepared) {
    clips[i] = {std::move(prepared.features), EncodePoses(prepared.motion, rig)};
  }));
  return std::pair{std::move(rig), std::move(clips)};
}

}  // namespace

absl::StatusOr<std::shared_ptr<const ReconstructionDatabase>> LoadDatabase(
    const std::vector<std::filesystem::path>& files) {
  MOCAP_ASSIGN_OR_RETURN(auto loaded, LoadDatabaseClips(files));
  return ReconstructionDatabase::Build(loaded.first, loaded.second);
}

absl::StatusOr<EvaluationDatabases> LoadDatabases(const std::vector<std::filesystem::path>& files,
                                                  const DatabaseBuildOptions& options) {
  MOCAP_ASSIGN_OR_RETURN(auto loaded, LoadDatabaseClips(files));
  EvaluationDatabases databases;
  MOCAP_ASSIGN_OR_RETURN(databases.method, ReconstructionDatabase::Build(loaded.first, loaded.second, options));
  DatabaseBuildOptions captured = options;
  captured.time_reversed_copies = false;
  MOCAP_ASSIGN_OR_RETURN(databases.captured, ReconstructionDatabase::Build(loaded.first, loaded.second, captured));
  for (const DatabaseClip& clip : loaded.second) {
    databases.captured_features.insert(databases.captured_features.end(), clip.features.begin(), clip.features.end());
  }
  return databases;
}

namespace {

void ScaleBody(float scale, const RigModel& rig, PreparedClip* clip) {
  std::vector<Joint> joints = clip->skeleton.joints();
  for (Joint& joint : joints) {
    joint.offset *= scale;
    if (joint.end_site) *joint.end_site *= scale;
  }
  clip->skeleton = Skeleton(std::move(joints));
  for (Eigen::ArrayXXf* t : {&clip->motion.tx, &clip->motion.ty, &clip->motion.tz}) *t *= scale;
  clip->features = ComputeFrameFeatures(ForwardKinematics(clip->skeleton, clip->motion), rig.topology.landmarks,
                                        rig.pelvis_up_local, clip->motion.frame_time);
}

}  // namespace

absl::StatusOr<std::vector<TestClip>> LoadTestClips(const std::vector<std::filesystem::path>& files,
                                                    const RigModel& rig, int max_frames,
                                                    const std::string& content_prefix, float body_scale) {
  std::vector<TestClip> tests(files.size());
  MOCAP_RETURN_IF_ERROR(PrepareAll(files, rig, [&](size_t i, PreparedClip&& prepared) {
    TestClip& t = tests[i];
    t.name = files[i].filename().string();
    const std::string content = LabelValue(ParseClipLabels(t.name), "content");
    t.content = content_prefix + (content.empty() ? "other" : content);
    if (max_frames > 0 && prepared.num_frames() > max_frames) {
      LocalMotion& m = prepared.motion;
      for (Eigen::ArrayXXf* a : {&m.qw, &m.qx, &m.qy, &m.qz, &m.tx, &m.ty, &m.tz})
        a->conservativeResize(max_frames, Eigen::NoChange);
      prepared.features.resize(max_frames);
    }
    if (body_scale != 1.0f) ScaleBody(body_scale, rig, &prepared);
    t.truth = ForwardKinematics(prepared.skeleton, prepared.motion);
    t.clip = std::move(prepared);
  }));
  return tests;
}

std::vector<WristSample> NoisyWristSamples(int frames, double frame_time,
                                           const std::function<std::array<Eigen::Vector3f, 2>(int)>& wrists,
                                           double noise_cm, unsigned seed) {
  std::mt19937 random(seed);
  std::normal_distribution<float> noise(0.0f, static_cast<float>(noise_cm / 100.0));
  std::vector<WristSample> samples;
  samples.reserve(frames);
  for (int f = 0; f < frames; ++f) {
    const std::array<Eigen::Vector3f, 2> at = wrists(f);
    WristSample s{.time = f * frame_time, .left = at[0], .right = at[1]};
    if (noise_cm > 0) {
      for (int axis = 0; axis < 3; ++axis) {
        s.left[axis] += noise(random);
        s.right[axis] += noise(random);
      }
    }
    samples.push_back(s);
  }
  return samples;
}

namespace {

// Issue #23: the file written must be what was scored. Reads it back (Blender's importer and
// three.js's BVHLoader read written files as this reader does: tests/motion/bvh/
// bvh_conformance_test.cc) and gives the largest distance, over the pelvis and every joint below
// it (those above stay at rest in written files), from the scored body, in metres.
absl::StatusOr<double> WrittenFileDeviation(const ReconstructionDatabase& database,
                                            const std::vector<ReconstructedFrame>& frames,
                                            const std::filesystem::path& file) {
  MOCAP_ASSIGN_OR_RETURN(BvhClip written, ReadBvhFile(file));
  if (written.num_frames() != static_cast<int>(frames.size())) {
    return absl::DataLossError(
        StrCat(file.string(), ": written with ", written.num_frames(), " frames, scored ", frames.size()));
  }
  const RigModel& rig = database.rig();
  LocalMotion motion = MotionFromChannels(written.skeleton, written.channels, written.frame_time);
  ScaleTranslations(motion, static_cast<float>(MetresPerUnit(rig.unit)));
  RotateWorld(motion, rig.to_y_up);
  const GlobalPoses read = ForwardKinematics(written.skeleton, motion);
  const int pelvis = rig.topology.landmarks.pelvis;
  std::vector<bool> below_pelvis(written.skeleton.num_joints(), false);
  for (int j = 0; j < written.skeleton.num_joints(); ++j) {
    below_pelvis[j] = j == pelvis || (written.skeleton.parent(j) >= 0 && below_pelvis[written.skeleton.parent(j)]);
  }
  std::vector<Eigen::Quaternionf> rotations;
  std::vector<Eigen::Vector3f> positions;
  double worst = 0.0;
  for (size_t f = 0; f < frames.size(); ++f) {
    database.body().WorldTransforms(frames[f].pose, &rotations, &positions);
    for (int j = 0; j < written.skeleton.num_joints(); ++j) {
      if (below_pelvis[j])
        worst = std::max(worst, double((read.position(static_cast<int>(f), j) - positions[j]).norm()));
    }
  }
  return worst;
}

// The captured clip as measured (database rate, cut, metres, Y up) on its own skeleton.
BvhClip TruthBvh(const TestClip& test) {
  return {test.clip.skeleton, test.clip.motion.frame_time, ChannelsFromMotion(test.clip.skeleton, test.clip.motion)};
}

constexpr double kMaxWrittenDeviationMetres = 0.001;

// The confidence pairs of a reconstruction on the database's rig, frame by frame against the
// capture's landmarks.
void ConfidenceSamplesOf(const ReconstructionDatabase& database, const GlobalPoses& truth,
                         const std::vector<ReconstructedFrame>& frames, std::vector<ConfidenceSample>* samples) {
  const std::array<int, kNumBodyLandmarks> joints = BodyLandmarkJoints(database.rig().topology.landmarks);
  std::vector<Eigen::Quaternionf> rotations;
  std::vector<Eigen::Vector3f> positions;
  std::array<Eigen::Vector3f, kNumBodyLandmarks> output, captured;
  const int scored = std::min(truth.num_frames(), static_cast<int>(frames.size()));
  samples->reserve(static_cast<size_t>(scored) * kNumBodyLandmarks);
  for (int f = 0; f < scored; ++f) {
    database.body().WorldTransforms(frames[f].pose, &rotations, &positions);
    for (int k = 0; k < kNumBodyLandmarks; ++k) {
      output[k] = positions[joints[k]];
      captured[k] = truth.position(f, joints[k]);
    }
    AddConfidenceSamples(frames[f], 1.0f, output, captured, samples);
  }
}

}  // namespace

int ClipsSizedByReach(const ReconstructionDatabase& database, const std::vector<TestClip>& tests) {
  const BodyLandmarks& l = database.rig().topology.landmarks;
  int sized = 0;
  for (const TestClip& test : tests) {
    std::vector<WristSample> wrists(test.truth.num_frames());
    for (int f = 0; f < test.truth.num_frames(); ++f) {
      wrists[f] = {.time = f * test.clip.motion.frame_time,
                   .left = test.truth.position(f, l.left_wrist),
                   .right = test.truth.position(f, l.right_wrist)};
    }
    const absl::StatusOr<ReachScale> reach = InputScaleFromReach(database.wrist_reach(), wrists);
    if (reach.ok() && reach->input_scale < 1.0f) ++sized;
  }
  return sized;
}

absl::StatusOr<std::vector<ExperimentResult>> RunEvaluation(const EvaluationDatabases& databases,
                                                            const std::vector<TestClip>& tests,
                                                            const std::vector<Experiment>& experiments,
                                                            const EvaluationConfig& config,
                                                            const std::function<void(const std::string&)>& progress) {
  std::vector<ExperimentResult> results;
  if (!config.bvh_dir.empty()) std::filesystem::create_directories(config.bvh_dir / "truth");
  for (const Experiment& experiment : experiments) {
    const std::shared_ptr<const ReconstructionDatabase>& database = databases.For(experiment);
    ExperimentResult result{experiment, {}, {}};
    std::vector<Metrics> per_clip(tests.size());
    std::vector<std::vector<ConfidenceSample>> confidence(tests.size());
    MOCAP_RETURN_IF_ERROR(ParallelFor(tests.size(), config.threads, [&](size_t i) -> absl::Status {
      const TestClip& test = tests[i];
      const BodyLandmarks& l = database->rig().topology.landmarks;
      // One seed per clip: the same noise whatever the thread count or experiment order.
      const std::vector<WristSample> wrists = NoisyWristSamples(
          test.truth.num_frames(), test.clip.motion.frame_time,
          [&](int f) {
            return std::array<Eigen::Vector3f, 2>{test.truth.position(f, l.left_wrist),
                                                  test.truth.position(f, l.right_wrist)};
          },
          experiment.noise_cm, config.seed + static_cast<unsigned>(i));
      const auto start = std::chrono::steady_clock::now();
      absl::StatusOr<std::vector<ReconstructedFrame>> frames = ReconstructOffline(database, experiment.options, wrists);
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      if (!frames.ok()) return absl::Status(frames.status().code(), StrCat(test.name, ": ", frames.status().message()));
      per_clip[i] = Measure(*database, test.clip, test.truth, *frames);
      per_clip[i].seconds = seconds;
      ConfidenceSamplesOf(*database, test.truth, *frames, &confidence[i]);
      for (ConfidenceSample& sample : confidence[i]) sample.clip = static_cast<int>(i);
      if (experiment.name != "full" || config.bvh_dir.empty()) return absl::OkStatus();
      const std::filesystem::path out = config.bvh_dir / test.name;
      MOCAP_RETURN_IF_ERROR(WriteBvhFile(ReconstructionToBvh(*database, *frames), out));
      MOCAP_ASSIGN_OR_RETURN(const double deviation, WrittenFileDeviation(*database, *frames, out));
      if (deviation > kMaxWrittenDeviationMetres) {
        return absl::InternalError(StrCat(out.string(), ": the file written is ", 1000 * deviation,
                                          " mm from the reconstruction scored (at most ",
                                          1000 * kMaxWrittenDeviationMetres, " mm)"));
      }
      return WriteBvhFile(TruthBvh(test), config.bvh_dir / "truth" / test.name);
    }));
    std::vector<ConfidenceSample> all_confidence;
    for (const std::vector<ConfidenceSample>& clip : confidence)
      all_confidence.insert(all_confidence.end(), clip.begin(), clip.end());
    result.confidence = SummariseConfidence(all_confidence);
    if (experiment.name == "full" && !config.confidence_samples.empty())
      MOCAP_RETURN_IF_ERROR(WriteConfidenceSamples(all_confidence, config.confidence_samples));
    for (size_t i = 0; i < tests.size(); ++i) {
      result.overall.Add(per_clip[i]);
      result.by_content[tests[i].content].Add(per_clip[i]);
      result.clips.push_back({tests[i].name, tests[i].content, per_clip[i]});
    }
    if (progress) {
      progress(StrCat(experiment.name, ": MPJPE ", 100 * result.overall.Mean(result.overall.joint_error_m), " cm over ",
                      result.overall.frames, " frames, ",
                      result.overall.frames / std::max(1e-9, result.overall.seconds), " frames/s; pelvis max ",
                      result.overall.plausibility.pelvis_speed.max(), " m/s (capture's ",
                      result.overall.truth_pelvis_speed_max, "), ", result.overall.clips_over_allowed_speed,
                      " clips over the allowed speed, hands p99 ",
                      100 * result.overall.plausibility.hand_distance.Quantile(0.99), " cm from the input"));
    }
    results.push_back(std::move(result));
  }
  return results;
}

}  // namespace mocap::eval

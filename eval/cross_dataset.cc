#include "eval/cross_dataset.h"

#include <chrono>
#include <fstream>
#include <random>

#include "eval/device_input.h"
#include "eval/parallel_for.h"
#include "motion/bvh/bvh_reader.h"
#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"
#include "motion/core/units.h"
#include "motion/preprocess/clip_labels.h"
#include "motion/preprocess/clip_preprocessor.h"
#include "motion/reconstruct/body_model.h"
#include "motion/reconstruct/body_sizer.h"
#include "motion/reconstruct/performer_scale.h"
#include "motion/reconstruct/wrist_reach.h"
#include "motion/skeleton/forward_kinematics.h"

namespace mocap::eval {

absl::StatusOr<LandmarkTestClip> LoadLandmarkTestClip(const std::filesystem::path& file, std::string source,
                                                      std::string content, int max_frames) {
  MOCAP_ASSIGN_OR_RETURN(BvhClip clip, ReadBvhFile(file));
  if (max_frames > 0 && clip.num_frames() > max_frames) clip.channels.conservativeResize(max_frames, Eigen::NoChange);
  if (clip.num_frames() < 2) {
    return absl::FailedPreconditionError(StrCat(file.filename().string(), ": one frame, nothing moves"));
  }
  MOCAP_ASSIGN_OR_RETURN(RigModel rig, BuildRigModel(clip, {}));
  const std::array<int, kNumScoredLandmarks> joints = ScoredLandmarkJoints(rig.topology.landmarks);
  for (int k = 0; k < kNumScoredLandmarks; ++k) {
    if (joints[k] < 0) {
      return absl::FailedPreconditionError(
          StrCat(file.filename().string(), ": the rig's analysis found no ", kLandmarkGroupNames[kLandmarkGroup[k]]));
    }
  }
  // At its own rate: the engine resamples the wrists as it would a device's.
  MOCAP_ASSIGN_OR_RETURN(PreparedClip prepared, PrepareClip(clip, rig, {.frame_rate = 1.0 / clip.frame_time}));
  const GlobalPoses poses = ForwardKinematics(prepared.skeleton, prepared.motion);
  LandmarkTestClip test{file.filename().string(), std::move(source), std::move(content), {}};
  test.truth.frame_time = prepared.motion.frame_time;
  test.truth.positions.resize(poses.num_frames());
  for (int f = 0; f < poses.num_frames(); ++f) {
    for (int k = 0; k < kNumScoredLandmarks; ++k) test.truth.positions[f][k] = poses.position(f, joints[k]);
  }
  return test;
}

bool Moves(const LandmarkTruth& truth) {
  constexpr float kMovedMetres = 0.05f;
  for (const auto& frame : truth.positions) {
    for (int k = 0; k < kNumScoredLandmarks; ++k) {
      if ((frame[k] - truth.positions.front()[k]).norm() >= kMovedMetres) return true;
    }
  }
  return false;
}

namespace {

struct NamedFile {
  std::filesystem::path path;
  std::string source, content;
};

absl::StatusOr<LandmarkTestSet> LoadAll(const std::vector<NamedFile>& files, int max_frames) {
  std::vector<absl::StatusOr<LandmarkTestClip>> loaded(files.size(), absl::UnknownError("not loaded"));
  MOCAP_RETURN_IF_ERROR(ParallelFor(files.size(), AllCores(), [&](size_t i) {
    loaded[i] = LoadLandmarkTestClip(files[i].path, files[i].source, files[i].content, max_frames);
    return absl::OkStatus();
  }));
  LandmarkTestSet set;
  for (size_t i = 0; i < files.size(); ++i) {
    if (!loaded[i].ok()) {
      // A file the reader refuses is an error; one whose landmarks cannot all be found is left out.
      if (loaded[i].status().code() != absl::StatusCode::kFailedPrecondition) {
        return absl::Status(loaded[i].status().code(),
                            StrCat(files[i].path.string(), ": ", loaded[i].status().message()));
      }
      set.left_out.push_back(std::string(loaded[i].status().message()));
    } else if (!Moves(loaded[i]->truth)) {
      set.left_out.push_back(StrCat(files[i].path.filename().string(), ": does not move"));
    } else {
      set.clips.push_back(*std::move(loaded[i]));
    }
  }
  return set;
}

std::string ContentFromName(const std::filesystem::path& file) {
  const std::string content = LabelValue(ParseClipLabels(file.filename().string()), "content");
  return content.empty() ? "other" : content;
}

// The fields of one CSV line (double quotes around fields that hold commas).
std::vector<std::string> CsvFields(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (char c : line) {
    if (c == '"') {
      quoted = !quoted;
    } else if (c == ',' && !quoted) {
      fields.emplace_back();
    } else if (c != '\r') {
      fields.back() += c;
    }
  }
  return fields;
}

// cmu-cc: what each trial shows, from cmu-descriptions.csv ("dance - small jetes, pirouette" →
// "dance"), keyed "subject_trial" as the file names ("005_12").
std::map<std::string, std::string> CmuContents(const std::filesystem::path& folder) {
  std::map<std::string, std::string> contents;
  std::ifstream in(folder / "cmu-descriptions.csv");
  std::string line;
  while (std::getline(in, line)) {
    const std::vector<std::string> f = CsvFields(line);
    if (f.size() < 3 || f[0].empty() || !std::isdigit(static_cast<unsigned char>(f[0][0]))) continue;
    std::string content = f[2].substr(0, std::min(f[2].find(" - "), f[2].find(',')));
    char key[32];
    std::snprintf(key, sizeof key, "%03d_%02d", std::atoi(f[0].c_str()), std::atoi(f[1].c_str()));
    contents[key] = content.empty() ? "other" : content;
  }
  return contents;
}

constexpr float kWalkingSpeed = 0.6f;  // m/s, the wrists' midpoint over the ground

float Median(std::vector<float> values) {
  if (values.empty()) return 1.0f;
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return std::max(1e-3f, values[values.size() / 2]);
}

// What the PerformerSize estimates compare the input with: the database body's bone lengths and
// its clips' wrist heights (the lower wrist; both wrists while walking).
struct SizeReference {
  LandmarkBodySize body;
  float lower_wrist = 0, walking_wrist = 0;  // medians, metres; 0: no walking frame
};

SizeReference DatabaseSizeReference(const EvaluationDatabases& databases) {
  SizeReference reference{.body = BodySizeOf(*databases.captured)};
  std::vector<float> lower, walking;
  for (const FrameFeatures& f : databases.captured_features) {
    lower.push_back(std::min(f.wrist_position[0][1], f.wrist_position[1][1]));
    const float vx = 0.5f * (f.wrist_velocity[0][0] + f.wrist_velocity[1][0]);
    const float vz = 0.5f * (f.wrist_velocity[0][2] + f.wrist_velocity[1][2]);
    if (std::hypot(vx, vz) < kWalkingSpeed) continue;
    walking.push_back(f.wrist_position[0][1]);
    walking.push_back(f.wrist_position[1][1]);
  }
  reference.lower_wrist = Median(lower);
  reference.walking_wrist = walking.empty() ? 0.0f : Median(walking);
  return reference;
}

// How much to scale a test's input (and divide its output by) to bring the performer to the
// database body's size (experiments.h, PerformerSize).
float TruthScale(const SizeReference& reference, const LandmarkTruth& truth) {
  const LandmarkBodySize performer = BodySizeOf(truth.positions.front());
  return (reference.body.leg + reference.body.arm) / (performer.leg + performer.arm);
}

// kService as the service resolves it: the reach estimate for a whole trajectory, followed
// online in the streaming modes.
PerformerSize ServiceSize(const Experiment& experiment) {
  if (experiment.size != PerformerSize::kService) return experiment.size;
  const bool whole = experiment.options.mode == StreamMode::kSubInterval && experiment.options.window == 0;
  return whole ? PerformerSize::kReach : PerformerSize::kOnline;
}

float InputScale(PerformerSize size, const ReconstructionDatabase& database, const SizeReference& reference,
                 const LandmarkTruth& truth, const std::vector<WristSample>& wrists, unsigned declared_seed,
                 float grip_offset, PerformerScaleEstimate* fit_out = nullptr) {
  switch (size) {
    case PerformerSize::kDatabase:
    case PerformerSize::kOnline:   // sized as the input streams in (BodySizer)
    case PerformerSize::kService:  // resolved by the caller (ServiceSize)
      return 1.0f;
    case PerformerSize::kTruth:
      return TruthScale(reference, truth);
    case PerformerSize::kDeclared: {
      const LandmarkBodySize performer = BodySizeOf(truth.positions.front());
      std::mt19937 random(declared_seed);
      std::normal_distribution<float> error(0.0f, 0.03f);
      const float declared = static_cast<float>(performer.leg / kLegShareOfStature) * (1.0f + error(random));
      return EstimatedStature(database.body()) / declared;
    }
    case PerformerSize::kDatabaseFit: {
      absl::StatusOr<PerformerScaleEstimate> fit = EstimatePerformerScale(database, wrists);
      if (fit_out != nullptr && fit.ok()) *fit_out = *fit;
      return fit.ok() ? fit->scale : 1.0f;
    }
    case PerformerSize::kLowerWrist: {
      std::vector<float> lower;
      for (const WristSample& s : wrists) lower.push_back(std::min(s.left.y(), s.right.y()));
      return std::clamp(reference.lower_wrist / Median(lower), 0.7f, 1.4f);
    }
    case PerformerSize::kReach: {
      absl::StatusOr<ReachScale> reach = InputScaleFromReach(DeviceReach(database.wrist_reach(), grip_offset), wrists);
      return reach.ok() ? reach->input_scale : 1.0f;
    }
    case PerformerSize::kWalkingWrists: {
      std::vector<float> heights;
      for (size_t k = 2; k + 2 < wrists.size(); ++k) {
        const double dt = wrists[k + 2].time - wrists[k - 2].time;
        const Eigen::Vector3f moved =
            0.5f * (wrists[k + 2].left + wrists[k + 2].right - wrists[k - 2].left - wrists[k - 2].right);
        if (dt <= 0 || std::hypot(moved.x(), moved.z()) / dt < kWalkingSpeed) continue;
        heights.push_back(wrists[k].left.y());
        heights.push_back(wrists[k].right.y());
      }
      // At least a second of walking frames (two heights per sample), else the database's size.
      const double seconds = wrists.size() > 1 ? (wrists.back().time - wrists.front().time) : 0.0;
      const double per_second = seconds > 0 ? 2.0 * (wrists.size() - 1) / seconds : 0.0;
      if (reference.walking_wrist <= 0 || static_cast<double>(heights.size()) < per_second) return 1.0f;
      return std::clamp(reference.walking_wrist / Median(heights), 0.75f, 1.33f);
    }
  }
  return 1.0f;
}

}  // namespace

absl::StatusOr<LandmarkTestSet> LoadLandmarkTests(const std::vector<std::filesystem::path>& files, int max_frames,
                                                  float body_scale) {
  std::vector<NamedFile> named;
  for (const auto& file : files) named.push_back({file, "named", ContentFromName(file)});
  MOCAP_ASSIGN_OR_RETURN(LandmarkTestSet set, LoadAll(named, max_frames));
  if (body_scale != 1.0f) {
    for (LandmarkTestClip& clip : set.clips) {
      for (auto& frame : clip.truth.positions) {
        for (Eigen::Vector3f& position : frame) position *= body_scale;
      }
    }
  }
  return set;
}

absl::StatusOr<LandmarkTestSet> LoadCrossDatasetTests(const datasets::DataLocation& data, int max_frames) {
  std::vector<NamedFile> files;
  for (const char* set : {"bandai-namco-1", "cmu-cc", "other-rigs"}) {
    std::string why;
    const std::optional<std::filesystem::path> folder = datasets::UnpackedSet(data, set, &why);
    if (!folder) return absl::NotFoundError(StrCat("the cross-dataset protocol needs ", set, ": ", why));
    const std::map<std::string, std::string> cmu =
        set == std::string_view("cmu-cc") ? CmuContents(*folder) : std::map<std::string, std::string>{};
    for (const std::filesystem::path& file : datasets::BvhFilesIn(*folder)) {
      std::string content;
      if (set == std::string_view("bandai-namco-1")) {
        content = ContentFromName(file);
      } else if (set == std::string_view("cmu-cc")) {
        const auto found = cmu.find(file.stem().string());
        content = found == cmu.end() ? "other" : found->second;
      } else {  // other-rigs: the exporter or lab, the file name's first word
        content = file.stem().string().substr(0, file.stem().string().find('_'));
      }
      files.push_back({file, set, content});
    }
  }
  return LoadAll(files, max_frames);
}

absl::StatusOr<std::vector<LandmarkExperimentResult>> RunLandmarkEvaluation(
    const EvaluationDatabases& databases, const std::vector<LandmarkTestClip>& tests,
    const std::vector<Experiment>& experiments, unsigned seed, int threads,
    const std::filesystem::path& confidence_samples, const std::function<void(const std::string&)>& progress) {
  std::vector<LandmarkExperimentResult> results;
  const SizeReference reference = DatabaseSizeReference(databases);
  for (const Experiment& experiment : experiments) {
    const std::shared_ptr<const ReconstructionDatabase>& database = databases.For(experiment);
    std::vector<LandmarkMetrics> per_clip(tests.size());
    std::vector<float> input_scales(tests.size(), 1.0f);
    std::vector<PerformerScaleEstimate> fits(tests.size());
    std::vector<std::vector<ConfidenceSample>> confidence(tests.size());
    MOCAP_RETURN_IF_ERROR(ParallelFor(tests.size(), threads, [&](size_t i) -> absl::Status {
      const LandmarkTruth& truth = tests[i].truth;
      std::vector<WristSample> wrists =
          DeviceSamples(truth, experiment.device, experiment.noise_cm, seed + static_cast<unsigned>(i));
      // The input is multiplied by it, the output divided; or sized as it streams in.
      const PerformerSize size = ServiceSize(experiment);
      const float scale = InputScale(size, *database, reference, truth, wrists, seed + static_cast<unsigned>(i),
                                     experiment.options.grip_offset, &fits[i]);
      BodySizer sizer(DeviceReach(database->wrist_reach(), experiment.options.grip_offset), 1.0f / scale,
                      {.online = size == PerformerSize::kOnline});
      const auto start = std::chrono::steady_clock::now();
      std::vector<SizeMap> maps;
      absl::StatusOr<std::vector<ReconstructedFrame>> frames =
          ReconstructSized(database, experiment.options, wrists, sizer, &maps);
      if (!frames.ok())
        return absl::Status(frames.status().code(), StrCat(tests[i].name, ": ", frames.status().message()));
      input_scales[i] = 1.0f / sizer.map().scale;  // where the size ended
      per_clip[i] = MeasureLandmarks(*database, truth, *frames, maps, &confidence[i]);
      if (experiment.device.dropout_s > 0 || experiment.device.gap_every_s > 0 ||
          experiment.device.left_hand_lost_s > 0)
        MeasureReentryJerk(*database, truth, *frames, wrists, maps, &per_clip[i]);
      // Input in another posture than the capture's has no truth to calibrate against.
      if (!experiment.device.accuracy_measured()) confidence[i].clear();
      for (ConfidenceSample& sample : confidence[i]) sample.clip = static_cast<int>(i);
      per_clip[i].seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      return absl::OkStatus();
    }));
    LandmarkExperimentResult result{experiment, {}, {}, {}, {}, {}, {}};
    std::vector<ConfidenceSample> all_confidence;
    std::map<std::string, std::vector<ConfidenceSample>> confidence_by_source;
    for (size_t i = 0; i < tests.size(); ++i) {
      all_confidence.insert(all_confidence.end(), confidence[i].begin(), confidence[i].end());
      std::vector<ConfidenceSample>& source = confidence_by_source[tests[i].source];
      source.insert(source.end(), confidence[i].begin(), confidence[i].end());
      std::vector<ConfidenceSample>().swap(confidence[i]);
    }
    result.confidence = SummariseConfidence(all_confidence);
    for (const auto& [source, samples] : confidence_by_source)
      result.confidence_by_source[source] = SummariseConfidence(samples);
    if (!confidence_samples.empty() && (experiment.name == "full" || !experiment.device.name.empty())) {
      MOCAP_RETURN_IF_ERROR(
          WriteConfidenceSamples(all_confidence, ConfidenceSamplesFile(confidence_samples, experiment.name)));
    }
    for (size_t i = 0; i < tests.size(); ++i) {
      result.overall.Add(per_clip[i]);
      result.by_source[tests[i].source].Add(per_clip[i]);
      result.by_content[StrCat(tests[i].source, "/", tests[i].content)].Add(per_clip[i]);
      result.clips.push_back({tests[i].name, tests[i].source, tests[i].content,
                              BodySizeOf(tests[i].truth.positions.front()), per_clip[i], input_scales[i],
                              TruthScale(reference, tests[i].truth), fits[i].candidates, fits[i].cost});
    }
    if (progress) {
      const LandmarkMetrics& o = result.overall;
      const std::string accuracy = experiment.device.accuracy_measured()
                                       ? StrCat("landmarks ", 100 * o.Mean(o.landmark_error_m), " cm, wrists ",
                                                100 * o.Mean(o.wrist_error_m()), " cm")
                                       : std::string("no truth in this posture");
      progress(StrCat(experiment.name, ": ", accuracy, " over ", o.frames, " frames; ", o.clips_over_allowed_speed,
                      " clips over the allowed pelvis speed"));
    }
    results.push_back(std::move(result));
  }
  return results;
}

}  // namespace mocap::eval

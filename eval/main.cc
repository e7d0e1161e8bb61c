// mocap-eval: the evaluation harness of issue #3. Runs the standard split of shared/data/README
// (or any database and test clips named on the command line) through the full method, the two
// baselines and (with --ablations) the window / noise / lag ablations, and writes report.json,
// report.md, SVG plots and every reconstruction as BVH.
#include <algorithm>
#include <fstream>
#include <iostream>
#include <iterator>
#include <set>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "eval/cross_dataset.h"
#include "eval/datasets/shared_data.h"
#include "eval/evaluation.h"
#include "eval/landmark_report.h"
#include "eval/quick_thresholds.h"
#include "eval/report.h"
#include "eval/standard_split.h"
#include "motion/bvh/bvh_files.h"
#include "motion/core/str_cat.h"
#include "motion/preprocess/clip_labels.h"

namespace {

constexpr int kExitRegression = 1, kExitError = 2, kExitNoData = 77;

// The BVH files of the given files and folders (motion/bvh/bvh_files.h); false, with the error
// printed, when an input is missing or holds none.
bool CollectInto(const std::vector<std::string>& inputs, std::vector<std::filesystem::path>* files) {
  absl::StatusOr<std::vector<std::filesystem::path>> collected = mocap::CollectBvhFiles(inputs);
  if (!collected.ok()) {
    std::cerr << "mocap-eval: " << collected.status().message() << "\n";
    return false;
  }
  *files = *std::move(collected);
  return true;
}

// --quick: the first held-out take of every content type, cut short.
std::vector<std::filesystem::path> QuickSubset(const std::vector<std::filesystem::path>& tests) {
  std::vector<std::filesystem::path> subset;
  std::set<std::string> seen;
  for (const auto& file : tests) {
    const std::string content = mocap::LabelValue(mocap::ParseClipLabels(file.filename().string()), "content");
    if (seen.insert(content).second) subset.push_back(file);
  }
  return subset;
}

// Tests scored on landmarks (clips on any rig; the cross-dataset protocol): runs, writes
// landmarks.md / landmarks.json, prints the per-source table.
int RunLandmarkTests(const mocap::eval::EvaluationDatabases& databases, const mocap::eval::LandmarkTestSet& tests,
                     const std::vector<mocap::eval::Experiment>& experiments, nlohmann::json context,
                     const std::string& out_dir, unsigned seed, int threads,
                     const std::filesystem::path& confidence_samples) {
  if (tests.clips.empty()) {
    std::cerr << "mocap-eval: no test clip can be scored\n";
    return kExitError;
  }
  context["test_clips"] = tests.clips.size();
  std::cerr << "reconstructing " << tests.clips.size() << " clips (scored on landmarks) with " << experiments.size()
            << " runs...\n";
  auto results =
      mocap::eval::RunLandmarkEvaluation(databases, tests.clips, experiments, seed, threads, confidence_samples,
                                         [](const std::string& line) { std::cerr << "  " << line << "\n"; });
  if (!results.ok()) {
    std::cerr << "mocap-eval: " << results.status().message() << "\n";
    return kExitError;
  }
  absl::StatusOr<std::string> summary = mocap::eval::WriteLandmarkReport(out_dir, context, tests.left_out, *results);
  if (!summary.ok()) {
    std::cerr << "mocap-eval: " << summary.status().message() << "\n";
    return kExitError;
  }
  std::cout << *summary;
  std::cout << "wrote " << out_dir << "/landmarks.md, landmarks.json\n";
  return 0;
}

// Every run `--runs` names is one of `experiments` (the runs this invocation can make): a name
// that matches none — a typo, an ablation without --ablations, a device run without --devices —
// is an error naming what it can be, not a run silently left out.
bool KnowsEveryRun(const std::vector<std::string>& only_runs, const std::vector<mocap::eval::Experiment>& experiments) {
  bool known = true;
  for (const std::string& name : only_runs) {
    if (std::any_of(experiments.begin(), experiments.end(), [&](const auto& e) { return e.name == name; })) continue;
    std::cerr << "mocap-eval: --runs " << name
              << ": no such run here (ablations need --ablations, RUN@DEVICE needs --devices; the runs are listed "
                 "in docs/evaluation.md)\n";
    known = false;
  }
  return known;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"mocap-eval — accuracy, motion quality and speed of the wrist-to-body reconstruction"};
  std::string out_dir = "out/eval";
  std::vector<std::string> database_dirs, test_paths;
  bool quick = false, ablations = false, generalisation = false, no_bvh = false, development = false;
  double noise_cm = 0.5;
  float test_body_scale = 1.0f;
  unsigned seed = 1;
  int max_frames = 0, max_clips = 0, threads = 2;
  mocap::ReconstructionOptions base;
  std::string thresholds_file;  // empty: the thresholds built in (eval/quick_thresholds.json)
  std::string shared_data;
  app.add_option("--out", out_dir, "output folder (report.json, report.md, plots/, bvh/)");
  app.add_option("--database-dir", database_dirs, "BVH folders forming the database (default: the standard split)");
  app.add_option("--test", test_paths, "test BVH files or folders (default: the standard split's held-out takes)");
  app.add_flag("--dev-split", development,
               "the development split (tests = takes ≡ 5 mod 10, database without takes ≡ 3 or 5): tune here, "
               "report on the standard split");
  app.add_flag("--quick", quick, "one held-out clip per content type, 120 frames each; fails on regression");
  app.add_flag(
      "--ablations", ablations,
      "also run window L ∈ {10,50,100}, noise σ ∈ {0,1,2} cm, lag D ∈ {0,5,15,30}, the full method on the "
      "captured frames alone (full_captured_only: without the travelling frames played backwards), with A5's "
      "K2 examples weighed alike (full_neighbours_alike, lag_5_neighbours_alike), "
      "without the torso's lean towards input beyond an arm's reach (full_no_reach_lean), the lean without the "
      "collar bones turning first (full_no_collars), without the body's shift "
      "towards it (full_no_reach_shift), with the shift over the ground only (full_horizontal_shift), "
      "twice as fast (full_shift_speed_0.5), with ankles left under the floor (full_feet_under_floor), the trunk too "
      "(A6 without its floor term: full_body_under_floor, lag_5_body_under_floor), with the "
      "torso's turn unsmoothed (full_unsmoothed_lean), with the joint filter not widened for a jittering body "
      "(full_jittery_body), with the whole clip's joint filter a Gaussian (full_gaussian_joint_filter), with A6's "
      "prior at its configured weight in a session unlike the database too (full_no_unfamiliar_prior, "
      "lag_5_no_unfamiliar_prior) and, at lag 0 and 5, with the ankle filter repeating the path's newest frame "
      "(lag_0_clamped_ankle_edges, lag_5_clamped_ankle_edges), with A6 given the decided ankles unplanted "
      "(lag_0_unplanted_ankles, lag_5_unplanted_ankles), with a contact that resumes during its release "
      "pinned where the solve put the ankle (lag_0_resumed_at_solve, lag_5_resumed_at_solve), with a planted "
      "foot held by the hands' midpoint standing alone, not by either hand (lag_0_midpoint_stands, "
      "lag_5_midpoint_stands) or with the joint filter repeating the newest frame for the pelvis too, as before "
      "stop 86 (lag_0_clamped_pelvis, lag_5_clamped_pelvis); and with the A4 "
      "ankle path's filter of σ = 2 frames, as before stop 79 (full_ankle_sigma_2)");
  bool cross_dataset = false, landmarks = false, devices = false, size_oracle = false;
  app.add_flag("--cross-dataset", cross_dataset,
               "the cross-dataset protocol of shared/data/README: database = all of bandai-namco-2; tests = "
               "bandai-namco-1, cmu-cc and the moving other-rigs clips, scored on body landmarks");
  app.add_flag("--landmarks", landmarks,
               "score the --test clips on body landmarks (automatic when a clip's rig is not the database's)");
  app.add_flag("--devices", devices,
               "landmark tests: also run the full method and the nearest neighbour on device-like input (VR "
               "controllers, a 90 Hz tracker, phone AR, dropouts; eval/device_input.h)");
  app.add_flag("--size-oracle", size_oracle,
               "landmark tests: also run the full method at the performer's own size, taken from the capture "
               "(an oracle: how much of the error body size explains), three estimates of it from the wrists, and "
               "a height declared as the service takes it (performer_height, with a 3% error)");
  app.add_flag("--generalisation", generalisation,
               "also test bandai-namco-1 walk/walk-back/walk-left/walk-right/run/dash clips");
  app.add_option(
         "--test-body-scale", test_body_scale,
         "test takes on the database's rig: every performer this much larger (bones and root path, the "
         "rotations kept; scored on landmarks: every landmark's position): people of other sizes on the standard or "
         "development split")
      ->check(CLI::Range(0.5f, 2.0f));
  app.add_option("--noise-cm", noise_cm, "wrist noise σ in cm (docs/method.md A8: 0.5)");
  app.add_option("--seed", seed, "noise seed");
  app.add_option("--max-frames", max_frames, "cut test clips to this many frames (0 = whole)");
  app.add_option("--max-clips", max_clips, "use at most this many test clips (0 = all)");
  app.add_option("--threads", threads, "clips reconstructed at once (each single-threaded)");
  app.add_option("--k1", base.ankle_candidates, "A3 ankle candidates K1");
  app.add_option("--k2", base.pose_neighbours, "A5 pose neighbours K2");
  mocap::DatabaseBuildOptions database_options;
  std::vector<float> ankle_scales;
  app.add_option("--eq8-ankle-scales", ankle_scales,
                 "A5 eq. 8: the ankle positions' and velocities' scales against the wrists' (default 2 0.5; 1 1: the "
                 "patent's)")
      ->expected(2);
  app.add_option("--pose-kernel", base.pose_neighbour_kernel,
                 "A5: weigh the K2 examples by a Gaussian kernel of this × the median neighbour's squared distance "
                 "(0: alike)")
      ->capture_default_str();
  app.add_option("--window", base.window, "A4 window L for the full run (0 = whole clip)");
  std::string contacts = "both";
  app.add_option(
         "--contacts", contacts,
         "A7 foot contacts from the chosen database frame, the estimated ankles, or both (planted where both say so)")
      ->check(CLI::IsMember({"database", "estimated", "both"}))
      ->capture_default_str();
  app.add_option("--contact-speed", base.footskate.contact_speed, "A7 planted below this ground speed, m/s")
      ->capture_default_str();
  app.add_option("--joint-smoothing", base.joint_smoothing_sigma, "A7 joint-space filter σ, frames")
      ->capture_default_str();
  app.add_option("--hand-sigma", base.hand_target_sigma,
                 "hand IK target: input smoothed by a centred Gaussian of this σ (frames); < 0: no hand IK")
      ->capture_default_str();
  app.add_option("--ankle-data-weight", base.ankle_path.data_weight, "A4 node cost weight on the eq. 2 wrist distance")
      ->capture_default_str();
  app.add_option("--components", base.pose_components, "A5 PCA components D'")->capture_default_str();
  app.add_option("--prior-weight", base.solver.prior_weight, "A6 E_prior weight")->capture_default_str();
  app.add_option("--unfamiliar-prior-max", base.unfamiliar_prior.max_factor,
                 "A6: the largest factor on the prior weight in a session unlike the database; 1: off")
      ->capture_default_str();
  app.add_option("--unfamiliar-prior-from", base.unfamiliar_prior.from_log_cost,
                 "A6: the session mean log energy where the prior weight starts to rise")
      ->capture_default_str();
  app.add_option("--unfamiliar-prior-to", base.unfamiliar_prior.to_log_cost,
                 "A6: the session mean log energy where the prior weight reaches its largest factor")
      ->capture_default_str();
  app.add_option("--control-weight", base.solver.control_weight, "A6 E_ctrl weight")->capture_default_str();
  app.add_option("--smooth-weight", base.solver.smooth_weight, "A6 E_smooth weight")->capture_default_str();
  app.add_option("--wrist-sigma", base.smoothing.local_linear_sigma,
                 "A2 as a local linear fit over a Gaussian window of this σ (frames); 0: the patent's exponential")
      ->capture_default_str();
  app.add_option("--lookahead", base.smoothing.lookahead, "A2 local linear fit: frames of look-ahead")
      ->capture_default_str();
  app.add_option("--smoothing", base.smoothing.smoothing, "A2 exponential smoothing s (1 = none)")
      ->capture_default_str();
  app.add_option("--max-gap", base.max_gap_seconds, "input dropouts longer than this (s) end the segment")
      ->capture_default_str();
  bool no_motion_guard = false;
  app.add_flag("--no-motion-guard", no_motion_guard,
               "do not bound the output pelvis by the database's speed and acceleration (issue #22)");
  std::vector<std::string> only_runs;
  app.add_option("--runs", only_runs,
                 "only these runs (full, nearest_neighbour, nearest_average, wrists_only, ...; any of them as "
                 "RUN@DEVICE with --devices); a name that is no run is an error");
  app.add_flag("--no-bvh", no_bvh, "do not write the reconstructions as BVH");
  std::string confidence_samples;
  app.add_option("--confidence-samples", confidence_samples,
                 "write the full run's (predicted, actual) landmark errors and their cues to this CSV, one line per "
                 "frame and landmark (fitting the confidence calibration: docs/method.md \"Confidence\"); with "
                 "--devices each device run's to FILE's stem.RUN.csv beside it");
  app.add_option("--thresholds", thresholds_file,
                 "regression thresholds for --quick (JSON; default: the built-in ones)");
  app.add_option("--shared-data", shared_data,
                 "the shared data folder (its unpack.sh; default: $MOCAP_SHARED_DATA_DIR, else ../shared/data)");
  CLI11_PARSE(app, argc, argv);
  if (no_motion_guard) base.motion_guard.enabled = false;
  if (ankle_scales.size() == 2) {
    database_options.pose_query.ankle_position_scale = ankle_scales[0];
    database_options.pose_query.ankle_velocity_scale = ankle_scales[1];
  }
  base.footskate.contact_source = contacts == "database"    ? mocap::ContactSource::kDatabaseFrame
                                  : contacts == "estimated" ? mocap::ContactSource::kEstimatedAnkles
                                                            : mocap::ContactSource::kBoth;

  mocap::datasets::DataLocation data = mocap::datasets::DataLocationFromEnvironment();
  if (!shared_data.empty()) data.shared_dir = shared_data;
  nlohmann::json context;
  std::vector<std::filesystem::path> database_files, test_files;
  if (cross_dataset) {
    std::string why;
    auto folder = mocap::datasets::UnpackedSet(data, "bandai-namco-2", &why);
    if (!folder) {
      std::cerr << "mocap-eval: --cross-dataset needs bandai-namco-2: " << why << "\n";
      return kExitNoData;
    }
    if (database_dirs.empty()) database_dirs.push_back(folder->string());
    if (!CollectInto(database_dirs, &database_files)) return kExitError;
    context["database"] = database_dirs.size() == 1 && database_dirs[0] == folder->string()
                              ? std::string("all of bandai-namco-2 (cross-dataset protocol)")
                              : database_dirs[0];
    context["test_set"] = "every bandai-namco-1 and cmu-cc clip, the other-rigs clips that move";
  } else if (database_dirs.empty()) {
    auto split = development ? mocap::eval::LoadDevelopmentSplit(data) : mocap::eval::LoadStandardSplit(data);
    if (!split.ok()) {
      std::cerr << "mocap-eval: " << split.status().message() << "\n";
      return kExitNoData;
    }
    database_files = split->database_files;
    if (test_paths.empty()) {
      test_files = split->test_files;
    } else if (!CollectInto(test_paths, &test_files)) {
      return kExitError;
    }
    context["database"] = development ? "bandai-namco-2 takes not ≡ 3 or 5 (mod 10) (development split)"
                                      : "bandai-namco-2 takes not ≡ 3 (mod 10) (standard split)";
    context["test_set"] = !test_paths.empty() ? "named on the command line"
                          : development       ? "bandai-namco-2 takes ≡ 5 (mod 10)"
                                              : "bandai-namco-2 takes ≡ 3 (mod 10)";
  } else {
    if (test_paths.empty()) {
      std::cerr << "mocap-eval: --database-dir needs --test (the clips to reconstruct)\n";
      return kExitError;
    }
    if (!CollectInto(database_dirs, &database_files) || !CollectInto(test_paths, &test_files)) return kExitError;
    std::string folders;
    for (const std::string& d : database_dirs) folders += (folders.empty() ? "" : ", ") + d;
    context["database"] = folders;  // one string: the report prints it
    context["test_set"] = "named on the command line";
  }
  if (quick && !cross_dataset) {
    test_files = QuickSubset(test_files);
    if (max_frames == 0) max_frames = 120;
  }
  if (max_clips > 0 && static_cast<int>(test_files.size()) > max_clips) test_files.resize(max_clips);
  if (test_files.empty() && !cross_dataset) {
    std::cerr << "mocap-eval: no test clips\n";
    return kExitError;
  }
  std::cerr << "loading the database (" << database_files.size() << " files)...\n";
  auto databases = mocap::eval::LoadDatabases(database_files, database_options);
  if (!databases.ok()) {
    std::cerr << "mocap-eval: database: " << databases.status().message() << "\n";
    return kExitError;
  }
  const std::shared_ptr<const mocap::ReconstructionDatabase>& database = databases->method;
  auto make_experiments = [&] {
    auto experiments = mocap::eval::MakeExperiments(base, noise_cm, ablations);
    std::erase_if(experiments, [&](const mocap::eval::Experiment& e) {
      if (!only_runs.empty()) return std::find(only_runs.begin(), only_runs.end(), e.name) == only_runs.end();
      return (cross_dataset || landmarks) && e.name == "wrists_only";  // landmarks: the method and the lookups
    });
    return experiments;
  };
  auto add_limits = [&] {
    const mocap::MotionLimits& limits = database->motion_limits();
    context["database_frames"] = database->num_frames();
    context["database_pelvis_speed_max_m_per_s"] = limits.pelvis_speed_max;
    context["database_ankle_speed_max_m_per_s"] = limits.ankle_speed_max;
    context["database_ankle_speed_by_hands_speed_m_per_s"] = limits.ankle_speed_by_hands_speed[0];
    context["database_pelvis_speed_beyond_hands_max_m_per_s"] = limits.pelvis_speed_beyond_hands_max;
    context["database_pelvis_speed_by_hands_speed_m_per_s"] = limits.pelvis_speed_by_hands_speed[0];
    context["database_pelvis_speed_by_long_hands_speed_m_per_s"] = limits.pelvis_speed_by_hands_speed[1];
    context["database_pelvis_speed_while_hands_stand_m_per_s"] = limits.pelvis_speed_while_hands_stand;
    context["seed"] = seed;
    context["noise_cm"] = noise_cm;
    const mocap::eval::LandmarkBodySize size = mocap::eval::BodySizeOf(*database);
    context["database_leg_m"] = size.leg;
    context["database_arm_m"] = size.arm;
  };
  bool by_landmarks = landmarks || cross_dataset;
  absl::StatusOr<std::vector<mocap::eval::TestClip>> tests = std::vector<mocap::eval::TestClip>{};
  if (!by_landmarks) {
    tests = mocap::eval::LoadTestClips(test_files, database->rig(), max_frames, "", test_body_scale);
    by_landmarks = tests.status().code() == absl::StatusCode::kFailedPrecondition;  // a clip on another rig
  }
  if (by_landmarks) {  // every test clip is scored on its body landmarks
    auto landmark_tests = cross_dataset ? mocap::eval::LoadCrossDatasetTests(data, max_frames)
                                        : mocap::eval::LoadLandmarkTests(test_files, max_frames, test_body_scale);
    if (!landmark_tests.ok()) {
      std::cerr << "mocap-eval: test clips: " << landmark_tests.status().message() << "\n";
      return landmark_tests.status().code() == absl::StatusCode::kNotFound ? kExitNoData : kExitError;
    }
    if (!cross_dataset) context["test_set"] = "named on the command line, scored on landmarks";
    add_limits();
    std::vector<mocap::eval::Experiment> experiments = make_experiments();
    if (devices) {
      for (auto& e : mocap::eval::MakeDeviceExperiments(base, !only_runs.empty())) {
        if (only_runs.empty() || std::find(only_runs.begin(), only_runs.end(), e.name) != only_runs.end())
          experiments.push_back(std::move(e));
      }
    }
    if (size_oracle) {
      mocap::eval::Experiment sized = mocap::eval::MakeExperiments(base, noise_cm, false).front();  // full
      for (auto [name, size] : {std::pair{"full_size_oracle", mocap::eval::PerformerSize::kTruth},
                                {"full_size_lower_wrist", mocap::eval::PerformerSize::kLowerWrist},
                                {"full_size_walking_wrists", mocap::eval::PerformerSize::kWalkingWrists},
                                {"full_size_database_fit", mocap::eval::PerformerSize::kDatabaseFit},
                                {"full_declared_height", mocap::eval::PerformerSize::kDeclared},
                                {"full_database_size", mocap::eval::PerformerSize::kDatabase}}) {
        sized.name = name;
        sized.size = size;
        if (only_runs.empty() || std::find(only_runs.begin(), only_runs.end(), name) != only_runs.end())
          experiments.push_back(sized);
      }
    }
    if (!KnowsEveryRun(only_runs, experiments)) return kExitError;
    return RunLandmarkTests(*databases, *landmark_tests, experiments, context, out_dir, seed, threads,
                            confidence_samples);
  }
  if (!tests.ok()) {
    std::cerr << "mocap-eval: test clips: " << tests.status().message() << "\n";
    return kExitError;
  }
  if (generalisation) {
    std::string why;
    auto folder = mocap::datasets::UnpackedSet(data, "bandai-namco-1", &why);
    if (!folder) {
      std::cerr << "mocap-eval: --generalisation needs bandai-namco-1: " << why << "\n";
      return kExitNoData;
    }
    std::vector<std::filesystem::path> extra;
    for (const auto& f : mocap::datasets::BvhFilesIn(*folder)) {
      const std::string c = mocap::LabelValue(mocap::ParseClipLabels(f.filename().string()), "content");
      if (c == "walk" || c == "walk-back" || c == "walk-left" || c == "walk-right" || c == "run" || c == "dash")
        extra.push_back(f);
    }
    auto more = mocap::eval::LoadTestClips(extra, database->rig(), max_frames, "bn1:");
    if (!more.ok()) {
      std::cerr << "mocap-eval: bandai-namco-1: " << more.status().message() << "\n";
      return kExitError;
    }
    for (auto& t : *more) tests->push_back(std::move(t));
  }
  context["database_frames"] = database->num_frames();
  const mocap::MotionLimits& motion_limits = database->motion_limits();
  context["database_pelvis_speed_max_m_per_s"] = motion_limits.pelvis_speed_max;
  context["database_ankle_speed_max_m_per_s"] = motion_limits.ankle_speed_max;
  context["database_ankle_speed_by_hands_speed_m_per_s"] = motion_limits.ankle_speed_by_hands_speed[0];
  context["database_pelvis_speed_p99_m_per_s"] = motion_limits.pelvis_speed_p99;
  context["database_pelvis_acceleration_max_m_per_s2"] = motion_limits.pelvis_acceleration_max;
  context["database_pelvis_speed_beyond_hands_max_m_per_s"] = motion_limits.pelvis_speed_beyond_hands_max;
  context["database_pelvis_speed_by_hands_speed_m_per_s"] = motion_limits.pelvis_speed_by_hands_speed[0];
  context["database_pelvis_speed_by_long_hands_speed_m_per_s"] = motion_limits.pelvis_speed_by_hands_speed[1];
  context["database_wrist_speed_max_m_per_s"] = motion_limits.wrist_speed_max;
  context["database_wrist_acceleration_max_m_per_s2"] = motion_limits.wrist_acceleration_max;
  context["test_clips"] = tests->size();
  // Scored at the database's size (same rig, joint angles): how many test clips the service would
  // have sized larger by their reach (wrist_reach.h) had they come as a whole trajectory.
  context["test_clips_sized_by_reach"] = mocap::eval::ClipsSizedByReach(*database, *tests);
  std::cerr << context["test_clips_sized_by_reach"] << " of " << tests->size()
            << " test clips reach beyond the database's bodies (scored at the database's size)\n";
  context["seed"] = seed;
  context["noise_cm"] = noise_cm;
  context["k1"] = base.ankle_candidates;
  context["k2"] = base.pose_neighbours;
  context["pose_neighbour_kernel"] = base.pose_neighbour_kernel;
  context["eq8_ankle_scales"] = {database_options.pose_query.ankle_position_scale,
                                 database_options.pose_query.ankle_velocity_scale};
  context["quick"] = quick;
  auto experiments = make_experiments();
  if (!KnowsEveryRun(only_runs, experiments)) return kExitError;
  mocap::eval::EvaluationConfig config{.seed = seed,
                                       .threads = threads,
                                       .bvh_dir = no_bvh ? "" : std::filesystem::path(out_dir) / "bvh",
                                       .confidence_samples = confidence_samples};
  std::cerr << "reconstructing " << tests->size() << " clips with " << experiments.size() << " runs...\n";
  auto results = mocap::eval::RunEvaluation(*databases, *tests, experiments, config,
                                            [](const std::string& line) { std::cerr << "  " << line << "\n"; });
  if (!results.ok()) {
    std::cerr << "mocap-eval: " << results.status().message() << "\n";
    return kExitError;
  }
  if (absl::Status status = mocap::eval::WriteReport(out_dir, context, *results); !status.ok()) {
    std::cerr << "mocap-eval: " << status.message() << "\n";
    return kExitError;
  }
  std::cout << "wrote " << out_dir << "/report.html, report.md, report.json, plots/" << (no_bvh ? "" : ", bvh/")
            << "\n";
  if (!quick) return 0;
  // Regression check against stored thresholds.
  std::string thresholds(mocap::eval::kQuickThresholdsJson);
  if (!thresholds_file.empty()) {
    std::ifstream in(thresholds_file);
    if (!in) {
      std::cerr << "mocap-eval: cannot read thresholds " << thresholds_file << "\n";
      return kExitError;
    }
    thresholds.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  const nlohmann::json limits = nlohmann::json::parse(thresholds, nullptr, false);
  if (limits.is_discarded()) {
    std::cerr << "mocap-eval: thresholds are not JSON\n";
    return kExitError;
  }
  const nlohmann::json full = mocap::eval::MetricsJson(results->front().overall);
  const nlohmann::json nn = mocap::eval::MetricsJson((*results)[1].overall);
  bool ok = true;
  auto check = [&](const char* what, double value, double limit) {
    const bool pass = value <= limit;
    std::cout << (pass ? "ok   " : "FAIL ") << what << " = " << value << " (limit " << limit << ")\n";
    ok = ok && pass;
  };
  check("full MPJPE cm", full["mpjpe_cm"], limits.value("full_mpjpe_cm_max", 1e9));
  check("full / nearest-neighbour MPJPE", full["mpjpe_cm"].get<double>() / nn["mpjpe_cm"].get<double>(),
        limits.value("full_over_nn_mpjpe_max", 1e9));
  check("full jitter / truth jitter",
        full["jitter_m_per_s3"].get<double>() / full["truth_jitter_m_per_s3"].get<double>(),
        limits.value("jitter_over_truth_max", 1e9));
  return ok ? 0 : kExitRegression;
}

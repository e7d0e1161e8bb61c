#include "client/cli/reconstruct_command.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <optional>
#include <thread>

#include "client/cli/body_size_note.h"
#include "client/cli/input_frame_flags.h"
#include "client/cli/output_paths.h"
#include "client/cli/reconstruction_bvh.h"
#include "client/cli/reconstruction_json.h"
#include "client/cli/reconstruction_timeline.h"
#include "client/cli/refusal_summary.h"
#include "client/cli/target_rig_file.h"
#include "client/wrist_input/wrist_source.h"
#include "motion/core/str_cat.h"
#include "motion/reconstruct/plausibility.h"
#include "motion/skeleton/forward_kinematics.h"
#include "proto/convert/method_overrides.h"
#include "tools/command_line/progress_bar.h"

namespace mocap::cli {
namespace {

struct ReconstructOptions {
  std::string database;
  std::string csv, bvh;
  double noise_cm = 0.0;
  unsigned seed = 1;
  std::string method = "full";
  std::string foot_contacts = "both";
  int window = -1, lag = -1;
  // Tunables asked for by flag (proto/convert/method_overrides.h), in the order given.
  std::vector<std::pair<const MethodTunable*, double>> tunables;
  float performer_height = 0.0f;
  bool estimate_height = true;  // the whole trajectory, no height declared, no target rig: by reach
  float min_confidence = 0.0f;
  bool diagnostics = false, strict = false, unary = false, realtime = false, quiet = false, recenter = false;
  int samples_per_message = 30;
  std::string output = "reconstruction";
  InputFrameFlags input_frame;
  std::string target_rig;  // issue #12: an avatar's BVH to answer on
  std::string target_rig_text;
};

absl::StatusOr<v1::SessionConfig> Config(const ReconstructOptions& o) {
  v1::SessionConfig config;
  config.set_database(o.database);
  if (o.method == "full") {
    config.set_method(v1::RECONSTRUCTION_METHOD_FULL);
  } else if (o.method == "wrists-only") {
    config.set_method(v1::RECONSTRUCTION_METHOD_WRISTS_ONLY);
  } else {
    config.set_method(v1::RECONSTRUCTION_METHOD_NEAREST_NEIGHBOUR);
  }
  if (o.lag >= 0) config.mutable_fixed_lag()->set_lag_frames(o.lag);
  if (o.window >= 0) config.mutable_sub_interval()->set_window_frames(o.window);
  for (const auto& [tunable, value] : o.tunables) SetMethodOverride(*tunable, value, config.mutable_overrides());
  config.mutable_overrides()->set_foot_contacts(o.foot_contacts == "database"    ? v1::FOOT_CONTACTS_DATABASE_FRAME
                                                : o.foot_contacts == "estimated" ? v1::FOOT_CONTACTS_ESTIMATED_ANKLES
                                                                                 : v1::FOOT_CONTACTS_BOTH);
  config.set_performer_height(o.performer_height);
  // The body sized by the wrists' reach: once for the whole input, as it streams in otherwise.
  config.set_estimate_performer_height(o.estimate_height && o.performer_height == 0.0f && o.target_rig_text.empty());
  config.set_include_diagnostics(o.diagnostics);
  config.set_strict(o.strict);
  config.set_min_confidence(o.min_confidence);
  config.set_client_label("mocap reconstruct");
  if (!o.target_rig_text.empty()) config.mutable_target_rig()->set_bvh(o.target_rig_text);
  return config;
}

// Streams the samples (a reader thread collects replies meanwhile, so neither side waits on the
// other's flow control) and gathers everything into one response-shaped message.
absl::StatusOr<v1::ReconstructTrajectoryResponse> Stream(client::Client& client, const v1::SessionConfig& config,
                                                         const std::vector<v1::WristSample>& samples,
                                                         const ReconstructOptions& o, bool show_progress) {
  auto stream = client.OpenReconstruction(config);
  if (!stream.ok()) return stream.status();
  v1::ReconstructTrajectoryResponse result;
  *result.mutable_started() = (*stream)->started();
  ProgressBar bar("reconstructing", static_cast<long>(samples.size()), show_progress);
  std::atomic<long> frames_back{0};
  std::thread reader([&] {
    while (true) {
      absl::StatusOr<std::optional<v1::ReconstructResponse>> reply = (*stream)->Read();
      if (!reply.ok() || !*reply) break;
      if ((*reply)->has_frames()) {  // (mutable_frames() would switch the reply's oneof to frames)
        for (v1::Frame& frame : *(*reply)->mutable_frames()->mutable_frames())
          result.mutable_frames()->Add(std::move(frame));
      }
      if ((*reply)->frames().has_skeleton())  // the body sized at the end of the input
        *result.mutable_started()->mutable_skeleton() = (*reply)->frames().skeleton();
      if ((*reply)->has_rejected()) *result.add_rejected() = (*reply)->rejected();
      if ((*reply)->has_input_report()) {  // one report, as the unary call answers
        const v1::InputReport& report = (*reply)->input_report();
        result.mutable_input_report()->set_floor_height(report.floor_height());
        result.mutable_input_report()->set_floor_calibrated(report.floor_calibrated());
        for (const v1::InputWarning& warning : report.warnings())
          *result.mutable_input_report()->add_warnings() = warning;
      }
      frames_back = result.frames_size();
    }
  });
  const auto start = std::chrono::steady_clock::now();
  const int per_message = std::max(1, o.samples_per_message);
  for (size_t i = 0; i < samples.size(); i += per_message) {
    const size_t end = std::min(samples.size(), i + per_message);
    if (o.realtime) {
      const double offset = samples[end - 1].time() - samples.front().time();
      std::this_thread::sleep_until(start + std::chrono::duration<double>(offset));
    }
    if (!(*stream)->Write({samples.begin() + static_cast<long>(i), samples.begin() + static_cast<long>(end)}).ok())
      break;
    bar.Update(static_cast<long>(end), std::to_string(frames_back.load()) + " frames back");
  }
  (*stream)->CloseInput().IgnoreError();  // always OK
  reader.join();
  bar.Finish();
  // The call's status decides (a failed write only means the call had ended).
  absl::StatusOr<v1::SessionSummary> summary = (*stream)->Finish();
  if (!summary.ok()) return summary.status();
  *result.mutable_summary() = *summary;
  return result;
}

// Issue #22: how plausible the body that came back is, without truth — the motion library's
// measures (motion/reconstruct/plausibility.h) on the frames as received (metres, Y up). The
// client does not know the database's ground, so a planted ankle's height is taken the way the
// database takes it: the 10th percentile of the lower ankle's height, here over the output.
struct Plausibility {
  PlausibilityStats stats;
  float input_speed_max = 0;  // m/s, the input wrists' midpoint (the smoothed wrists the frames were given)
  // The server's tracking states, per hand and frame.
  long predicted_hand_frames = 0, lost_hand_frames = 0, put_down_hand_frames = 0;
};

std::optional<Plausibility> PlausibilityOf(const v1::SessionStarted& started, const std::vector<v1::Frame>& frames) {
  const v1::Skeleton& rig = started.skeleton();
  std::vector<Joint> joints;
  for (const v1::Joint& joint : rig.joints())
    joints.push_back({joint.name(), joint.parent(), {joint.offset().x(), joint.offset().y(), joint.offset().z()}});
  const Skeleton skeleton(std::move(joints));
  const v1::BodyLandmarks& l = rig.landmarks();
  BodyLandmarks landmarks;
  landmarks.pelvis = l.pelvis();
  landmarks.left_wrist = l.left_wrist();
  landmarks.right_wrist = l.right_wrist();
  landmarks.left_ankle = l.left_ankle();
  landmarks.right_ankle = l.right_ankle();
  const int count = skeleton.num_joints();
  for (int j :
       {landmarks.pelvis, landmarks.left_wrist, landmarks.right_wrist, landmarks.left_ankle, landmarks.right_ankle}) {
    if (j < 0 || j >= count) return std::nullopt;
  }
  if (frames.empty() || !skeleton.Validate().ok()) return std::nullopt;
  LocalMotion motion;
  motion.Resize(static_cast<int>(frames.size()), count);
  for (int f = 0; f < static_cast<int>(frames.size()); ++f) {
    if (frames[f].rotations_size() != count) return std::nullopt;
    for (int j = 0; j < count; ++j) {
      const v1::Quaternion& q = frames[f].rotations(j);
      const v1::Vec3& root = frames[f].root_position();
      motion.SetRotation(f, j, Eigen::Quaternionf(q.w(), q.x(), q.y(), q.z()).normalized());
      motion.SetTranslation(f, j,
                            j == 0 ? Eigen::Vector3f(root.x(), root.y(), root.z())
                                   : BodyScale(frames[f]) * skeleton.joint(j).offset);  // as the body grew
    }
  }
  const GlobalPoses poses = ForwardKinematics(skeleton, motion);
  const PlausibilityRig plausibility_rig = MakePlausibilityRig(skeleton, landmarks);
  auto vec = [](const v1::Vec3& v) { return Eigen::Vector3f(v.x(), v.y(), v.z()); };
  std::vector<PlausibilityFrame> measured;
  std::vector<float> lower_ankle;
  std::vector<Eigen::Vector3f> positions(count);
  Plausibility result;
  for (int f = 0; f < static_cast<int>(frames.size()); ++f) {
    const v1::Frame& frame = frames[f];
    for (int j = 0; j < count; ++j) positions[j] = poses.position(f, j);
    const bool implausible = frame.left_hand_state() == v1::TRACKING_STATE_IMPLAUSIBLE ||
                             frame.right_hand_state() == v1::TRACKING_STATE_IMPLAUSIBLE;
    for (v1::TrackingState state : {frame.left_hand_state(), frame.right_hand_state()}) {
      result.predicted_hand_frames += state == v1::TRACKING_STATE_PREDICTED;
      result.put_down_hand_frames += state == v1::TRACKING_STATE_PUT_DOWN;
      result.lost_hand_frames += state == v1::TRACKING_STATE_LOST;
    }
    measured.push_back(MakePlausibilityFrame(plausibility_rig, positions,
                                             {vec(frame.left_wrist()), vec(frame.right_wrist())}, frame.time(),
                                             frame.segment(), implausible, frame.motion_limited()));
    lower_ankle.push_back(std::min(measured.back().ankles[0].y(), measured.back().ankles[1].y()));
    if (f > 0 && frames[f - 1].segment() == frame.segment() && frame.time() > frames[f - 1].time()) {
      const Eigen::Vector3f step = 0.5f * (vec(frame.left_wrist()) + vec(frame.right_wrist()) -
                                           vec(frames[f - 1].left_wrist()) - vec(frames[f - 1].right_wrist()));
      result.input_speed_max =
          std::max(result.input_speed_max, static_cast<float>(step.norm() / (frame.time() - frames[f - 1].time())));
    }
  }
  const size_t tenth = lower_ankle.size() / 10;
  std::nth_element(lower_ankle.begin(), lower_ankle.begin() + static_cast<long>(tenth), lower_ankle.end());
  result.stats = MeasurePlausibility(measured, lower_ankle[tenth], 0.0f);
  return result;
}

// The mean expected error of each body landmark over the frames that carry one (docs/method.md
// "Confidence"), metres, in the message's field order; nothing from a server before them.
std::optional<std::vector<std::pair<std::string, double>>> MeanExpectedErrors(const std::vector<v1::Frame>& frames) {
  const google::protobuf::Descriptor* descriptor = v1::LandmarkErrors::descriptor();
  const google::protobuf::Reflection* reflection = v1::LandmarkErrors::GetReflection();
  std::vector<std::pair<std::string, double>> means;
  for (int k = 0; k < descriptor->field_count(); ++k) means.emplace_back(descriptor->field(k)->name(), 0.0);
  long counted = 0;
  for (const v1::Frame& frame : frames) {
    if (!frame.has_expected_error()) continue;
    ++counted;
    for (int k = 0; k < descriptor->field_count(); ++k)
      means[k].second += reflection->GetFloat(frame.expected_error(), descriptor->field(k));
  }
  if (counted == 0) return std::nullopt;
  for (auto& [name, mean] : means) mean /= static_cast<double>(counted);
  return means;
}

absl::Status WriteFile(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) return absl::DataLossError("cannot write " + path.string());
  return absl::OkStatus();
}

int Run(client::Client& client, ReconstructOptions o, const GlobalOptions& global) {
  if (!o.target_rig.empty()) {
    // The server's BVH limit, less room for the rest of the config.
    absl::StatusOr<std::string> text = TargetRigText(o.target_rig, (1 << 20) - 4096);
    if (!text.ok()) return ReportError(text.status());
    o.target_rig_text = std::move(*text);
  }
  absl::StatusOr<std::vector<v1::WristSample>> samples =
      o.csv.empty() ? WristsFromBvh(o.bvh, o.noise_cm, o.seed) : WristsFromCsv(o.csv);
  if (!samples.ok()) return ReportError(samples.status());
  absl::StatusOr<DeclaredInputFrame> input_frame = ResolveInputFrame(o.input_frame);
  if (!input_frame.ok()) return ReportError(input_frame.status());
  if (!o.bvh.empty()) {  // the clip's wrists as a tracker in the declared frame would send them
    if (absl::Status s = ToDeclaredFrame(input_frame->frame, &*samples); !s.ok()) return ReportError(s);
  }
  if (o.recenter) RecenterHorizontally(&*samples, UpAxisIndex(input_frame->frame.convention.up));
  absl::StatusOr<v1::SessionConfig> config = Config(o);
  if (!config.ok()) return ReportError(config.status());
  *config->mutable_input_frame() = input_frame->proto;
  config->set_output_frame(v1::OUTPUT_FRAME_SERVER);  // BVH and JSON stay standard: metres, Y up, right-handed
  absl::StatusOr<v1::ReconstructTrajectoryResponse> result =
      o.unary ? client.ReconstructTrajectory(*config, *samples)
              : Stream(client, *config, *samples, o, !o.quiet && !global.json);
  if (!result.ok()) return ReportError(result.status());
  const std::vector<RefusalGroup> refusals = GroupRefusals(result->rejected());
  if (result->frames().empty()) {  // nothing half-made is written, and the run fails
    return ReportError(absl::InvalidArgumentError(NothingReconstructedMessage(refusals, samples->size())));
  }
  // The frames apart from the rest of the answer, moved, not copied (a target rig's are large).
  std::vector<v1::Frame> frames;
  frames.reserve(static_cast<size_t>(result->frames_size()));
  for (v1::Frame& frame : *result->mutable_frames()) frames.push_back(std::move(frame));
  result->clear_frames();
  // The BVH plays on the input's clock: a dropout too long to bridge is filled (the JSON keeps
  // only the frames the session made, each with its time and segment).
  const std::optional<FilledTimeline> timeline = FillDropouts(frames, result->started().frame_rate());
  const std::vector<v1::Frame>& bvh_frames = timeline ? timeline->frames : frames;
  absl::StatusOr<std::string> bvh = o.target_rig.empty()
                                        ? ReconstructionBvh(result->started(), bvh_frames)
                                        : RetargetedBvhText(o.target_rig_text, result->started(), bvh_frames);
  if (!bvh.ok()) return ReportError(bvh.status());
  const auto [bvh_path, json_path] = OutputPathsOf(o.output);
  if (absl::Status s = WriteFile(bvh_path, *bvh); !s.ok()) return ReportError(s);
  if (absl::Status s = WriteReconstructionJson(json_path, *result, frames); !s.ok()) return ReportError(s);
  const v1::SessionSummary& summary = result->summary();
  const std::optional<Plausibility> plausibility = PlausibilityOf(result->started(), frames);
  const auto expected_errors = MeanExpectedErrors(frames);
  if (global.json) {
    nlohmann::json out = nlohmann::json::parse(Json(summary));
    if (expected_errors) {
      for (const auto& [name, metres] : *expected_errors) out["mean_expected_error_cm"][name] = 100 * metres;
    }
    if (plausibility) {
      const PlausibilityStats& p = plausibility->stats;
      out["plausibility"] = {
          {"pelvis_speed_max_m_per_s", p.pelvis_speed.max()},
          {"pelvis_speed_p99_m_per_s", p.pelvis_speed.Quantile(0.99)},
          {"pelvis_acceleration_max_m_per_s2", p.pelvis_acceleration_max},
          {"ankle_speed_max_m_per_s", p.ankle_speed.max()},
          {"ankle_speed_p99_m_per_s", p.ankle_speed.Quantile(0.99)},
          {"input_wrists_speed_max_m_per_s", plausibility->input_speed_max},
          {"hand_to_input_p99_cm", 100 * p.hand_distance.Quantile(0.99)},
          {"hand_to_input_max_cm", 100 * p.hand_distance.max()},
          {"hand_frames_out_of_reach", p.hand_frames_out_of_reach},
          {"lower_foot_height_p99_cm", 100 * p.lower_foot_height.Quantile(0.99)},
          {"lower_foot_height_max_cm", 100 * p.lower_foot_height.max()},
          {"ground_penetration_max_cm", 100 * p.penetration_max},
          {"implausible_input_frames", p.flagged_frames},
          {"predicted_hand_frames", plausibility->predicted_hand_frames},
          {"put_down_hand_frames", plausibility->put_down_hand_frames},
          {"lost_hand_frames", plausibility->lost_hand_frames},
          {"motion_limited_frames", p.motion_limited_frames},
      };
    }
    out["bvh"] = bvh_path;
    out["bvh_filled_frames"] = timeline ? timeline->filled_frames : 0;
    out["bvh_filled_gaps"] = timeline ? timeline->gaps : 0;
    out["bvh_unfilled_gaps"] = timeline ? timeline->unfilled_gaps : 0;
    out["json"] = json_path;
    out["session_id"] = result->started().session_id();
    std::cout << out.dump(2) << "\n";
    return 0;
  }
  for (const v1::InputWarning& warning : result->input_report().warnings()) {
    std::cerr << "  input frame: " << warning.message() << "\n";
  }
  std::cerr << DescribeRefusals(refusals);
  std::cout << "session " << result->started().session_id() << ": " << summary.samples() << " samples → "
            << summary.frames() << " frames in " << summary.segments() << " segment(s)"
            << (summary.rejected_samples() ? ", " + std::to_string(summary.rejected_samples()) + " samples refused"
                                           : "")
            << (summary.repeated_hand_samples()
                    ? ", " + std::to_string(summary.repeated_hand_samples()) +
                          " hand-samples repeated the hand's last position (a tracker that did not update: "
                          "interpolated across)"
                    : "")
            << "\n  per frame: cloud " << summary.cloud_ms_per_frame() << " ms, ankle path "
            << summary.path_ms_per_frame() << " ms, pose " << summary.pose_ms_per_frame() << " ms, cleanup "
            << summary.cleanup_ms_per_frame() << " ms\n";
  std::cout << BodySizeNote(summary, result->started().database_height(),
                            o.performer_height > 0.0f || !o.target_rig_text.empty());
  if (plausibility) {
    const PlausibilityStats& p = plausibility->stats;
    std::cout << std::fixed << std::setprecision(2) << "  plausibility: pelvis at most " << p.pelvis_speed.max()
              << " m/s (99% ≤ " << p.pelvis_speed.Quantile(0.99) << "; input wrists at most "
              << plausibility->input_speed_max << " m/s), acceleration ≤ " << p.pelvis_acceleration_max
              << " m/s²; ankles at most " << p.ankle_speed.max() << " m/s; hands within "
              << 100 * p.hand_distance.Quantile(0.99) << " cm of the input in 99% of "
              << "frames (max " << 100 * p.hand_distance.max() << " cm"
              << (p.hand_frames_out_of_reach
                      ? ", " + std::to_string(p.hand_frames_out_of_reach) + " hand-frames out of reach"
                      : std::string())
              << "); lower foot ≤ " << 100 * p.lower_foot_height.Quantile(0.99) << " cm above the ground in 99% (max "
              << 100 * p.lower_foot_height.max() << "); under the floor ≤ " << 100 * p.penetration_max << " cm; "
              << p.flagged_frames << " frames with implausible input, " << p.motion_limited_frames
              << " frames where the body was held to a body's speed";
    if (plausibility->predicted_hand_frames || plausibility->put_down_hand_frames || plausibility->lost_hand_frames) {
      std::cout << "; hand-frames bridged over a dropout " << plausibility->predicted_hand_frames
                << ", with the device put down " << plausibility->put_down_hand_frames << ", lost "
                << plausibility->lost_hand_frames;
    }
    std::cout << "\n";
    std::cout.unsetf(std::ios::floatfield);
  }
  if (expected_errors) {
    // The groups a person reads: the pelvis, the head, then each pair's mean.
    std::cout << std::fixed << std::setprecision(1) << "  expected error (mean over frames, docs/method.md "
              << "\"Confidence\"): pelvis " << 100 * (*expected_errors)[0].second << " cm, head "
              << 100 * (*expected_errors)[1].second << " cm";
    for (size_t k = 2; k + 1 < expected_errors->size(); k += 2) {
      std::string group = (*expected_errors)[k].first.substr(std::string("left_").size()) + "s";
      std::cout << ", " << group << " " << 50 * ((*expected_errors)[k].second + (*expected_errors)[k + 1].second)
                << " cm";
    }
    std::cout << "\n";
    std::cout.unsetf(std::ios::floatfield);
  }
  if (timeline && timeline->gaps) {
    std::cout << "  the BVH plays on the input's clock: " << timeline->filled_frames << " frames across "
              << timeline->gaps << " dropout(s) too long to bridge are filled, moving from the frame before to "
              << "the frame after (" << json_path << " lists only the frames made)\n";
  }
  if (timeline && timeline->unfilled_gaps) {
    std::cout << "  " << timeline->unfilled_gaps << " gap(s) in the input over " << kLongestFilledGapSeconds
              << " s are not filled: in the BVH the motion after them comes early (" << json_path
              << " has every frame's time)\n";
  }
  std::cout << "  wrote " << bvh_path << " and " << json_path << "\n";
  return 0;
}

}  // namespace

void RegisterReconstruct(CLI::App& app, Registry& registry) {
  auto global = registry.global;
  auto o = std::make_shared<ReconstructOptions>();
  CLI::App* command = app.add_subcommand("reconstruct",
                                         "Reconstruct whole-body motion from wrist trajectories; "
                                         "writes OUTPUT.bvh and OUTPUT.json");
  command->add_option("--database", o->database, "Database to draw motion from")->required();
  auto* csv = command
                  ->add_option("--csv", o->csv,
                               "Wrist samples: time,left_x,left_y,left_z,right_x,right_y,right_z"
                               "[,left_confidence,right_confidence[,left_qw,...,right_qz]] (seconds; metres, Y up "
                               "unless --input-frame or --units, --up, --handedness, --floor say otherwise)")
                  ->check(CLI::ExistingFile);
  auto* bvh = command->add_option("--bvh", o->bvh, "Take the wrists from this BVH clip's forward kinematics")
                  ->check(CLI::ExistingFile);
  csv->excludes(bvh);
  command->add_option("--noise-cm", o->noise_cm, "With --bvh: Gaussian noise on the wrists, cm")
      ->check(CLI::NonNegativeNumber)
      ->needs(bvh);
  command->add_option("--seed", o->seed, "With --noise-cm: random seed")->capture_default_str();
  command->add_option("--method", o->method, "full, wrists-only or nearest")
      ->check(CLI::IsMember({"full", "wrists-only", "nearest"}))
      ->capture_default_str();
  auto* window = command->add_option("--window", o->window, "Sub-interval length L in frames (0: whole trajectory)")
                     ->check(CLI::NonNegativeNumber);
  auto* lag = command->add_option("--lag", o->lag, "Fixed lag D in frames (frame t-D leaves when t arrives)")
                  ->check(CLI::NonNegativeNumber);
  window->excludes(lag);
  // The method's tunables that have a flag, from the one table the server checks them by.
  const ReconstructionOptions defaults;
  for (const MethodTunable& tunable : MethodTunables()) {
    if (tunable.flag.empty()) continue;
    command
        ->add_option_function<double>(
            std::string(tunable.flag), [o, &tunable](double value) { o->tunables.emplace_back(&tunable, value); },
            StrCat(tunable.help, " (", tunable.min, "..", tunable.max, "; server default ", tunable.get(defaults), ")"))
        ->check(CLI::Range(tunable.min, tunable.max));
  }
  command
      ->add_option("--foot-contacts", o->foot_contacts,
                   "A7 foot contacts: both (planted where the estimated ankle and the chosen database frame say so), "
                   "estimated or database (least skating for the database's own performers, worse for others)")
      ->check(CLI::IsMember({"estimated", "database", "both"}))
      ->capture_default_str();
  command
      ->add_option("--performer-height", o->performer_height, "Performer's height in metres (scales input and output)")
      ->check(CLI::NonNegativeNumber);
  command->add_flag("!--no-estimate-height", o->estimate_height,
                    "Keep the database performer's size instead of sizing the body by how far the wrists reach "
                    "(done without --performer-height or --target-rig: once for a whole trajectory, as the input "
                    "streams in with --lag or --window)");
  AddInputFrameFlags(command, &o->input_frame);
  command
      ->add_option("--target-rig", o->target_rig,
                   "Answer on this avatar's rig (a BVH file: any joint names, count, proportions, unit, up axis); "
                   "OUTPUT.bvh is then written on that rig, in its own unit, axes and channels")
      ->check(CLI::ExistingFile);
  command
      ->add_option("--min-confidence", o->min_confidence,
                   "A hand whose CSV confidence is below this is lost: the body goes on from the other hand "
                   "(both below: a dropout); a confidence of 0 is always lost")
      ->check(CLI::Range(0.0f, 1.0f))
      ->capture_default_str();
  command->add_flag("--diagnostics", o->diagnostics, "Per-frame diagnostics in the JSON");
  command->add_flag("--strict", o->strict, "Fail at the first refused sample instead of skipping it");
  command->add_flag("--unary", o->unary, "One ReconstructTrajectory call instead of a stream");
  command->add_flag("--realtime", o->realtime, "Send samples at their timestamps' pace (as a live tracker would)");
  command->add_option("--samples-per-message", o->samples_per_message, "Samples per stream message")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  command->add_flag("--recenter", o->recenter,
                    "Move the samples so the first one's wrists are at the origin on the ground plane (height "
                    "kept): for positions in a game engine's world, kilometres from the origin");
  command
      ->add_option("-o,--output", o->output,
                   "Output path prefix: writes OUTPUT.bvh and OUTPUT.json (a trailing .bvh or .json is taken off)")
      ->capture_default_str();
  command->add_flag("--quiet", o->quiet, "No progress bar");
  command->callback([o, csv, bvh] {
    if (csv->count() == 0 && bvh->count() == 0) throw CLI::ValidationError("give --csv or --bvh");
  });
  registry.Add(command, [o, global](client::Client& client) { return Run(client, *o, *global); });
}

}  // namespace mocap::cli

#include "server/pose_search_convert.h"

#include <cmath>
#include <string_view>

#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"

namespace mocap {
namespace {

GroupWeights WeightsFromProto(const v1::GroupValues& values) {
  return {
      {{values.spine(), values.head(), values.left_arm(), values.right_arm(), values.left_leg(), values.right_leg()}}};
}

void GroupValuesToProto(const std::array<float, kNumBodyGroups>& values, v1::GroupValues* out) {
  out->set_spine(values[static_cast<int>(BodyGroup::kSpine)]);
  out->set_head(values[static_cast<int>(BodyGroup::kHead)]);
  out->set_left_arm(values[static_cast<int>(BodyGroup::kLeftArm)]);
  out->set_right_arm(values[static_cast<int>(BodyGroup::kRightArm)]);
  out->set_left_leg(values[static_cast<int>(BodyGroup::kLeftLeg)]);
  out->set_right_leg(values[static_cast<int>(BodyGroup::kRightLeg)]);
}

}  // namespace

absl::StatusOr<PoseSearchOptions> SearchOptionsFromProto(const v1::FindSimilarPosesRequest& request,
                                                         const PoseSearchLimits& limits) {
  if (request.databases().empty()) return absl::InvalidArgumentError("databases: name at least one database");
  if (request.databases_size() > limits.max_databases) {
    return absl::InvalidArgumentError(
        StrCat("databases: at most ", limits.max_databases, " per call, not ", request.databases_size()));
  }
  for (int i = 0; i < request.databases_size(); ++i) {
    if (request.databases(i).empty()) return absl::InvalidArgumentError("databases: a database name is empty");
    for (int j = 0; j < i; ++j) {
      if (request.databases(j) == request.databases(i)) {
        return absl::InvalidArgumentError(StrCat("databases: entries ", j, " and ", i, " name the same database"));
      }
    }
  }
  if (request.query_case() == v1::FindSimilarPosesRequest::QUERY_NOT_SET) {
    return absl::InvalidArgumentError("query: send `bvh` (frames of a BVH file) or `poses`");
  }
  PoseSearchOptions options;
  options.top_k = request.top_k() == 0 ? 10 : request.top_k();
  if (options.top_k < 1 || options.top_k > limits.max_top_k) {
    return absl::InvalidArgumentError(StrCat("top_k must be 1 to ", limits.max_top_k, ", not ", request.top_k()));
  }
  options.window = request.window() == 0 ? 1 : request.window();
  if (options.window < 1 || options.window > 61 || options.window % 2 == 0) {
    return absl::InvalidArgumentError(
        StrCat("window must be an odd number of frames from 1 to 61, not ", request.window()));
  }
  if (request.has_poses() && options.window != 1) {
    return absl::InvalidArgumentError("window: a pose is a single frame: use window 1");
  }
  if (request.has_weights()) {
    options.weights = WeightsFromProto(request.weights());
    float sum = 0;
    for (float w : options.weights.weight) {
      if (!std::isfinite(w) || w < 0 || w > 1e6f) return absl::InvalidArgumentError("weights must be finite, 0 to 1e6");
      sum += w;
    }
    if (sum <= 0) return absl::InvalidArgumentError("weights: at least one group must weigh more than 0");
  } else {
    switch (request.weights_preset()) {
      case v1::GROUP_WEIGHTS_PRESET_LOCOMOTION:
        options.weights = GroupWeights::Locomotion();
        break;
      case v1::GROUP_WEIGHTS_PRESET_UPPER_BODY:
        options.weights = GroupWeights::UpperBody();
        break;
      case v1::GROUP_WEIGHTS_PRESET_UNSPECIFIED:
      case v1::GROUP_WEIGHTS_PRESET_UNIFORM:
        options.weights = GroupWeights::Uniform();
        break;
      default:
        return absl::InvalidArgumentError(StrCat("weights_preset: unknown value ", request.weights_preset()));
    }
  }
  if (request.suppress_within_frames() < 0 || request.suppress_within_frames() > 10'000) {
    return absl::InvalidArgumentError(
        StrCat("suppress_within_frames must be 0 to 10000, not ", request.suppress_within_frames()));
  }
  options.suppress_within_frames = request.suppress_within_frames();
  options.exact = request.exact();
  if (request.has_poses()) {
    const int poses = request.poses().poses_size();
    if (poses == 0) return absl::InvalidArgumentError("poses: the query has no poses");
    if (poses > limits.max_poses) {
      return absl::InvalidArgumentError(StrCat("poses: at most ", limits.max_poses, " poses per call, not ", poses));
    }
    for (int i = 0; i < poses; ++i) {
      const int joints = request.poses().poses(i).joints_size();
      if (joints > MaxNamedPoseJoints()) {
        return absl::InvalidArgumentError(
            StrCat("poses[", i, "]: at most ", MaxNamedPoseJoints(), " joints, not ", joints));
      }
    }
  }
  return options;
}

absl::StatusOr<BodyPointOptions> PointOptionsFromProto(const v1::FindSimilarPosesRequest& request) {
  BodyPointOptions points;
  switch (request.scaling()) {
    case v1::BODY_SCALING_UNSPECIFIED:
    case v1::BODY_SCALING_BONE_DIRECTIONS:
      points.scaling = ChainScaling::kBoneDirections;
      break;
    case v1::BODY_SCALING_PER_CHAIN:
      points.scaling = ChainScaling::kPerChain;
      break;
    case v1::BODY_SCALING_BODY_SCALE:
      points.scaling = ChainScaling::kBodyScale;
      break;
    default:
      return absl::InvalidArgumentError(StrCat("scaling: unknown value ", request.scaling()));
  }
  switch (request.sampling()) {
    case v1::CHAIN_SAMPLING_UNSPECIFIED:
    case v1::CHAIN_SAMPLING_RESAMPLE:
      points.sampling = PointSampling::kResampleChains;
      break;
    case v1::CHAIN_SAMPLING_DROP:
      points.sampling = PointSampling::kDropNearestEndEffector;
      break;
    default:
      return absl::InvalidArgumentError(StrCat("sampling: unknown value ", request.sampling()));
  }
  return points;
}

absl::StatusOr<SimilarQuery> QueryFromProto(const v1::FindSimilarPosesRequest& request,
                                            const PoseSearchOptions& options, const PoseSearchLimits& limits,
                                            bool streaming, const BodyPointOptions& points) {
  const int max_frames = options.exact ? limits.max_exact_query_frames
                         : streaming   ? limits.max_stream_query_frames
                                       : limits.max_query_frames;
  const char* limit_name = options.exact ? "with exact"
                           : streaming   ? "per StreamSimilarPoses call"
                                         : "per FindSimilarPoses call";
  auto check_count = [&](std::int64_t frames) -> absl::Status {
    if (!streaming && frames * options.top_k > limits.max_matches) {
      return absl::InvalidArgumentError(StrCat("the query has ", frames, " query frames x top_k ", options.top_k, " = ",
                                               frames * options.top_k, " matches; at most ", limits.max_matches,
                                               " per FindSimilarPoses call (use StreamSimilarPoses for long clips)"));
    }
    if (frames <= max_frames) return absl::OkStatus();
    return absl::InvalidArgumentError(
        StrCat("the query has ", frames, " query frames; at most ", max_frames, " ", limit_name,
               streaming || options.exact ? "" : " (use StreamSimilarPoses for long clips)",
               ": narrow the frame range or raise frame_step"));
  };
  if (request.has_poses()) {
    MOCAP_RETURN_IF_ERROR(check_count(request.poses().poses_size()));
    std::vector<NamedPose> poses;
    for (const v1::NamedPose& pose : request.poses().poses()) poses.push_back(FromProto(pose));
    return SimilarQuery::FromPoses(poses, points);
  }
  const v1::BvhQuery& bvh = request.bvh();
  if (bvh.frame_step() < 0)
    return absl::InvalidArgumentError(StrCat("bvh.frame_step must be 0 or more, not ", bvh.frame_step()));
  const int step = std::max(1, bvh.frame_step());
  // The frame count before the clip is analysed: from the requested range, or the header.
  if (bvh.has_first_frame() && bvh.has_last_frame() && bvh.last_frame() >= bvh.first_frame()) {
    MOCAP_RETURN_IF_ERROR(check_count((static_cast<std::int64_t>(bvh.last_frame()) - bvh.first_frame()) / step + 1));
  }
  const std::string name = bvh.file_name().empty() ? std::string("query.bvh") : bvh.file_name();
  MOCAP_ASSIGN_OR_RETURN(BvhClip clip, ParseBvh(bvh.bvh(), name));
  std::optional<int> first, last;
  if (bvh.has_first_frame()) first = bvh.first_frame();
  if (bvh.has_last_frame()) last = bvh.last_frame();
  const int file_frames = clip.num_frames();
  const std::int64_t range = static_cast<std::int64_t>(last.value_or(file_frames - 1)) - first.value_or(0);
  if (range >= 0) MOCAP_RETURN_IF_ERROR(check_count(range / step + 1));
  return SimilarQuery::FromBvh(std::move(clip), name, first, last, step);
}

void ToProto(int query_frame, const std::vector<FoundPose>& matches, std::optional<float> novelty,
             v1::QueryFrameMatches* out) {
  out->set_query_frame(query_frame);
  if (novelty) {
    out->set_novelty(*novelty);
    out->set_no_similar_pose(*novelty > kNoSimilarPoseNovelty);
  }
  for (const FoundPose& found : matches) {
    const ClipSummary& clip = found.database->clips[found.match.clip];
    v1::PoseMatch* match = out->add_matches();
    match->set_database(found.database->summary.ref.name());
    match->set_clip_id(clip.id);
    match->set_file_name(clip.source_name);
    match->set_frame(found.source_frame);
    match->set_database_frame(found.match.frame);
    match->set_distance(found.match.distance.total);
    GroupValuesToProto(found.match.distance.per_group, match->mutable_group_distances());
    const GroundAlignment& alignment = found.match.distance.alignment;
    match->mutable_alignment()->set_yaw_degrees(static_cast<float>(alignment.yaw * 180.0 / M_PI));
    match->mutable_alignment()->set_x_body_scales(alignment.x);
    match->mutable_alignment()->set_z_body_scales(alignment.z);
  }
}

}  // namespace mocap

#include "server/similar_search.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"
#include "motion/skeleton/forward_kinematics.h"

namespace mocap {

absl::StatusOr<SearchDatabasePtr> LoadSearchDatabase(MotionStore& store, const DatabaseSummary& database,
                                                     const BodyPointOptions& points) {
  auto loaded = std::make_shared<SearchDatabase>();
  loaded->summary = database;
  MOCAP_ASSIGN_OR_RETURN(loaded->clips, store.ListClips(database.ref));
  if (loaded->clips.empty()) {
    return absl::FailedPreconditionError(
        StrCat("database '", loaded->summary.ref.name(), "' has no clips: import motion into it first"));
  }
  MOCAP_ASSIGN_OR_RETURN(RigModel rig, store.LoadRig(database.ref));
  loaded->index = PoseIndex(points);
  const BodyChains chains = MakeBodyChains(rig.skeleton, rig.topology);
  for (const ClipSummary& clip : loaded->clips) {
    MOCAP_ASSIGN_OR_RETURN(StoredClip stored, store.LoadClip(database.ref, clip.id, rig));
    ClipPoints clip_points = MakeClipPoints(ForwardKinematics(stored.skeleton, stored.motion), chains, points);
    clip_points.name = clip.source_name;
    clip_points.clip_id = clip.id;
    loaded->index.AddClip(std::move(clip_points));
  }
  MOCAP_RETURN_IF_ERROR(loaded->index.Build());
  return SearchDatabasePtr(std::move(loaded));
}

absl::StatusOr<SimilarQuery> SimilarQuery::FromBvh(BvhClip clip, const std::string& name,
                                                   std::optional<int> first_frame, std::optional<int> last_frame,
                                                   int step) {
  if (step < 1) return absl::InvalidArgumentError("frame step must be at least 1");
  SimilarQuery query;
  absl::StatusOr<RigModel> rig = BuildRigModel(clip, {});
  if (!rig.ok()) return absl::Status(rig.status().code(), StrCat(name, ": ", rig.status().message()));
  const int file_frames = clip.num_frames();
  const int first = first_frame.value_or(0);
  const int last = last_frame.value_or(file_frames - 1);
  if (first < 0 || last >= file_frames || first > last) {
    return absl::InvalidArgumentError(
        StrCat("query frames ", first, ":", last, " are outside the file's 0:", file_frames - 1));
  }
  for (int frame = first; frame <= last; frame += step) query.frames_.push_back(frame);
  query.rig_ = std::move(*rig);
  query.clip_ = std::move(clip);
  return query;
}

absl::StatusOr<SimilarQuery> SimilarQuery::FromPoses(const std::vector<NamedPose>& poses,
                                                     const BodyPointOptions& points) {
  if (poses.empty()) return absl::InvalidArgumentError("the query has no poses");
  SimilarQuery query;
  for (size_t i = 0; i < poses.size(); ++i) {
    absl::StatusOr<ClipPoints> pose_points = NamedPosePoints(poses[i], points);
    if (!pose_points.ok()) {
      return absl::Status(pose_points.status().code(),
                          poses.size() == 1 ? std::string(pose_points.status().message())
                                            : StrCat("poses[", i, "]: ", pose_points.status().message()));
    }
    query.pose_points_.push_back(std::move(*pose_points));
    query.frames_.push_back(static_cast<int>(i));
  }
  return query;
}

absl::Status SimilarQuery::Prepare(const std::vector<SearchDatabasePtr>& databases, const BodyPointOptions& points) {
  databases_ = databases;
  clip_points_.clear();
  if (!clip_) return absl::OkStatus();
  const BodyChains chains = MakeBodyChains(rig_->skeleton, rig_->topology);
  // A one-frame file (a T-pose, a single exported pose) is that pose held still: two frames, so
  // it resamples like any clip (issue #25: it was refused as "shorter than two frames").
  BvhClip held;
  const BvhClip* source = &*clip_;
  if (clip_->num_frames() == 1) {
    held = *clip_;
    held.channels = clip_->channels.replicate(2, 1).eval();
    source = &held;
  }
  for (const SearchDatabasePtr& database : databases_) {
    if (source == &held) held.frame_time = 1.0 / database->summary.frame_rate;  // two frames at its rate
    MOCAP_ASSIGN_OR_RETURN(PreparedClip prepared,
                           PrepareClip(*source, *rig_, {.frame_rate = database->summary.frame_rate}));
    clip_points_.push_back(MakeClipPoints(ForwardKinematics(prepared.skeleton, prepared.motion), chains, points));
  }
  return absl::OkStatus();
}

std::optional<float> MatchNovelty(const std::vector<FoundPose>& found, const PoseSearchOptions& options, bool measure) {
  // `found` is best first, so each database's first match is its best: one reference per database
  // (isolated is at least kMinIsolatedDistance, never 0).
  std::optional<float> novelty;
  std::vector<const SearchDatabase*> seen;
  for (const FoundPose& pose : found) {
    if (std::find(seen.begin(), seen.end(), pose.database) != seen.end()) continue;
    seen.push_back(pose.database);
    std::optional<NeighbourDistances> reference = pose.database->index.CachedNeighbourReference(options);
    if (!reference && measure) {
      absl::StatusOr<NeighbourDistances> measured = pose.database->index.NeighbourReference(options);
      if (measured.ok()) reference = *measured;
    }
    if (!reference) continue;
    const float ratio = pose.match.distance.total / reference->isolated;
    if (!novelty || ratio < *novelty) novelty = ratio;
  }
  return novelty;
}

absl::StatusOr<SimilarSearchRun> SimilarQuery::StartSearch(size_t index, const PoseSearchOptions& options) const {
  SimilarSearchRun run;
  run.top_k_ = options.top_k;
  for (size_t d = 0; d < databases_.size(); ++d) {
    const SearchDatabase& database = *databases_[d];
    const ClipPoints* points = nullptr;
    int frame = 0;
    if (clip_) {
      points = &clip_points_[d];
      const double seconds = frames_[index] * clip_->frame_time;
      frame = std::min<int>(static_cast<int>(std::lround(seconds * database.summary.frame_rate)),
                            static_cast<int>(points->points.rows()) - 1);
    } else {
      points = &pose_points_[frames_[index]];
    }
    MOCAP_ASSIGN_OR_RETURN(PoseIndex::Run part, database.index.StartSearch(*points, frame, options));
    run.parts_.push_back({&database, std::move(part)});
  }
  return run;
}

bool SimilarSearchRun::Step(std::int64_t max_rows) {
  while (max_rows > 0 && !done()) {
    PoseIndex::Run& run = parts_[next_part_].run;
    const std::int64_t before = run.compared();
    const bool part_done = run.Step(max_rows);
    max_rows -= std::max<std::int64_t>(1, run.compared() - before);
    if (part_done) ++next_part_;
  }
  return done();
}

std::vector<FoundPose> SimilarSearchRun::Matches() const {
  std::vector<FoundPose> merged;
  for (const Part& part : parts_) {
    for (const PoseMatch& match : part.run.Matches()) {
      const ClipSummary& clip = part.database->clips[match.clip];
      const double source_frame = match.frame / part.database->summary.frame_rate * clip.source_frame_rate;
      merged.push_back({part.database, match, static_cast<int>(std::lround(source_frame))});
    }
  }
  std::stable_sort(merged.begin(), merged.end(), [](const FoundPose& a, const FoundPose& b) {
    return a.match.distance.total < b.match.distance.total;
  });
  if (static_cast<int>(merged.size()) > top_k_) merged.resize(top_k_);
  return merged;
}

absl::StatusOr<std::vector<FoundPose>> SimilarQuery::Search(size_t index, const PoseSearchOptions& options) const {
  MOCAP_ASSIGN_OR_RETURN(SimilarSearchRun run, StartSearch(index, options));
  run.Step(std::numeric_limits<std::int64_t>::max());
  return run.Matches();
}

}  // namespace mocap

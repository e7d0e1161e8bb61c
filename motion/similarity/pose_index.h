// PoseIndex: cross-skeleton similar-pose search over a motion database (docs/method.md B; issue #5).
// Exact search compares the query with every frame (the reference). The fast path prefilters
// with a FLANN kd-tree over a rig-independent feature (heading-normalised body points reduced by
// PCA) and re-ranks the candidates with the exact distance.
//
// Thread safety: build once (AddClip..., Build), then Search and NeighbourReference are const and
// safe to call from many threads at once.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "motion/similarity/body_points.h"
#include "motion/similarity/pose_distance.h"

namespace mocap {

struct PoseSearchOptions {
  GroupWeights weights;
  int top_k = 10;
  // Frames compared, centred on the query frame (odd; 1 = single pose). With more than one,
  // each neighbouring frame's points are placed relative to the centre frame's pelvis, so that
  // the same pose while walking differs from the pose while standing.
  int window = 1;
  bool exact = false;     // compare with every frame instead of the prefiltered candidates
  int candidates = 1000;  // fast path: candidates re-ranked with the exact distance
  // Matches closer than this many frames to a better match in the same clip are dropped, so the
  // top K are not K neighbours of one frame. 0 keeps all.
  int suppress_within_frames = 0;
  // Matches in this clip (index in the order added) are left out; −1 none.
  int exclude_clip = -1;
};

// How far a database's own frames lie from their nearest pose in another clip, with the same
// search options: the yardstick of "nothing here is like this" (issue #25). A query frame whose
// best match is further than kNoSimilarPoseNovelty × `isolated` has no similar pose here.
struct NeighbourDistances {
  float median = 0.0f;
  float isolated = 0.0f;  // the 95th percentile, at least kMinIsolatedDistance
  int frames = 0;         // database frames measured
};
inline constexpr int kNeighbourReferenceFrames = 256;
// The least `isolated` taken (body scales): a database of copies of one clip measures about 0,
// against which every query would be new (bandai-namco-2, one clip in 8: median 0.36, 95th
// percentile 0.69).
inline constexpr float kMinIsolatedDistance = 0.1f;
inline constexpr float kNoSimilarPoseNovelty = 3.0f;

struct PoseMatch {
  int clip = 0;   // index of the clip in the order added
  int frame = 0;  // frame in that clip (the database's frame numbering)
  PoseDistance distance;
};

// The body points of one clip, at the database's frame rate.
struct ClipPoints {
  std::string name;
  std::int64_t clip_id = 0;
  BodyPointMatrix points;                                           // frames x (groups * points_per_group * 3)
  Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor> pelvis;  // frames x 3, body scales
};

// Points and pelvis trajectory of a clip (world Y up), ready for AddClip or as a query.
ClipPoints MakeClipPoints(const GlobalPoses& poses, const BodyChains& chains, const BodyPointOptions& options);

class PoseIndex {
  struct Impl;

 public:
  explicit PoseIndex(BodyPointOptions options = {});
  ~PoseIndex();
  PoseIndex(PoseIndex&&) noexcept;
  PoseIndex& operator=(PoseIndex&&) noexcept;

  void AddClip(ClipPoints clip);
  // Builds the prefilter (PCA + FLANN kd-tree). FailedPrecondition when there are no frames.
  absl::Status Build();

  // One query frame's search, run a step at a time: an exact window search compares every
  // database frame, seconds of work that the service cuts into slices of a few milliseconds
  // (issue #24). Refers to the index, which must outlive it; one caller at a time.
  class Run {
   public:
    // Compares up to `max_rows` more candidates (database frames, or the prefilter's); true once
    // all are compared.
    bool Step(std::int64_t max_rows);
    bool done() const { return next_ >= total_; }
    std::int64_t compared() const { return next_; }
    // The top matches, best first; all candidates must have been compared.
    std::vector<PoseMatch> Matches() const;

   private:
    friend class PoseIndex;
    struct Candidate {
      std::int64_t row = 0;
      PoseMatch match;
    };
    const Impl* index_ = nullptr;
    PoseSearchOptions options_;
    int cloud_points_ = 0;
    std::vector<float> query_cloud_, candidate_cloud_;
    std::vector<std::int64_t> rows_;  // the prefilter's candidates; empty for an exact search (every row)
    std::int64_t total_ = 0, next_ = 0;
    size_t keep_ = 0;              // candidates that can still make the top matches
    std::vector<Candidate> best_;  // heap, worst on top
  };

  // Top matches for frame `frame` of `query` (a clip made with the same BodyPointOptions).
  absl::StatusOr<std::vector<PoseMatch>> Search(const ClipPoints& query, int frame,
                                                const PoseSearchOptions& options) const;
  // The same search, to be run in steps.
  absl::StatusOr<Run> StartSearch(const ClipPoints& query, int frame, const PoseSearchOptions& options) const;

  // The database's neighbour distances under `options` (their weights, window and candidates;
  // an exact search's are measured with the prefilter), on up to kNeighbourReferenceFrames frames
  // spread evenly over the database, computed on first use and kept. FailedPrecondition with a
  // single clip (no other clip to be near).
  absl::StatusOr<NeighbourDistances> NeighbourReference(const PoseSearchOptions& options) const;
  // The reference if already measured.
  std::optional<NeighbourDistances> CachedNeighbourReference(const PoseSearchOptions& options) const;
  // The reference measured a step at a time, kept by Result() for every later caller.
  class ReferenceRun {
   public:
    // Compares up to about `max_rows` more candidates; true once every sample frame is searched.
    bool Step(std::int64_t max_rows);
    bool done() const { return next_sample_ >= samples_; }
    absl::StatusOr<NeighbourDistances> Result();

   private:
    friend class PoseIndex;
    const PoseIndex* index_ = nullptr;
    PoseSearchOptions options_;
    std::int64_t samples_ = 0, next_sample_ = 0;
    std::optional<Run> sample_;  // the sample frame being searched
    std::vector<float> distances_;
    absl::Status status_;  // a sample search that could not start
  };
  absl::StatusOr<ReferenceRun> StartNeighbourReference(const PoseSearchOptions& options) const;

  int num_clips() const;
  std::int64_t num_frames() const;
  const ClipPoints& clip(int index) const;
  const BodyPointOptions& point_options() const;

 private:
  absl::Status CheckQuery(const ClipPoints& query, int frame, const PoseSearchOptions& options) const;
  absl::StatusOr<Run> MakeRun(const ClipPoints& query, int frame, const PoseSearchOptions& options) const;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mocap

// The similar-pose search over store databases that `mocapd similar` and the PoseSearch service
// share (docs/method.md B; issue #11): a query checked before any search work, the searchable form of
// a database version, and the matches of one query frame merged over several databases. No gRPC:
// the service converts (server/pose_search_convert.h), `mocapd similar` prints.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "motion/bvh/bvh_reader.h"
#include "motion/preprocess/clip_preprocessor.h"
#include "motion/similarity/named_pose.h"
#include "motion/similarity/pose_index.h"
#include "storage/motion_store.h"

namespace mocap {

// One database version ready to search; immutable, shared by every search on it.
struct SearchDatabase {
  DatabaseSummary summary;
  std::vector<ClipSummary> clips;  // in the index's clip order
  PoseIndex index;
};
using SearchDatabasePtr = std::shared_ptr<const SearchDatabase>;

// Builds the pose index of a database (found with FindDatabase) from the store.
// FailedPrecondition when it has no clips.
absl::StatusOr<SearchDatabasePtr> LoadSearchDatabase(MotionStore& store, const DatabaseSummary& database,
                                                     const BodyPointOptions& points);

// One match of a query frame, with the database it came from.
struct FoundPose {
  const SearchDatabase* database = nullptr;  // valid while the caller holds the SearchDatabasePtr
  PoseMatch match;
  int source_frame = 0;  // the match's frame in its clip's own numbering (source frame rate)
};

// One query frame's search over every database of a query, run a step at a time
// (PoseIndex::Run): the service cuts long searches into slices of bounded time (issue #24).
class SimilarSearchRun {
 public:
  // Compares up to about `max_rows` more candidates; true once every database is searched.
  bool Step(std::int64_t max_rows);
  bool done() const { return next_part_ >= parts_.size(); }
  // The top_k matches over the databases, best first; all must have been searched.
  std::vector<FoundPose> Matches() const;

 private:
  friend class SimilarQuery;
  struct Part {
    const SearchDatabase* database = nullptr;
    PoseIndex::Run run;
  };
  std::vector<Part> parts_;
  size_t next_part_ = 0;
  int top_k_ = 0;
};

// A query: frames of a BVH clip on any rig, or poses given as named joint positions.
// Thread safety: Prepare once, then Search is const.
class SimilarQuery {
 public:
  // Analyses the clip's rig and picks the frames first..last (file numbering; default all) with
  // `step`. InvalidArgument naming the frames or the rig problem (prefixed with `name`).
  static absl::StatusOr<SimilarQuery> FromBvh(BvhClip clip, const std::string& name, std::optional<int> first_frame,
                                              std::optional<int> last_frame, int step);
  // Each pose is one query frame. InvalidArgument naming the pose and what is wrong with it.
  static absl::StatusOr<SimilarQuery> FromPoses(const std::vector<NamedPose>& poses, const BodyPointOptions& points);

  // Query frames in order: frames of the file (its numbering) or pose indices.
  const std::vector<int>& frames() const { return frames_; }
  bool is_poses() const { return !pose_points_.empty(); }

  // Computes the query's points for these databases (a clip resampled to each database's rate).
  absl::Status Prepare(const std::vector<SearchDatabasePtr>& databases, const BodyPointOptions& points);
  // The top_k matches of query frame frames()[index] over every prepared database, best first.
  absl::StatusOr<std::vector<FoundPose>> Search(size_t index, const PoseSearchOptions& options) const;
  // The same search, to be run in steps; valid while the query lives.
  absl::StatusOr<SimilarSearchRun> StartSearch(size_t index, const PoseSearchOptions& options) const;

 private:
  SimilarQuery() = default;
  std::optional<BvhClip> clip_;
  std::optional<RigModel> rig_;
  std::vector<ClipPoints> pose_points_;  // one per pose
  std::vector<int> frames_;
  std::vector<SearchDatabasePtr> databases_;
  std::vector<ClipPoints> clip_points_;  // per database, for a clip
};

// The novelty of a query frame's matches (NeighbourDistances): the smallest match distance
// against its database's isolated-frame distance under `options`; nullopt when no match's
// database has two clips (nothing to compare with). With `measure` false, only references
// already measured are used (PoseIndex::CachedNeighbourReference): the service measures them in
// slices before searching.
std::optional<float> MatchNovelty(const std::vector<FoundPose>& found, const PoseSearchOptions& options,
                                  bool measure = true);

}  // namespace mocap

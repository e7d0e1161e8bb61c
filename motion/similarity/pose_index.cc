#include "motion/similarity/pose_index.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>

#include <Eigen/Eigenvalues>
#include "motion/core/kd_tree.h"
#include "motion/core/mutex.h"

#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"

namespace mocap {
namespace {

// Prefilter feature: the centre frame's points turned so that the hips' left-right axis is +X
// (removes the heading the exact distance aligns away), reduced by PCA to kReducedDims.
constexpr int kReducedDims = 16;

void CanonicalFeature(const float* points, int num_points, int points_per_group, float* out) {
  const float* left_hip = points + 3 * (static_cast<int>(BodyGroup::kLeftLeg) * points_per_group);
  const float* right_hip = points + 3 * (static_cast<int>(BodyGroup::kRightLeg) * points_per_group);
  float dx = left_hip[0] - right_hip[0], dz = left_hip[2] - right_hip[2];
  const float norm = std::sqrt(dx * dx + dz * dz);
  if (norm < 1e-6f) {
    dx = 1.0f;
    dz = 0.0f;
  } else {
    dx /= norm;
    dz /= norm;
  }
  // Rotate about Y so that (dx, dz) becomes (1, 0).
  for (int i = 0; i < num_points; ++i) {
    const float x = points[3 * i], y = points[3 * i + 1], z = points[3 * i + 2];
    out[3 * i] = x * dx + z * dz;
    out[3 * i + 1] = y;
    out[3 * i + 2] = -x * dz + z * dx;
  }
}

}  // namespace

ClipPoints MakeClipPoints(const GlobalPoses& poses, const BodyChains& chains, const BodyPointOptions& options) {
  ClipPoints clip;
  clip.points = BodyPointsOfClip(poses, chains, options);
  clip.pelvis.resize(poses.num_frames(), 3);
  for (int f = 0; f < poses.num_frames(); ++f) {
    // Same scale as the frame's points.
    clip.pelvis.row(f) = poses.position(f, chains.pelvis).transpose() / BodyScale(poses, f, chains);
  }
  return clip;
}

struct PoseIndex::Impl {
  BodyPointOptions options;
  std::vector<ClipPoints> clips;
  std::vector<std::int64_t> clip_start;  // first global row of each clip
  std::int64_t rows = 0;
  bool built = false;
  Eigen::RowVectorXf mean;
  Eigen::MatrixXf basis;  // features x kReducedDims
  KdTree kd_tree;         // over the reduced features
  // Neighbour references per search options (weights, window, candidates, exact), computed once.
  struct Reference {
    PoseSearchOptions options;
    NeighbourDistances distances;
  };
  mutable Mutex reference_mutex;
  mutable std::vector<Reference> references ABSL_GUARDED_BY(reference_mutex);
  static constexpr size_t kMaxReferences = 16;  // weights are the caller's: a bounded cache

  int pose_points() const { return kNumBodyGroups * options.points_per_group; }

  // Cloud of `window` frames around `frame` of `clip`, each placed relative to the centre
  // frame's pelvis; frames past the clip's ends are clamped.
  void WindowCloud(const ClipPoints& clip, int frame, int window, float* out) const {
    const int n = pose_points();
    const int half = window / 2;
    const int last = static_cast<int>(clip.points.rows()) - 1;
    for (int k = -half; k <= half; ++k) {
      const int f = std::clamp(frame + k, 0, last);
      const Eigen::Vector3f shift = (clip.pelvis.row(f) - clip.pelvis.row(frame)).transpose();
      const float* src = clip.points.row(f).data();
      float* dst = out + 3 * n * (k + half);
      for (int i = 0; i < n; ++i) {
        dst[3 * i] = src[3 * i] + shift.x();
        dst[3 * i + 1] = src[3 * i + 1] + shift.y();
        dst[3 * i + 2] = src[3 * i + 2] + shift.z();
      }
    }
  }

  void Reduce(const float* points, float* out) const {
    const int dims = 3 * pose_points();
    std::vector<float> canonical(dims);
    CanonicalFeature(points, pose_points(), options.points_per_group, canonical.data());
    const Eigen::Map<const Eigen::RowVectorXf> x(canonical.data(), dims);
    Eigen::Map<Eigen::RowVectorXf>(out, basis.cols()) = (x - mean) * basis;
  }

  std::pair<int, int> Locate(std::int64_t row) const {
    const auto it = std::upper_bound(clip_start.begin(), clip_start.end(), row);
    const int clip = static_cast<int>(it - clip_start.begin()) - 1;
    return {clip, static_cast<int>(row - clip_start[clip])};
  }
};

PoseIndex::PoseIndex(BodyPointOptions options) : impl_(std::make_unique<Impl>()) { impl_->options = options; }
PoseIndex::~PoseIndex() = default;
PoseIndex::PoseIndex(PoseIndex&&) noexcept = default;
PoseIndex& PoseIndex::operator=(PoseIndex&&) noexcept = default;

void PoseIndex::AddClip(ClipPoints clip) {
  impl_->clip_start.push_back(impl_->rows);
  impl_->rows += clip.points.rows();
  impl_->clips.push_back(std::move(clip));
  impl_->built = false;
}

absl::Status PoseIndex::Build() {
  Impl& m = *impl_;
  if (m.rows == 0) return absl::FailedPreconditionError("pose index has no frames");
  const int dims = 3 * m.pose_points();
  // PCA over (a sample of) the canonical features.
  const std::int64_t stride = std::max<std::int64_t>(1, m.rows / 50000);
  std::vector<float> canonical(dims);
  Eigen::RowVectorXd mean = Eigen::RowVectorXd::Zero(dims);
  Eigen::MatrixXd scatter = Eigen::MatrixXd::Zero(dims, dims);
  std::int64_t samples = 0;
  for (std::int64_t row = 0; row < m.rows; row += stride) {
    const auto [clip, frame] = m.Locate(row);
    CanonicalFeature(m.clips[clip].points.row(frame).data(), m.pose_points(), m.options.points_per_group,
                     canonical.data());
    const Eigen::RowVectorXd x = Eigen::Map<const Eigen::RowVectorXf>(canonical.data(), dims).cast<double>();
    mean += x;
    scatter += x.transpose() * x;
    ++samples;
  }
  mean /= static_cast<double>(samples);
  const Eigen::MatrixXd covariance = scatter / static_cast<double>(samples) - mean.transpose() * mean;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(covariance);
  const int reduced_dims = std::min(kReducedDims, dims);
  m.mean = mean.cast<float>();
  m.basis = solver.eigenvectors().rightCols(reduced_dims).cast<float>();

  std::vector<float> reduced(static_cast<size_t>(m.rows) * reduced_dims, 0.0f);
  for (std::int64_t row = 0; row < m.rows; ++row) {
    const auto [clip, frame] = m.Locate(row);
    m.Reduce(m.clips[clip].points.row(frame).data(), reduced.data() + row * reduced_dims);
  }
  if (absl::Status status = m.kd_tree.Build(std::move(reduced), reduced_dims); !status.ok()) return status;
  m.built = true;
  return absl::OkStatus();
}

absl::Status PoseIndex::CheckQuery(const ClipPoints& query, int frame, const PoseSearchOptions& options) const {
  const Impl& m = *impl_;
  if (!m.built) return absl::FailedPreconditionError("pose index is not built");
  if (frame < 0 || frame >= query.points.rows()) {
    return absl::InvalidArgumentError(StrCat("query frame ", frame, " is outside 0..", query.points.rows() - 1));
  }
  if (query.points.cols() != 3 * m.pose_points()) {
    return absl::InvalidArgumentError("query points were made with other BodyPointOptions");
  }
  if (options.window < 1 || options.window % 2 == 0 || options.window > 61) {
    return absl::InvalidArgumentError(
        StrCat("window must be an odd number of frames from 1 to 61, not ", options.window));
  }
  if (options.top_k < 1) return absl::InvalidArgumentError("top_k must be at least 1");
  return absl::OkStatus();
}

absl::StatusOr<PoseIndex::Run> PoseIndex::MakeRun(const ClipPoints& query, int frame,
                                                  const PoseSearchOptions& options) const {
  const Impl& m = *impl_;
  Run run;
  run.index_ = &m;
  run.options_ = options;
  run.cloud_points_ = m.pose_points() * options.window;
  run.query_cloud_.resize(3 * run.cloud_points_);
  run.candidate_cloud_.resize(3 * run.cloud_points_);
  m.WindowCloud(query, frame, options.window, run.query_cloud_.data());
  if (options.exact) {
    run.total_ = m.rows;
  } else {
    const int reduced_dims = static_cast<int>(m.basis.cols());
    std::vector<float> reduced(reduced_dims);
    m.Reduce(query.points.row(frame).data(), reduced.data());
    const int count = static_cast<int>(std::min<std::int64_t>(std::max(options.candidates, options.top_k), m.rows));
    MOCAP_ASSIGN_OR_RETURN(std::vector<Neighbour> candidates, m.kd_tree.Search(reduced.data(), count));
    for (const Neighbour& candidate : candidates) run.rows_.push_back(candidate.row);
    run.total_ = static_cast<std::int64_t>(run.rows_.size());
  }
  // The greedy suppression below keeps top_k matches among at most top_k (2 s + 1) best
  // candidates (each kept match suppresses at most 2 s frames of its clip), so only those are
  // kept while comparing: memory and the final sort do not grow with the database.
  run.keep_ =
      static_cast<size_t>(options.top_k) * (2 * static_cast<size_t>(std::max(0, options.suppress_within_frames)) + 1);
  run.best_.reserve(std::min<std::int64_t>(static_cast<std::int64_t>(run.keep_) + 1, run.total_ + 1));
  return run;
}

absl::StatusOr<PoseIndex::Run> PoseIndex::StartSearch(const ClipPoints& query, int frame,
                                                      const PoseSearchOptions& options) const {
  MOCAP_RETURN_IF_ERROR(CheckQuery(query, frame, options));
  return MakeRun(query, frame, options);
}

namespace {
// Best first; equal distances in database order, so the result does not depend on the steps.
bool Better(const PoseMatch& a, std::int64_t a_row, const PoseMatch& b, std::int64_t b_row) {
  if (a.distance.total != b.distance.total) return a.distance.total < b.distance.total;
  return a_row < b_row;
}
}  // namespace

bool PoseIndex::Run::Step(std::int64_t max_rows) {
  const Impl& m = *index_;
  const auto worse_on_top = [](const Candidate& a, const Candidate& b) {
    return Better(a.match, a.row, b.match, b.row);
  };
  const std::int64_t end = std::min(total_, next_ + max_rows);
  for (; next_ < end; ++next_) {
    const std::int64_t row = rows_.empty() ? next_ : rows_[next_];
    const auto [clip, candidate_frame] = m.Locate(row);
    if (clip == options_.exclude_clip) continue;
    m.WindowCloud(m.clips[clip], candidate_frame, options_.window, candidate_cloud_.data());
    Candidate candidate;
    candidate.row = row;
    candidate.match.clip = clip;
    candidate.match.frame = candidate_frame;
    candidate.match.distance = ComparePoses(query_cloud_.data(), candidate_cloud_.data(), cloud_points_,
                                            m.options.points_per_group, options_.weights);
    if (best_.size() == keep_ && !worse_on_top(candidate, best_.front())) continue;
    best_.push_back(candidate);
    std::push_heap(best_.begin(), best_.end(), worse_on_top);
    if (best_.size() > keep_) {
      std::pop_heap(best_.begin(), best_.end(), worse_on_top);
      best_.pop_back();
    }
  }
  return done();
}

std::vector<PoseMatch> PoseIndex::Run::Matches() const {
  std::vector<Candidate> sorted = best_;
  std::sort(sorted.begin(), sorted.end(),
            [](const Candidate& a, const Candidate& b) { return Better(a.match, a.row, b.match, b.row); });
  std::vector<PoseMatch> top;
  for (const Candidate& candidate : sorted) {
    const PoseMatch& match = candidate.match;
    if (static_cast<int>(top.size()) >= options_.top_k) break;
    bool suppressed = false;
    if (options_.suppress_within_frames > 0) {
      for (const PoseMatch& kept : top) {
        if (kept.clip == match.clip && std::abs(kept.frame - match.frame) <= options_.suppress_within_frames) {
          suppressed = true;
          break;
        }
      }
    }
    if (!suppressed) top.push_back(match);
  }
  return top;
}

absl::StatusOr<std::vector<PoseMatch>> PoseIndex::Search(const ClipPoints& query, int frame,
                                                         const PoseSearchOptions& options) const {
  MOCAP_ASSIGN_OR_RETURN(Run run, StartSearch(query, frame, options));
  run.Step(run.total_);
  return run.Matches();
}

namespace {
// The options a neighbour reference is measured and kept under: one best match, no suppression,
// and the prefilter even for exact searches (256 exact window searches of a large database would
// take minutes; the prefilter's nearest is the exact one for nearly every frame).
PoseSearchOptions ReferenceOptions(const PoseSearchOptions& options) {
  PoseSearchOptions search = options;
  search.top_k = 1;
  search.suppress_within_frames = 0;
  search.exclude_clip = -1;
  search.exact = false;
  return search;
}
bool SameReference(const PoseSearchOptions& a, const PoseSearchOptions& b) {
  return a.weights.weight == b.weights.weight && a.window == b.window && a.candidates == b.candidates;
}
}  // namespace

std::optional<NeighbourDistances> PoseIndex::CachedNeighbourReference(const PoseSearchOptions& options) const {
  const Impl& m = *impl_;
  MutexLock lock(&m.reference_mutex);
  for (const Impl::Reference& reference : m.references) {
    if (SameReference(reference.options, options)) return reference.distances;
  }
  return std::nullopt;
}

absl::StatusOr<PoseIndex::ReferenceRun> PoseIndex::StartNeighbourReference(const PoseSearchOptions& options) const {
  const Impl& m = *impl_;
  if (!m.built) return absl::FailedPreconditionError("pose index is not built");
  if (m.clips.size() < 2) return absl::FailedPreconditionError("a single clip has no other clip to be near");
  ReferenceRun run;
  run.index_ = this;
  run.options_ = ReferenceOptions(options);
  run.samples_ = std::min<std::int64_t>(kNeighbourReferenceFrames, m.rows);
  MOCAP_RETURN_IF_ERROR(CheckQuery(m.clips[0], 0, run.options_));
  return run;
}

bool PoseIndex::ReferenceRun::Step(std::int64_t max_rows) {
  const Impl& m = *index_->impl_;
  while (max_rows > 0 && next_sample_ < samples_) {
    if (!sample_) {
      const std::int64_t row = (2 * next_sample_ + 1) * m.rows / (2 * samples_);  // evenly, away from the ends
      const auto [clip, frame] = m.Locate(row);
      PoseSearchOptions search = options_;
      search.exclude_clip = clip;
      absl::StatusOr<Run> sample = index_->MakeRun(m.clips[clip], frame, search);
      if (!sample.ok()) {
        status_ = sample.status();
        next_sample_ = samples_;
        break;
      }
      sample_ = std::move(*sample);
    }
    const std::int64_t before = sample_->compared();
    const bool sample_done = sample_->Step(max_rows);
    max_rows -= std::max<std::int64_t>(1, sample_->compared() - before);
    if (!sample_done) break;
    const std::vector<PoseMatch> best = sample_->Matches();
    if (!best.empty()) distances_.push_back(best.front().distance.total);
    sample_.reset();
    ++next_sample_;
  }
  return done();
}

absl::StatusOr<NeighbourDistances> PoseIndex::ReferenceRun::Result() {
  if (!done()) return absl::FailedPreconditionError("the neighbour reference is not measured yet");
  if (!status_.ok()) return status_;
  if (distances_.empty()) return absl::FailedPreconditionError("no frame has a neighbour in another clip");
  std::sort(distances_.begin(), distances_.end());
  const auto at = [&](double fraction) {
    return distances_[static_cast<size_t>(fraction * static_cast<double>(distances_.size() - 1))];
  };
  NeighbourDistances result{at(0.5), std::max(at(0.95), kMinIsolatedDistance), static_cast<int>(distances_.size())};
  const Impl& m = *index_->impl_;
  MutexLock lock(&m.reference_mutex);
  for (const Impl::Reference& reference : m.references) {
    if (SameReference(reference.options, options_)) return reference.distances;  // another caller was first
  }
  if (m.references.size() >= Impl::kMaxReferences) m.references.erase(m.references.begin());  // oldest out
  m.references.push_back({options_, result});
  return result;
}

absl::StatusOr<NeighbourDistances> PoseIndex::NeighbourReference(const PoseSearchOptions& options) const {
  if (std::optional<NeighbourDistances> cached = CachedNeighbourReference(options)) return *cached;
  MOCAP_ASSIGN_OR_RETURN(ReferenceRun run, StartNeighbourReference(options));
  while (!run.Step(std::numeric_limits<std::int64_t>::max() / 2)) {
  }
  return run.Result();
}

int PoseIndex::num_clips() const { return static_cast<int>(impl_->clips.size()); }
std::int64_t PoseIndex::num_frames() const { return impl_->rows; }
const ClipPoints& PoseIndex::clip(int index) const { return impl_->clips[index]; }
const BodyPointOptions& PoseIndex::point_options() const { return impl_->options; }

}  // namespace mocap

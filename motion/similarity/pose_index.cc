#include "motion/similarity/pose_index.h"

#include <algorithm>
#include <cmath>
#include <numeric>

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

absl::StatusOr<std::vector<PoseMatch>> PoseIndex::Search(const ClipPoints& query, int frame,
                                                         const PoseSearchOptions& options) const {
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

  const int cloud_points = m.pose_points() * options.window;
  std::vector<float> query_cloud(3 * cloud_points), candidate_cloud(3 * cloud_points);
  m.WindowCloud(query, frame, options.window, query_cloud.data());

  std::vector<std::int64_t> rows;
  if (options.exact) {
    rows.resize(m.rows);
    std::iota(rows.begin(), rows.end(), 0);
  } else {
    const int reduced_dims = static_cast<int>(m.basis.cols());
    std::vector<float> reduced(reduced_dims);
    m.Reduce(query.points.row(frame).data(), reduced.data());
    const int count = static_cast<int>(std::min<std::int64_t>(std::max(options.candidates, options.top_k), m.rows));
    absl::StatusOr<std::vector<Neighbour>> candidates = m.kd_tree.Search(reduced.data(), count);
    if (!candidates.ok()) return candidates.status();
    for (const Neighbour& candidate : *candidates) rows.push_back(candidate.row);
  }

  std::vector<PoseMatch> matches;
  matches.reserve(rows.size());
  for (std::int64_t row : rows) {
    const auto [clip, candidate_frame] = m.Locate(row);
    if (clip == options.exclude_clip) continue;
    m.WindowCloud(m.clips[clip], candidate_frame, options.window, candidate_cloud.data());
    PoseMatch match;
    match.clip = clip;
    match.frame = candidate_frame;
    match.distance = ComparePoses(query_cloud.data(), candidate_cloud.data(), cloud_points, m.options.points_per_group,
                                  options.weights);
    matches.push_back(match);
  }
  std::sort(matches.begin(), matches.end(),
            [](const PoseMatch& a, const PoseMatch& b) { return a.distance.total < b.distance.total; });
  std::vector<PoseMatch> top;
  for (const PoseMatch& match : matches) {
    if (static_cast<int>(top.size()) >= options.top_k) break;
    bool suppressed = false;
    if (options.suppress_within_frames > 0) {
      for (const PoseMatch& kept : top) {
        if (kept.clip == match.clip && std::abs(kept.frame - match.frame) <= options.suppress_within_frames) {
          suppressed = true;
          break;
        }
      }
    }
    if (!suppressed) top.push_back(match);
  }
  return top;
}

absl::StatusOr<NeighbourDistances> PoseIndex::NeighbourReference(const PoseSearchOptions& options) const {
  const Impl& m = *impl_;
  if (!m.built) return absl::FailedPreconditionError("pose index is not built");
  if (m.clips.size() < 2) return absl::FailedPreconditionError("a single clip has no other clip to be near");
  const auto same = [&](const PoseSearchOptions& a) {
    return a.weights.weight == options.weights.weight && a.window == options.window &&
           a.candidates == options.candidates && a.exact == options.exact;
  };
  {
    MutexLock lock(&m.reference_mutex);
    for (const Impl::Reference& reference : m.references) {
      if (same(reference.options)) return reference.distances;
    }
  }
  // Computed outside the lock: two first callers may both measure (the same figures).
  PoseSearchOptions search = options;
  search.top_k = 1;
  search.suppress_within_frames = 0;
  const std::int64_t samples = std::min<std::int64_t>(kNeighbourReferenceFrames, m.rows);
  std::vector<float> distances;
  for (std::int64_t i = 0; i < samples; ++i) {
    const std::int64_t row = (2 * i + 1) * m.rows / (2 * samples);  // evenly, away from the ends
    const auto [clip, frame] = m.Locate(row);
    search.exclude_clip = clip;
    MOCAP_ASSIGN_OR_RETURN(std::vector<PoseMatch> best, Search(m.clips[clip], frame, search));
    if (!best.empty()) distances.push_back(best.front().distance.total);
  }
  if (distances.empty()) return absl::FailedPreconditionError("no frame has a neighbour in another clip");
  std::sort(distances.begin(), distances.end());
  const auto at = [&](double fraction) {
    return distances[static_cast<size_t>(fraction * static_cast<double>(distances.size() - 1))];
  };
  NeighbourDistances result{at(0.5), std::max(at(0.95), kMinIsolatedDistance), static_cast<int>(distances.size())};
  MutexLock lock(&m.reference_mutex);
  if (m.references.size() >= Impl::kMaxReferences) m.references.erase(m.references.begin());  // oldest out
  m.references.push_back({options, result});
  return result;
}

int PoseIndex::num_clips() const { return static_cast<int>(impl_->clips.size()); }
std::int64_t PoseIndex::num_frames() const { return impl_->rows; }
const ClipPoints& PoseIndex::clip(int index) const { return impl_->clips[index]; }
const BodyPointOptions& PoseIndex::point_options() const { return impl_->options; }

}  // namespace mocap

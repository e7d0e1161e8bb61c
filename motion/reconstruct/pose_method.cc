#include "motion/reconstruct/pose_method.h"

#include <vector>

#include "motion/core/status_macros.h"
#include "motion/reconstruct/local_pose_model.h"

namespace mocap {
namespace {

// A database frame's pelvis placed in the query's wrist reference frame.
void PelvisInQueryFrame(const DatabaseFrame& f, const ReferenceFrame& ref, SolvedPose* pose) {
  const Eigen::Quaternionf ref_rotation(ref.rotation);
  pose->pelvis_position =
      ref.origin + ref.rotation * Eigen::Vector3f(f.pelvis_position[0], f.pelvis_position[1], f.pelvis_position[2]);
  pose->pelvis_rotation = (ref_rotation * Eigen::Quaternionf(f.pelvis_rotation[0], f.pelvis_rotation[1],
                                                             f.pelvis_rotation[2], f.pelvis_rotation[3]))
                              .normalized();
}

// A database frame's pose placed in the query's wrist reference frame (A1: local coordinates are
// comparable across frames): its pose feature, its pelvis moved into `ref`.
SolvedPose DatabasePoseInQueryFrame(const ReconstructionDatabase& db, int row, const ReferenceFrame& ref) {
  SolvedPose pose;
  pose.pose_feature = db.pose_feature(row).transpose();
  PelvisInQueryFrame(db.frames()[row], ref, &pose);
  return pose;
}

absl::StatusOr<std::vector<Neighbour>> NearestByWrists(const ReconstructionDatabase& db, const FrameFeatures& query,
                                                       int count) {
  float feature[kWristFeatureDims];
  WristFeature(query, db.wrist_feature_options(), feature);
  return db.wrist_index().Search(feature, count);
}

// A5–A6: the local linear model of the neighbours' poses, solved against the targets; a segment's
// first frame starts from the nearest database pose. The full method (A2–A7) takes the frames
// nearest by wrists and the estimated ankles (eq. 8) and is driven by both; the wrists-only
// baseline (patent §5) takes the frames nearest by wrists and is driven by the wrists alone.
class LocalModelMethod final : public PoseMethod {
 public:
  LocalModelMethod(const ReconstructionOptions& options, bool ankles)
      : ankles_(ankles),
        neighbours_(options.pose_neighbours),
        components_(options.pose_components),
        kernel_(options.pose_neighbour_kernel),
        solver_(options.solver) {
    if (!ankles_) solver_.control_ankles = false;
  }
  bool uses_ankles() const override { return ankles_; }
  bool solves() const override { return true; }
  absl::StatusOr<std::vector<Neighbour>> Neighbours(const ReconstructionDatabase& db,
                                                    const FrameFeatures& query) const override {
    if (!ankles_) return NearestByWrists(db, query, neighbours_);
    float feature[kWristAnkleFeatureDims];
    WristAnkleFeature(query, db.wrist_ankle_weights(), feature);
    return db.NearestByWristsAndAnkles(feature, neighbours_);
  }
  absl::StatusOr<SolvedPose> Pose(const ReconstructionDatabase& db, std::span<const Neighbour> neighbours,
                                  const ReferenceFrame& ref, const ControlTargets& targets,
                                  const PoseHistory& history) const override {
    Eigen::MatrixXf examples(static_cast<Eigen::Index>(neighbours.size()), db.pose_feature_size());
    for (size_t i = 0; i < neighbours.size(); ++i)
      examples.row(static_cast<Eigen::Index>(i)) = db.pose_feature(neighbours[i].row);
    Eigen::VectorXf weights;
    if (kernel_ > 0) {
      std::vector<float> distances(neighbours.size());
      for (size_t i = 0; i < neighbours.size(); ++i) distances[i] = neighbours[i].distance;
      weights = NeighbourKernelWeights(distances, kernel_);
    }
    MOCAP_ASSIGN_OR_RETURN(const LocalPoseModel model, FitLocalPoseModel(examples, components_, weights));
    const SolvedPose initial =
        history.previous ? *history.previous : DatabasePoseInQueryFrame(db, neighbours.front().row, ref);
    PoseSolverOptions solver = solver_;
    solver.prior_weight *= history.prior_weight_factor;
    return SolvePose(db.body(), model, targets, initial, history.previous, history.before_previous, solver);
  }

 private:
  bool ankles_;
  int neighbours_, components_;
  float kernel_;
  PoseSolverOptions solver_;  // without the ankles' E_ctrl where the method has none
};

// Baseline: the database pose nearest by eq. 2, a plain motion-matching lookup.
class NearestNeighbourMethod final : public PoseMethod {
 public:
  bool uses_ankles() const override { return false; }
  bool solves() const override { return false; }
  absl::StatusOr<std::vector<Neighbour>> Neighbours(const ReconstructionDatabase& db,
                                                    const FrameFeatures& query) const override {
    return NearestByWrists(db, query, 1);
  }
  absl::StatusOr<SolvedPose> Pose(const ReconstructionDatabase& db, std::span<const Neighbour> neighbours,
                                  const ReferenceFrame& ref, const ControlTargets&, const PoseHistory&) const override {
    return DatabasePoseInQueryFrame(db, neighbours.front().row, ref);
  }
};

// Baseline: the mean of the `average_neighbours` poses nearest by eq. 2 (joint rotation vectors
// about the rig's reference, and the pelvis, each neighbour placed in the query's wrist frame).
class NearestAverageMethod final : public PoseMethod {
 public:
  explicit NearestAverageMethod(int count) : count_(count) {}
  bool uses_ankles() const override { return false; }
  bool solves() const override { return false; }
  absl::StatusOr<std::vector<Neighbour>> Neighbours(const ReconstructionDatabase& db,
                                                    const FrameFeatures& query) const override {
    return NearestByWrists(db, query, count_);
  }
  absl::StatusOr<SolvedPose> Pose(const ReconstructionDatabase& db, std::span<const Neighbour> neighbours,
                                  const ReferenceFrame& ref, const ControlTargets&, const PoseHistory&) const override {
    SolvedPose mean = DatabasePoseInQueryFrame(db, neighbours.front().row, ref);
    Eigen::Vector3f position = Eigen::Vector3f::Zero();
    Eigen::Vector4f rotation = Eigen::Vector4f::Zero();
    mean.pose_feature.setZero();
    for (const Neighbour& n : neighbours) {
      SolvedPose one;
      PelvisInQueryFrame(db.frames()[n.row], ref, &one);
      position += one.pelvis_position;
      Eigen::Vector4f q = one.pelvis_rotation.coeffs();
      if (q.dot(mean.pelvis_rotation.coeffs()) < 0) q = -q;  // the nearest's hemisphere
      rotation += q;
      mean.pose_feature += db.pose_feature(n.row).transpose();
    }
    const float count = static_cast<float>(neighbours.size());
    mean.pose_feature /= count;
    mean.pelvis_position = position / count;
    mean.pelvis_rotation = Eigen::Quaternionf(rotation.normalized());
    return mean;
  }

 private:
  int count_;
};

}  // namespace

std::unique_ptr<PoseMethod> MakePoseMethod(const ReconstructionOptions& options) {
  switch (options.method) {
    case ReconstructionMethod::kFull:
      return std::make_unique<LocalModelMethod>(options, /*ankles=*/true);
    case ReconstructionMethod::kWristsOnly:
      return std::make_unique<LocalModelMethod>(options, /*ankles=*/false);
    case ReconstructionMethod::kNearestNeighbour:
      return std::make_unique<NearestNeighbourMethod>();
    case ReconstructionMethod::kNearestAverage:
      return std::make_unique<NearestAverageMethod>(options.average_neighbours);
  }
  return std::make_unique<LocalModelMethod>(options, /*ankles=*/true);
}

}  // namespace mocap

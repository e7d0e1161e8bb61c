// What each ReconstructionMethod does for one frame's pose (docs/method.md A5–A6 and the
// baselines of A8): which database frames it looks at, and how it makes a pose of them. The
// session runs the shared stages around it (A2 input, A3–A4 ankles when the method uses them, A7
// post-processing); a new method is one more PoseMethod, not a branch in every stage.
#pragma once

#include <memory>
#include <span>
#include <vector>

#include "absl/status/statusor.h"
#include "motion/core/kd_tree.h"
#include "motion/preprocess/frame_features.h"
#include "motion/reconstruct/pose_solver.h"
#include "motion/reconstruct/reconstruction_database.h"
#include "motion/reconstruct/reconstruction_options.h"

namespace mocap {

// The segment's last two solved poses: A6 starts from the previous one, E_smooth reads both. And
// the session's factor on A6's prior weight (unfamiliar_prior.h).
struct PoseHistory {
  const SolvedPose* previous = nullptr;
  const SolvedPose* before_previous = nullptr;
  float prior_weight_factor = 1.0f;
};

class PoseMethod {
 public:
  virtual ~PoseMethod() = default;
  // Whether the method needs the A3–A4 ankle estimate (its query carries the ankles, and the
  // frame's targets hold them).
  virtual bool uses_ankles() const = 0;
  // Whether the pose comes from a model solved against the targets (A5–A6), which starts from the
  // segment's previous solution; a lookup's pose comes from the neighbours alone.
  virtual bool solves() const = 0;
  // The database frames the pose comes from, nearest first (at least one).
  virtual absl::StatusOr<std::vector<Neighbour>> Neighbours(const ReconstructionDatabase& db,
                                                            const FrameFeatures& query) const = 0;
  // The frame's pose from `neighbours`, placed in the query's wrist frame `ref`.
  virtual absl::StatusOr<SolvedPose> Pose(const ReconstructionDatabase& db, std::span<const Neighbour> neighbours,
                                          const ReferenceFrame& ref, const ControlTargets& targets,
                                          const PoseHistory& history) const = 0;
};

std::unique_ptr<PoseMethod> MakePoseMethod(const ReconstructionOptions& options);

}  // namespace mocap

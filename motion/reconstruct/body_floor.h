// No part of the body under the floor (issue #22): a pose the solve made for input the database
// has no posture for — a dancer down on the floor, a hand on it and the pelvis 20 cm up — can
// bend its trunk into the ground (stop 72: a head 17 cm under it). The session's space has the
// ground at y = 0 (hand_floor.h). The feet have their own rule (the leg IK lifts an ankle to the
// planted height); the hands are put on their floor-clamped input by the arm IK. Every other
// joint — pelvis, spine, head, shoulders, elbows, wrists, hips, knees — keeps the body above the
// floor by lifting the whole body, as a person lying down rests on the ground.
#pragma once

#include <span>
#include <vector>

#include <Eigen/Core>

#include "motion/skeleton/body_topology.h"
#include "motion/skeleton/skeleton.h"

namespace mocap {

// The joints that lift the body: all but those above the pelvis (the root chain the pelvis hangs
// from) and those past an ankle or a wrist (feet, toes, hands, fingers: their own rules).
std::vector<int> FloorBearingJoints(const Skeleton& skeleton, const BodyLandmarks& landmarks);

// How far the body must rise (metres, ≥ 0) for none of `joints` to be under the ground.
float FloorLift(std::span<const Eigen::Vector3f> world_positions, std::span<const int> joints);

}  // namespace mocap

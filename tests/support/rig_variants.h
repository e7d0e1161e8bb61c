// Variants of a clip for similarity tests: the same motion re-rigged as another user's file would
// be (renamed joints, a split bone, another channel order, another unit, turned and moved), and
// the same joint rotations on a differently built body (each body group's bones lengthened or
// shortened). Work on any rig, synthetic or captured.
#pragma once

#include <random>
#include <string>

#include <Eigen/Core>

#include "absl/status/status.h"
#include "motion/bvh/bvh_clip.h"
#include "motion/skeleton/body_topology.h"

namespace mocap::testing {

// Turns the whole clip about the vertical (world Y up) and moves it on the ground (file units).
void MoveOnGround(BvhClip& clip, float yaw_degrees, const Eigen::Vector3f& ground_translation);

// Names every joint "j<index>".
void RenameJoints(BvhClip& clip);

// Inserts a joint `new_name` halfway along the bone ending at joint `child` (a split bone): the
// new joint has rotation channels, all zero, and `child` hangs off it with half its offset.
// InvalidArgument for the root or a joint without rotation channels.
absl::Status SplitBone(BvhClip& clip, int child, const std::string& new_name);

// The same rotations written in another Euler order (a permutation of "XYZ").
void ChangeRotationOrder(BvhClip& clip, const std::string& order);

// Multiplies every length (offsets, end sites, position channels) by `factor`: another unit.
void ScaleLengths(BvhClip& clip, float factor);

// Length factors per body group (both legs share one, both arms one).
struct Proportions {
  float legs = 1.0f;
  float arms = 1.0f;
  float spine = 1.0f;
  float head = 1.0f;
};
// Each factor drawn log-uniformly in [low, high].
Proportions RandomProportions(std::mt19937& random, float low = 0.8f, float high = 1.25f);

// The same joint rotations on a differently built body: every bone of a group (the topology
// analysis' groups of this clip's rig) is scaled by its group's factor (its offset and position
// channels); the pelvis and the joints above it carry the body's travel and height, which follow
// the legs. `topology` is the clip's own (BuildRigModel).
void ScaleProportions(BvhClip& clip, const BodyTopology& topology, const Proportions& proportions);

// The same joint rotations on a body whose every bone has its own length factor, drawn
// log-uniformly in [low, high]: thigh and shin, upper arm and forearm, left and right, each
// vertebra and the clavicles all differ (ScaleProportions keeps the proportions within a group).
// The pelvis and its ancestors follow the legs' mean factor.
void ScaleEveryBone(BvhClip& clip, const BodyTopology& topology, std::mt19937& random, float low = 0.8f,
                    float high = 1.25f);

// A new user's copy of the clip: joints renamed, the bone into `split_joint` split (an extra
// joint), XYZ rotation order, inches instead of the file's unit (the file is taken to be in cm),
// turned by `yaw_degrees` and moved on the ground.
absl::Status Rerig(BvhClip& clip, int split_joint, float yaw_degrees, const Eigen::Vector3f& ground_translation);

}  // namespace mocap::testing

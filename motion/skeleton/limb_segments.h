// Where a limb chain (docs/method.md B1 groups: clavicle -> wrist, hip -> ankle) is cut into its two
// long bones, from lengths along the chain alone, so that a clavicle, a hip offset, a twist joint
// or a split bone never takes the place of the shoulder (hip) or the elbow (knee).
#pragma once

#include <span>

namespace mocap {

// `cumulative[i]` is the length along the chain from its first joint to its i-th (cumulative[0]
// = 0, non-decreasing). Returns the index of the upper segment's start (shoulder / hip): the
// joint above `middle` whose distance to it along the chain is nearest the lower segment's
// length (upper arm ≈ forearm, thigh ≈ shin). 0 when no joint above `middle` gives a length.
int UpperSegmentStart(std::span<const float> cumulative, int middle);

// The bend (elbow / knee) of a chain whose landmarks do not name it: the inner joint that cuts
// the chain into the two parts nearest in length. For chains of fewer than three joints, the
// last joint.
int LimbBendByLength(std::span<const float> cumulative);

}  // namespace mocap

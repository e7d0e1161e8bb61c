// Which reading of a BVH root's position channels a file was written for.
//
// Readers disagree: Blender's importer, three.js's BVHLoader and MotionBuilder take the root's
// position channels alone and ignore its OFFSET (and most exporters write for them, e.g. Mixamo
// roots with a non-zero OFFSET); other files keep the hip height in the root OFFSET and small
// channel values, so root translation = OFFSET + channels (the cmu-cc files rooted at the hip).
// A reader has to decide per file (shared/data/README.md); a writer writes files on which both
// readings agree: root OFFSET zero where the root has position channels.
#pragma once

#include "motion/bvh/bvh_clip.h"

namespace mocap {

// Decides from the evidence of the motion: with the root OFFSET left out, and with it added, which
// reading puts the body's lowest point (its 10th percentile over the clip) nearer the floor (height
// 0 on the body's up axis, the axis of its largest extent)? A clip spent wholly off the ground
// (on a climbing frame) can fool it. A tie (an OFFSET with no height, or no root position
// channels) keeps the common readers' reading, channels alone. Cost: forward kinematics of at
// most 64 frames.
RootPositionReading DecideRootPositionReading(const BvhClip& clip);

// Applies the decision to the clip (`clip.root_reading`): where the channels alone are meant, the
// root OFFSET's components that position channels drive are set to zero, so that everything
// downstream can read translation = OFFSET + channels, as MotionFromChannels does.
void NormaliseRootPosition(BvhClip& clip);

// For writers: the same motion in a form every reader places alike. Readers agree on joints
// without position channels; on a joint with them, Blender reads the channels alone (as this
// reader does below the root), three.js adds the OFFSET (on every joint), this reader adds it on
// the root only. So: the root's OFFSET moves into its position channels (every frame); a non-root
// joint whose position channels never change gets them as its OFFSET (the channels are dropped,
// so the rest pose keeps the bone); one whose translation is animated keeps its channels over a
// zero OFFSET. Returns
// whether anything changed. Channel order is the skeleton's, as in Skeleton::channel_start.
bool MakeReadersAgree(BvhClip& clip);
// True when MakeReadersAgree would change nothing.
bool ReadersAgreeOn(const BvhClip& clip);

}  // namespace mocap

// A procedural humanoid rig and walking clip for unit tests: the answer key is known exactly, so
// tests of the importer, forward kinematics and the preprocessing steps can check what they find.
//
// World (after the root rotation when `z_up`): Y up, the character faces +Z and walks along +Z at
// kSyntheticWalkSpeed, its left side at +X (right-handed: left = up x forward). Lengths below are
// in centimetres; every length in the clip is multiplied by SyntheticRigOptions::length_scale.
//
// Joint names (BVH order, parents before children; "Left*" at +X, "Right*" at -X):
//   [RL_BoneRoot]            when z_up: root of a Z-up hierarchy, offset 0, 6 channels; its
//                            rotation is -90 deg about X (Xrotation = -90, other angles 0)
//   [Root]                   when extra_root: static node, offset 0, 6 channels all zero
//   Hips                     rest OFFSET (0, 96, 0) (Y-up axes); pelvis
//     [Pelvis]               when twist_bones: zero offset; the thighs hang off it
//       LeftUpLeg (9,-6,0) -> LeftLeg (0,-43,0) -> LeftFoot (0,-42,0) -> LeftToeBase (0,-4.5,13)
//         when fingers_and_toes: LeftToe1..LeftToe5 under LeftToeBase (1 = big toe, medial)
//         when twist_bones: LeftUpLegTwist (zero offset, child of LeftUpLeg) -> LeftUpLegTwistMid
//           (0,-21.5,0); LeftLegTwist (child of LeftLeg) -> LeftLegTwistMid (0,-21,0);
//           LeftKneeShareBone (zero offset leaf under LeftLeg)
//       RightUpLeg ... the mirror image (same names with "Right")
//     Spine (0,10,0) -> Chest (0,15,0) -> Neck (0,22,0) -> Head (0,9,0), End Site (0,18,0)
//     Chest -> LeftShoulder (3,17,0) -> LeftArm (14,0,0) -> LeftForeArm (28,0,0) -> LeftHand (25,0,0)
//       when fingers_and_toes: LeftHand{Thumb,Index,Middle,Ring,Pinky}{1,2,3} under LeftHand
//       when twist_bones: LeftArmTwist -> LeftArmTwistMid (14,0,0) under LeftArm; LeftForeArmTwist
//         -> LeftForeArmTwistMid (12.5,0,0) under LeftForeArm; LeftElbowShareBone under LeftForeArm
//     Chest -> RightShoulder ... the mirror image
// Order in the file: Hips, Spine, Chest, Neck, Head, LeftShoulder.., RightShoulder.., [Pelvis],
// LeftUpLeg.., RightUpLeg... Every leaf joint has an End Site. The plain rig has 21 joints (22 with
// extra_root, like the Bandai rig).
//
// Rest pose (all rotations zero, plain rig): a T-pose standing with the ankles kSyntheticAnkleHeight
// above the floor, arms straight along +-X at shoulder height.
//
// Motion: a walk with gait cycle kSyntheticGaitCycle seconds (left heel strike at t = 0, right at
// half a cycle; 60 cm steps). Each stance foot is flat and planted (it does not slide) with the
// ankle exactly at kSyntheticAnkleHeight and the toe base at kSyntheticToeHeight (the landing foot
// touches down from < 0.5 cm above); at every instant one foot is down. The hips rise and fall by ~5 cm (highest at
// mid-stance, ~92 cm on average); hip flexion (thigh angle from vertical, forward positive) stays within about -18..+29
// deg; knees bend 5-15 deg in stance and up to 60 deg early in swing, the swing foot clearing the floor; the arms hang
// (lowered 75 deg from the T-pose) and swing +-18 deg opposite to the legs with the elbows bent 20-30 deg; the pelvis
// yaws +-4 deg and the spine counter-rotates so that the head keeps facing +Z exactly. Twist joints roll +-3 deg about
// their bone.
//
// Channel values follow the BVH semantics of MotionFromChannels (motion/skeleton/local_motion.h):
// root translation = OFFSET + position channels; a position channel on any other joint replaces
// that OFFSET component. Which joint carries the travel:
//   plain / position_channels_everywhere: Hips is the root; its channels are (position - OFFSET);
//   extra_root: Hips' position channels hold its absolute position (in Root's frame);
//   z_up without extra_root: RL_BoneRoot's position channels hold the world translation and Hips
//   has rotation channels only (unless position_channels_everywhere, where they equal its OFFSET).
#pragma once

#include <string>

#include "motion/bvh/bvh_clip.h"

namespace mocap::testing {

inline constexpr double kSyntheticWalkSpeed = 120.0;      // cm/s along +Z
inline constexpr double kSyntheticGaitCycle = 1.0;        // seconds per two steps
inline constexpr double kSyntheticAnkleHeight = 5.0;      // cm, ankle of a planted foot
inline constexpr double kSyntheticToeHeight = 0.5;        // cm, toe base of a planted foot
inline constexpr double kSyntheticRestHipsHeight = 96.0;  // cm, Hips OFFSET
inline constexpr double kSyntheticLegLength = 85.0;       // cm, hip joint -> ankle
inline constexpr double kSyntheticThighLength = 43.0;
inline constexpr double kSyntheticShinLength = 42.0;

// Where the synthetic walk goes (the body always faces its own +Z; the gait is the same).
enum class SyntheticPath {
  kStraight,   // along +Z, facing it (the walk described above)
  kBackwards,  // facing +Z, travelling along -Z (the walk played backwards in time)
  kSideways,   // facing +Z, travelling along +X (its left) at half the speed: the legs step in place
  kCircle,     // turning continuously: the whole body turns about the vertical through the circle's centre
};

struct SyntheticRigOptions {
  bool extra_root = false;                    // static node "Root" above "Hips" (like Bandai's joint_Root: zero
                                              // offset, 6 channels all zero; Hips then carries the motion in
                                              // its position channels)
  bool z_up = false;                          // hierarchy authored Z-up under "RL_BoneRoot"; its rotation of
                                              // -90 deg about X makes the world Y-up (like some cmu-cc files)
  bool fingers_and_toes = false;              // 5 fingers (3 joints each) on each hand, 5 toes on each foot
  bool twist_bones = false;                   // CC-like extras: twist joints with mid-bone children, ShareBone
                                              // leaves at knee and elbow, a zero-length Pelvis joint
  bool position_channels_everywhere = false;  // 6 channels on every joint (Bandai)
  double length_scale = 1.0;                  // 1.0: centimetres; 0.01: metres; 1 / 2.54: inches
  std::string rotation_order = "ZXY";         // Euler channel order of every joint (a permutation of XYZ)
  // Added for issue 23 (rigs and clips of other exporters); the defaults give the clip above.
  double clavicle_length = 14.0;  // cm, LeftShoulder -> LeftArm (and its mirror); the CMU rig's clavicle is
                                  // longer than its forearm (here 25)
  bool mirrored_names = false;    // names that lie: every "Left*" joint is named "Right*" and the reverse
                                  // (the joint at +X, the body's left, is then "RightHand" etc.)
  SyntheticPath path = SyntheticPath::kStraight;
  double circle_radius = 100.0;  // cm, for kCircle: > 0 turns left (towards +X first), < 0 turns right; the
                                 // walk covers 2 pi |radius| in 2 pi |radius| / kSyntheticWalkSpeed seconds
};

// The walking clip described above; `frames` frames, `frame_time` seconds apart.
// Rig options from bit flags (1 extra_root, 2 z_up, 4 fingers_and_toes, 8 twist_bones,
// 16 position_channels_everywhere), for tests that sweep every combination.
SyntheticRigOptions SyntheticRigFromBits(int bits, const std::string& rotation_order = "ZXY");

BvhClip MakeWalkingClip(const SyntheticRigOptions& options = {}, int frames = 60, double frame_time = 1.0 / 30.0);

// One frame of the rig standing still (options.path is ignored): every rotation zero, feet flat,
// the hips at kSyntheticRestHipsHeight, except the arms, lowered `arm_lowering_degrees` from the
// T-pose in the body's frontal plane (0: T-pose; 45: an A-pose).
BvhClip MakeStandingClip(const SyntheticRigOptions& options, double arm_lowering_degrees);

}  // namespace mocap::testing

#include "motion/similarity/body_points.h"

#include <algorithm>
#include <span>
#include <tuple>

#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"
#include "motion/skeleton/limb_segments.h"

namespace mocap {
namespace {

std::vector<int> ChainBetween(const Skeleton& skeleton, int top, int end) {
  std::vector<int> chain;
  for (int j = end; j >= 0; j = skeleton.parent(j)) {
    chain.push_back(j);
    if (j == top) break;
  }
  if (chain.back() != top) return {end};  // `top` is not an ancestor: degenerate rig, one point
  std::reverse(chain.begin(), chain.end());
  return chain;
}

// Each limb's shoulder / hip and elbow / knee as indices in its chain (BodyChains::root, bend),
// from the landmarks that name them. Landmarks of -1 are skipped, and so are landmarks that are
// not an inner joint of their chain (or, for a shoulder / hip, not above the elbow / knee, or
// named without it) unless `strict`: then InvalidArgument names the first.
absl::Status SetLimbSections(const BodyLandmarks& l, bool strict, BodyChains* chains) {
  struct Limb {
    BodyGroup group;
    int root, bend;
    const char *root_name, *bend_name;
  };
  for (const Limb& limb : {Limb{BodyGroup::kLeftArm, l.left_shoulder, l.left_elbow, "left_shoulder", "left_elbow"},
                           Limb{BodyGroup::kRightArm, l.right_shoulder, l.right_elbow, "right_shoulder", "right_elbow"},
                           Limb{BodyGroup::kLeftLeg, l.left_hip, l.left_knee, "left_hip", "left_knee"},
                           Limb{BodyGroup::kRightLeg, l.right_hip, l.right_knee, "right_hip", "right_knee"}}) {
    const int g = static_cast<int>(limb.group);
    const std::vector<int>& chain = chains->joints[g];
    auto index_of = [&](int joint) {
      const auto it = std::find(chain.begin(), chain.end(), joint);
      return it == chain.end() ? -1 : static_cast<int>(it - chain.begin());
    };
    if (limb.bend < 0) {
      if (strict && limb.root >= 0)
        return absl::InvalidArgumentError(StrCat(limb.root_name, " needs ", limb.bend_name));
      continue;  // unknown: found by length
    }
    const int bend = index_of(limb.bend);
    if (bend <= 0 || bend + 1 >= static_cast<int>(chain.size())) {
      if (!strict) continue;
      return absl::InvalidArgumentError(
          StrCat("landmark '", limb.bend_name, "' is not a joint inside the ", BodyGroupName(limb.group)));
    }
    chains->bend[g] = bend;
    if (limb.root < 0) continue;
    const int root = index_of(limb.root);
    if (root < 0 || root >= bend) {
      if (!strict) continue;
      return absl::InvalidArgumentError(StrCat("landmark '", limb.root_name, "' is not a joint of the ",
                                               BodyGroupName(limb.group), " above '", limb.bend_name, "'"));
    }
    chains->root[g] = root;
  }
  return absl::OkStatus();
}

}  // namespace

std::string_view ChainScalingName(ChainScaling scaling) {
  switch (scaling) {
    case ChainScaling::kBoneDirections:
      return "bone-directions";
    case ChainScaling::kPerChain:
      return "per-chain";
    case ChainScaling::kBodyScale:
      return "body-scale";
  }
  return "unknown";
}

std::optional<ChainScaling> ParseChainScaling(std::string_view name) {
  for (ChainScaling scaling : {ChainScaling::kBoneDirections, ChainScaling::kPerChain, ChainScaling::kBodyScale}) {
    if (name == ChainScalingName(scaling)) return scaling;
  }
  return std::nullopt;
}

std::string_view PointSamplingName(PointSampling sampling) {
  return sampling == PointSampling::kDropNearestEndEffector ? "drop" : "resample";
}

std::optional<PointSampling> ParsePointSampling(std::string_view name) {
  for (PointSampling sampling : {PointSampling::kResampleChains, PointSampling::kDropNearestEndEffector}) {
    if (name == PointSamplingName(sampling)) return sampling;
  }
  return std::nullopt;
}

BodyChains MakeBodyChains(const Skeleton& skeleton, const BodyTopology& topology) {
  BodyChains chains;
  const BodyLandmarks& l = topology.landmarks;
  chains.pelvis = l.pelvis;
  auto top = [&](BodyGroup group) { return topology.group_top[static_cast<int>(group)]; };
  const int chest = skeleton.parent(top(BodyGroup::kLeftArm));
  chains.joints[static_cast<int>(BodyGroup::kSpine)] = ChainBetween(skeleton, l.pelvis, chest >= 0 ? chest : l.pelvis);
  chains.joints[static_cast<int>(BodyGroup::kHead)] = ChainBetween(skeleton, top(BodyGroup::kHead), l.head);
  chains.joints[static_cast<int>(BodyGroup::kLeftArm)] = ChainBetween(skeleton, top(BodyGroup::kLeftArm), l.left_wrist);
  chains.joints[static_cast<int>(BodyGroup::kRightArm)] =
      ChainBetween(skeleton, top(BodyGroup::kRightArm), l.right_wrist);
  chains.joints[static_cast<int>(BodyGroup::kLeftLeg)] = ChainBetween(skeleton, top(BodyGroup::kLeftLeg), l.left_ankle);
  chains.joints[static_cast<int>(BodyGroup::kRightLeg)] =
      ChainBetween(skeleton, top(BodyGroup::kRightLeg), l.right_ankle);
  // An unusable landmark (a rig stored before these were kept has none): the length rules stand in.
  SetLimbSections(l, /*strict=*/false, &chains).IgnoreError();
  return chains;
}

absl::StatusOr<BodyChains> ChainsFromLandmarks(const Skeleton& skeleton, const BodyLandmarks& l) {
  for (int joint : {l.pelvis, l.head, l.left_wrist, l.right_wrist, l.left_ankle, l.right_ankle}) {
    if (joint < 0 || joint >= skeleton.num_joints())
      return absl::InvalidArgumentError("a landmark is not a joint of the pose");
  }
  auto ancestors = [&](int joint) {
    std::vector<int> out;
    for (int j = joint; j >= 0; j = skeleton.parent(j)) out.push_back(j);
    return out;  // joint first, root last
  };
  auto common = [&](int a, int b) {
    const std::vector<int> up_a = ancestors(a);
    for (int j : ancestors(b)) {
      if (std::find(up_a.begin(), up_a.end(), j) != up_a.end()) return j;
    }
    return 0;
  };
  // The chain below `ancestor` down to `end`: its first joint is the child of `ancestor`.
  auto below = [&](int ancestor, int end) -> absl::StatusOr<std::vector<int>> {
    if (end == ancestor)
      return absl::InvalidArgumentError(
          StrCat("joint '", skeleton.joint(end).name, "' cannot be both a limb end and where limbs branch"));
    std::vector<int> chain;
    for (int j = end; j != ancestor; j = skeleton.parent(j)) chain.push_back(j);
    std::reverse(chain.begin(), chain.end());
    return chain;
  };
  BodyChains chains;
  chains.pelvis = l.pelvis;
  const int chest = common(l.left_wrist, l.right_wrist);
  const int hips = common(l.left_ankle, l.right_ankle);
  auto set = [&](BodyGroup group, absl::StatusOr<std::vector<int>> chain) -> absl::Status {
    if (!chain.ok()) return chain.status();
    chains.joints[static_cast<int>(group)] = std::move(*chain);
    return absl::OkStatus();
  };
  for (auto [group, ancestor, end] :
       {std::tuple{BodyGroup::kLeftArm, chest, l.left_wrist}, std::tuple{BodyGroup::kRightArm, chest, l.right_wrist},
        std::tuple{BodyGroup::kLeftLeg, hips, l.left_ankle}, std::tuple{BodyGroup::kRightLeg, hips, l.right_ankle},
        std::tuple{BodyGroup::kHead, common(l.head, l.left_wrist), l.head}}) {
    if (absl::Status status = set(group, below(ancestor, end)); !status.ok()) return status;
  }
  chains.joints[static_cast<int>(BodyGroup::kSpine)] = ChainBetween(skeleton, l.pelvis, chest);
  for (int joint : {l.left_elbow, l.right_elbow, l.left_knee, l.right_knee, l.left_shoulder, l.right_shoulder,
                    l.left_hip, l.right_hip}) {
    if (joint < -1 || joint >= skeleton.num_joints())
      return absl::InvalidArgumentError("a landmark is not a joint of the pose");
  }
  MOCAP_RETURN_IF_ERROR(SetLimbSections(l, /*strict=*/true, &chains));
  return chains;
}

float BodyScale(const GlobalPoses& poses, int frame, const BodyChains& chains) {
  float scale = 0.0f;
  for (BodyGroup leg : {BodyGroup::kLeftLeg, BodyGroup::kRightLeg}) {
    const std::vector<int>& chain = chains.joints[static_cast<int>(leg)];
    for (size_t i = 1; i < chain.size(); ++i) {
      scale += (poses.position(frame, chain[i]) - poses.position(frame, chain[i - 1])).norm();
    }
  }
  return scale > 0 ? 0.5f * scale : 1.0f;
}

namespace {

// Lengths along `chain` from its first joint, in this frame (rotation-invariant), into
// `cumulative`; returns how many joints it covers (the chain, at most Skeleton::kMaxJoints).
size_t CumulativeLengths(const GlobalPoses& poses, int frame, const std::vector<int>& chain,
                         float (&cumulative)[Skeleton::kMaxJoints]) {
  const size_t m = std::min<size_t>(chain.size(), Skeleton::kMaxJoints);
  cumulative[0] = 0.0f;
  for (size_t i = 1; i < m; ++i) {
    cumulative[i] = cumulative[i - 1] + (poses.position(frame, chain[i]) - poses.position(frame, chain[i - 1])).norm();
  }
  return m;
}

// The chain's points in world coordinates (sampled as options.sampling says); returns the
// chain's length along its bones.
float SampleChain(const GlobalPoses& poses, int frame, const std::vector<int>& chain, const BodyPointOptions& options,
                  Eigen::Vector3f* out) {
  const int n = options.points_per_group;
  float cumulative[Skeleton::kMaxJoints];
  const size_t m = CumulativeLengths(poses, frame, chain, cumulative);
  const float length = cumulative[m - 1];
  if (options.sampling == PointSampling::kDropNearestEndEffector || m == 1) {
    // The seed's rule: keep the first n joints, dropping those nearest the end effector; a
    // shorter chain repeats its last joint.
    for (int k = 0; k < n; ++k) out[k] = poses.position(frame, chain[std::min<size_t>(k, m - 1)]);
    return length;
  }
  // Resample at equal fractions of the chain's length.
  size_t segment = 1;
  for (int k = 0; k < n; ++k) {
    const float s = n > 1 ? length * k / (n - 1) : 0.0f;
    while (segment < m - 1 && cumulative[segment] < s) ++segment;
    const float span = cumulative[segment] - cumulative[segment - 1];
    const float u = span > 0 ? std::clamp((s - cumulative[segment - 1]) / span, 0.0f, 1.0f) : 1.0f;
    out[k] = (1 - u) * poses.position(frame, chain[segment - 1]) + u * poses.position(frame, chain[segment]);
  }
  return length;
}

// `v` scaled to unit length; zero when it has none (a bone of zero length has no direction).
Eigen::Vector3f Direction(const Eigen::Vector3f& v) {
  const float norm = v.norm();
  return norm > 1e-8f ? Eigen::Vector3f(v / norm) : Eigen::Vector3f::Zero();
}

// `v` without its part along the unit vector `axis`, as a direction.
Eigen::Vector3f DirectionAcross(const Eigen::Vector3f& v, const Eigen::Vector3f& axis) {
  return Direction(v - axis * axis.dot(v));
}

// n points at equal fractions of the polyline start -> start + a·d1 -> ... + b·d2.
void SampleTwoBones(const Eigen::Vector3f& start, const Eigen::Vector3f& d1, float a, const Eigen::Vector3f& d2,
                    float b, int n, Eigen::Vector3f* out) {
  for (int k = 0; k < n; ++k) {
    const float s = n > 1 ? (a + b) * k / (n - 1) : 0.0f;
    out[k] = s <= a ? Eigen::Vector3f(start + s * d1) : Eigen::Vector3f(start + a * d1 + (s - a) * d2);
  }
}

// The limb's shoulder (hip), elbow (knee) and wrist (ankle) in this frame.
struct LimbJointsInFrame {
  Eigen::Vector3f root, bend, end;
};
LimbJointsInFrame LimbJointsOf(const GlobalPoses& poses, int frame, const std::vector<int>& chain, int root_hint,
                               int bend_hint) {
  float cumulative[Skeleton::kMaxJoints];
  const size_t m = CumulativeLengths(poses, frame, chain, cumulative);
  const std::span<const float> lengths(cumulative, m);
  const int bend = bend_hint > 0 && bend_hint + 1 < static_cast<int>(m) ? bend_hint : LimbBendByLength(lengths);
  const int root =
      root_hint >= 0 && root_hint < bend && bend == bend_hint ? root_hint : UpperSegmentStart(lengths, bend);
  return {poses.position(frame, chain[root]), poses.position(frame, chain[bend]), poses.position(frame, chain[m - 1])};
}

// kBoneDirections (see body_points.h): the pose's joint directions on the canonical body,
// pelvis at the origin. `out` already holds every chain's points sampled in world coordinates
// with their lengths in `lengths` (spine and head keep their own shapes).
void PoseCanonicalBody(const GlobalPoses& poses, int frame, const BodyChains& chains, int n,
                       const std::array<float, kNumBodyGroups>& lengths, Eigen::Vector3f* out) {
  using C = CanonicalBody;
  auto group_points = [&](BodyGroup group) { return out + static_cast<int>(group) * n; };
  auto chain = [&](BodyGroup group) -> const std::vector<int>& { return chains.joints[static_cast<int>(group)]; };
  const Eigen::Vector3f pelvis = poses.position(frame, chains.pelvis);
  const Eigen::Vector3f chest = poses.position(frame, chain(BodyGroup::kSpine).back());
  Eigen::Vector3f torso_up = Direction(chest - pelvis);
  if (torso_up.isZero()) torso_up = Eigen::Vector3f::UnitY();

  // Spine: its own shape at the canonical length, from the pelvis.
  Eigen::Vector3f* spine = group_points(BodyGroup::kSpine);
  const float spine_scale = C::kSpine / std::max(lengths[static_cast<int>(BodyGroup::kSpine)], 1e-6f);
  for (int k = 0; k < n; ++k) spine[k] = (spine[k] - pelvis) * spine_scale;
  const Eigen::Vector3f canonical_chest = (chest - pelvis) * spine_scale;

  // Head: its own shape at the canonical length, from a neck above the chest along the torso.
  Eigen::Vector3f* head = group_points(BodyGroup::kHead);
  const Eigen::Vector3f neck = head[0];
  const float head_length = lengths[static_cast<int>(BodyGroup::kHead)];
  const Eigen::Vector3f canonical_neck = canonical_chest + C::kNeck * torso_up;
  for (int k = 0; k < n; ++k) {
    head[k] = head_length > 1e-6f ? Eigen::Vector3f(canonical_neck + (head[k] - neck) * (C::kHead / head_length))
                                  : canonical_neck;
  }

  // Limbs: two bones each, hung from the body's shoulder / hip line at canonical widths.
  struct Pair {
    BodyGroup left, right;
    Eigen::Vector3f anchor;
    float half_width, upper, lower;
  };
  for (const Pair& pair :
       {Pair{BodyGroup::kLeftArm, BodyGroup::kRightArm, canonical_chest, C::kHalfShoulders, C::kUpperArm, C::kForearm},
        Pair{BodyGroup::kLeftLeg, BodyGroup::kRightLeg, Eigen::Vector3f::Zero(), C::kHalfHips, C::kThigh, C::kShin}}) {
    const int left_group = static_cast<int>(pair.left), right_group = static_cast<int>(pair.right);
    const LimbJointsInFrame left =
        LimbJointsOf(poses, frame, chain(pair.left), chains.root[left_group], chains.bend[left_group]);
    const LimbJointsInFrame right =
        LimbJointsOf(poses, frame, chain(pair.right), chains.root[right_group], chains.bend[right_group]);
    // The line between the two roots, across the torso: the body's own twist and lean.
    Eigen::Vector3f across = DirectionAcross(left.root - right.root, torso_up);
    if (across.isZero()) across = DirectionAcross(Eigen::Vector3f::UnitX(), torso_up);
    for (auto [group, joints, side] : {std::tuple{pair.left, &left, 1.0f}, std::tuple{pair.right, &right, -1.0f}}) {
      SampleTwoBones(pair.anchor + side * pair.half_width * across, Direction(joints->bend - joints->root), pair.upper,
                     Direction(joints->end - joints->bend), pair.lower, n, group_points(group));
    }
  }
}

}  // namespace

void BodyPointsOfFrame(const GlobalPoses& poses, int frame, const BodyChains& chains, const BodyPointOptions& options,
                       Eigen::Vector3f* out) {
  const int n = options.points_per_group;
  const Eigen::Vector3f pelvis = poses.position(frame, chains.pelvis);
  std::array<float, kNumBodyGroups> lengths{};
  for (int g = 0; g < kNumBodyGroups; ++g)
    lengths[g] = SampleChain(poses, frame, chains.joints[g], options, out + g * n);

  if (options.scaling == ChainScaling::kBodyScale) {
    const float inverse = 1.0f / BodyScale(poses, frame, chains);
    for (int i = 0; i < kNumBodyGroups * n; ++i) out[i] = (out[i] - pelvis) * inverse;
    return;
  }
  if (options.scaling == ChainScaling::kBoneDirections) {
    PoseCanonicalBody(poses, frame, chains, n, lengths, out);
    return;
  }
  // Per chain: the chain's shape relative to where it hangs, in its own lengths, re-assembled at
  // the canonical proportions. Legs and spine hang from the pelvis, arms and head from the
  // spine's end (the chest, where the arms branch off).
  const std::vector<int>& spine = chains.joints[static_cast<int>(BodyGroup::kSpine)];
  const Eigen::Vector3f chest = poses.position(frame, spine.back());
  const float spine_scale = kCanonicalChainLengths[static_cast<int>(BodyGroup::kSpine)] /
                            std::max(lengths[static_cast<int>(BodyGroup::kSpine)], 1e-6f);
  const Eigen::Vector3f canonical_chest = (chest - pelvis) * spine_scale;
  for (int g = 0; g < kNumBodyGroups; ++g) {
    const BodyGroup group = static_cast<BodyGroup>(g);
    const bool from_chest = group == BodyGroup::kHead || group == BodyGroup::kLeftArm || group == BodyGroup::kRightArm;
    const Eigen::Vector3f& anchor = from_chest ? chest : pelvis;
    const Eigen::Vector3f canonical_anchor = from_chest ? canonical_chest : Eigen::Vector3f::Zero();
    // A chain of one joint has no length: the body's leg length stands in.
    const float length = lengths[g] > 1e-6f ? lengths[g] : BodyScale(poses, frame, chains);
    const float scale = kCanonicalChainLengths[g] / length;
    for (int k = 0; k < n; ++k) out[g * n + k] = canonical_anchor + (out[g * n + k] - anchor) * scale;
  }
}

BodyPointMatrix BodyPointsOfClip(const GlobalPoses& poses, const BodyChains& chains, const BodyPointOptions& options) {
  const int points = kNumBodyGroups * options.points_per_group;
  BodyPointMatrix out(poses.num_frames(), points * 3);
  for (int f = 0; f < poses.num_frames(); ++f) {
    BodyPointsOfFrame(poses, f, chains, options, reinterpret_cast<Eigen::Vector3f*>(out.row(f).data()));
  }
  return out;
}

}  // namespace mocap

#include "motion/skeleton/body_topology.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "motion/core/str_cat.h"
#include "motion/skeleton/forward_kinematics.h"

namespace mocap {
namespace {

// Bones shorter than this fraction of the longest root-to-leaf path are helper joints (zero-length
// "pelvis", twist roots, share bones): merged into their parent for the branching analysis.
constexpr float kCollapseFraction = 0.02f;
// A leaf chain whose joints stay within this fraction of a sibling bone's length from that bone
// (in the clip's frames) is a twist/share overlay, not a limb.
constexpr float kOverlayDistanceFraction = 0.1f;
constexpr int kMaxFramesSampled = 240;

class TreeMetric {
 public:
  TreeMetric(const Skeleton& skeleton, const Eigen::VectorXf& bone) : skeleton_(skeleton) {
    const int joints = skeleton.num_joints();
    path_length_.assign(joints, 0.0f);
    depth_.assign(joints, 0);
    for (int j = 1; j < joints; ++j) {
      path_length_[j] = path_length_[skeleton.parent(j)] + bone[j];
      depth_[j] = depth_[skeleton.parent(j)] + 1;
    }
  }
  int Lca(int a, int b) const {
    while (depth_[a] > depth_[b]) a = skeleton_.parent(a);
    while (depth_[b] > depth_[a]) b = skeleton_.parent(b);
    while (a != b) {
      a = skeleton_.parent(a);
      b = skeleton_.parent(b);
    }
    return a;
  }
  float Distance(int a, int b) const { return path_length_[a] + path_length_[b] - 2 * path_length_[Lca(a, b)]; }
  float path_length(int j) const { return path_length_[j]; }
  // The child of `ancestor` on the path down to `descendant`.
  int ChildToward(int ancestor, int descendant) const {
    while (skeleton_.parent(descendant) != ancestor) descendant = skeleton_.parent(descendant);
    return descendant;
  }
  // Joints from `top` down to `end`, inclusive.
  std::vector<int> Path(int top, int end) const {
    std::vector<int> path;
    for (int j = end; j != top; j = skeleton_.parent(j)) path.push_back(j);
    path.push_back(top);
    std::reverse(path.begin(), path.end());
    return path;
  }

 private:
  const Skeleton& skeleton_;
  std::vector<float> path_length_;
  std::vector<int> depth_;
};

std::vector<int> SampleFrames(int frames) {
  std::vector<int> sample;
  const int count = std::min(frames, kMaxFramesSampled);
  for (int i = 0; i < count; ++i) sample.push_back(static_cast<int>(static_cast<long long>(i) * frames / count));
  return sample;
}

float PointSegmentDistance(const Eigen::Vector3f& p, const Eigen::Vector3f& a, const Eigen::Vector3f& b,
                           float* along) {
  const Eigen::Vector3f ab = b - a;
  const float length_sq = ab.squaredNorm();
  const float t = length_sq > 0 ? (p - a).dot(ab) / length_sq : 0.0f;
  *along = t;
  return (p - (a + std::clamp(t, 0.0f, 1.0f) * ab)).norm();
}

void AxisOf(const Eigen::Vector3f& direction, int* axis, int* sign, float* alignment) {
  Eigen::Index index;
  direction.cwiseAbs().maxCoeff(&index);
  *axis = static_cast<int>(index);
  *sign = direction[index] >= 0 ? 1 : -1;
  const float norm = direction.norm();
  *alignment = norm > 0 ? std::abs(direction[index]) / norm : 0.0f;
}

}  // namespace

std::string_view BodyGroupName(BodyGroup group) {
  switch (group) {
    case BodyGroup::kSpine: return "spine";
    case BodyGroup::kHead: return "head";
    case BodyGroup::kLeftArm: return "left_arm";
    case BodyGroup::kRightArm: return "right_arm";
    case BodyGroup::kLeftLeg: return "left_leg";
    case BodyGroup::kRightLeg: return "right_leg";
  }
  return "?";
}

int BodyTopology::group_size(BodyGroup group) const {
  return static_cast<int>(std::count(group_of_joint.begin(), group_of_joint.end(), group));
}

absl::StatusOr<BodyTopology> AnalyseBody(const Skeleton& skeleton, const LocalMotion& motion,
                                         const BodyTopologyOptions& options) {
  const int joints = skeleton.num_joints();
  if (motion.num_joints() != joints || motion.num_frames() < 1) {
    return absl::InvalidArgumentError("motion does not match the skeleton");
  }
  const GlobalPoses poses = ForwardKinematics(skeleton, motion);
  const std::vector<int> frames = SampleFrames(motion.num_frames());

  // 1. Bone lengths; joints whose translation moves over the clip (a root-like joint carrying the
  //    motion, as Bandai's Hips under joint_Root) have no bone.
  Eigen::VectorXf bone = BoneLengths(motion);
  bone[0] = 0.0f;
  for (int j = 1; j < joints; ++j) {
    const float range = std::max({motion.tx.col(j).maxCoeff() - motion.tx.col(j).minCoeff(),
                                  motion.ty.col(j).maxCoeff() - motion.ty.col(j).minCoeff(),
                                  motion.tz.col(j).maxCoeff() - motion.tz.col(j).minCoeff()});
    if (range > 1e-3f * (1.0f + bone[j])) bone[j] = 0.0f;
  }
  const TreeMetric metric(skeleton, bone);
  std::vector<std::vector<int>> children(joints);
  for (int j = 1; j < joints; ++j) children[skeleton.parent(j)].push_back(j);
  // Body size: half the tree's diameter (double sweep), so a long static stem above the hips
  // (an extra root node) does not count.
  float body_size = 0.0f;
  {
    int far = 0;
    for (int j = 0; j < joints; ++j) {
      if (metric.Distance(0, j) > metric.Distance(0, far)) far = j;
    }
    for (int j = 0; j < joints; ++j) body_size = std::max(body_size, 0.5f * metric.Distance(far, j));
  }
  if (body_size <= 0.0f) return absl::FailedPreconditionError("skeleton has no bones of non-zero length");

  std::vector<int> representative(joints, 0);
  std::vector<std::vector<int>> virtual_children(joints);
  for (int j = 1; j < joints; ++j) {
    const bool collapsed = bone[j] < kCollapseFraction * body_size;
    representative[j] = collapsed ? representative[skeleton.parent(j)] : j;
    if (!collapsed) virtual_children[representative[skeleton.parent(j)]].push_back(j);
  }
  auto position = [&](int frame, int joint) { return poses.position(frame, joint); };

  // Leaf chains lying along a sibling bone (twist and share bones) are ignored.
  std::vector<bool> ignored(joints, false);
  for (int v = 0; v < joints; ++v) {
    const std::vector<int>& kids = virtual_children[v];
    if (kids.size() < 2) continue;
    for (int chain_top : kids) {
      std::vector<int> chain = {chain_top};
      while (virtual_children[chain.back()].size() == 1) chain.push_back(virtual_children[chain.back()][0]);
      if (!virtual_children[chain.back()].empty()) continue;  // branches further: not an overlay
      for (int sibling : kids) {
        if (sibling == chain_top || ignored[sibling]) continue;  // of two duplicates, keep one
        float worst = 0.0f;
        bool inside = true;
        float sibling_length = 0.0f;
        for (int joint : chain) {
          float mean_distance = 0.0f;
          for (int f : frames) {
            float along;
            // From the sibling's real parent: the virtual node may stand for a collapsed joint
            // elsewhere (e.g. a static root above moving hips).
            const Eigen::Vector3f a = position(f, skeleton.parent(sibling)), b = position(f, sibling);
            sibling_length = std::max(sibling_length, (b - a).norm());
            mean_distance += PointSegmentDistance(position(f, joint), a, b, &along);
            if (along < -0.1f || along > 1.1f) inside = false;
          }
          worst = std::max(worst, mean_distance / frames.size());
        }
        if (inside && sibling_length > 0 && worst < kOverlayDistanceFraction * sibling_length) {
          for (int joint : chain) ignored[joint] = true;
          break;
        }
      }
    }
  }
  std::vector<int> leaves;
  for (int j = 1; j < joints; ++j) {
    if (representative[j] == j && virtual_children[j].empty() && !ignored[j]) leaves.push_back(j);
  }
  if (leaves.size() < 5) {
    return absl::FailedPreconditionError(
        StrCat("not a humanoid rig: found ", leaves.size(),
               " limb ends; two arms, two legs and a head need five"));
  }

  // 2. Farthest-point sampling of the five limb ends.
  std::vector<int> tips;
  tips.push_back(*std::max_element(leaves.begin(), leaves.end(), [&](int a, int b) {
    return metric.path_length(a) < metric.path_length(b);
  }));
  while (tips.size() < 5) {
    int best = -1;
    float best_distance = -1.0f;
    for (int leaf : leaves) {
      float nearest = std::numeric_limits<float>::infinity();
      for (int tip : tips) nearest = std::min(nearest, metric.Distance(leaf, tip));
      if (nearest > best_distance) {
        best_distance = nearest;
        best = leaf;
      }
    }
    tips.push_back(best);
  }

  // 3. Head, pairs, arms vs legs.
  std::vector<int> attach(5);
  std::vector<float> limb_length(5);
  for (int i = 0; i < 5; ++i) {
    int deepest = 0;
    for (int k = 0; k < 5; ++k) {
      if (k == i) continue;
      const int lca = metric.Lca(tips[i], tips[k]);
      if (metric.path_length(lca) > metric.path_length(deepest) ||
          (metric.path_length(lca) == metric.path_length(deepest) && lca > deepest)) {
        deepest = lca;
      }
    }
    attach[i] = deepest;
    limb_length[i] = metric.path_length(tips[i]) - metric.path_length(deepest);
  }
  const int head_index = static_cast<int>(std::min_element(limb_length.begin(), limb_length.end()) - limb_length.begin());
  std::vector<int> limbs;
  for (int i = 0; i < 5; ++i) {
    if (i != head_index) limbs.push_back(i);
  }
  // Pair the four limbs so that each pair's common ancestor is as deep as possible.
  const int pairings[3][4] = {{0, 1, 2, 3}, {0, 2, 1, 3}, {0, 3, 1, 2}};
  float best_score = -1.0f;
  std::array<int, 4> paired{};
  for (const auto& p : pairings) {
    const float score = metric.path_length(metric.Lca(tips[limbs[p[0]]], tips[limbs[p[1]]])) +
                        metric.path_length(metric.Lca(tips[limbs[p[2]]], tips[limbs[p[3]]]));
    if (score > best_score) {
      best_score = score;
      paired = {limbs[p[0]], limbs[p[1]], limbs[p[2]], limbs[p[3]]};
    }
  }
  const int head_tip = tips[head_index];
  const float first_to_head = metric.path_length(metric.Lca(head_tip, tips[paired[0]]));
  const float second_to_head = metric.path_length(metric.Lca(head_tip, tips[paired[2]]));

  BodyTopology topology;
  const int pelvis = metric.Lca(metric.Lca(tips[paired[0]], tips[paired[2]]), head_tip);
  topology.landmarks.pelvis = pelvis;

  // 4. Up axis from the frames: pelvis -> head end.
  Eigen::Vector3f body_axis = Eigen::Vector3f::Zero();
  for (int f : frames) body_axis += (position(f, head_tip) - position(f, pelvis)).normalized();
  AxisOf(body_axis, &topology.up_axis, &topology.up_sign, &topology.up_alignment);
  {
    const GlobalPoses rest = ForwardKinematics(skeleton, RestMotion(skeleton));
    float unused;
    AxisOf(rest.position(0, head_tip) - rest.position(0, pelvis), &topology.rest_up_axis, &topology.rest_up_sign,
           &unused);
  }
  const Eigen::Vector3f up = topology.up();
  auto height = [&](int frame, int joint) { return position(frame, joint).dot(up); };

  // Arms branch off closer to the head; when the tree cannot tell (a star rig), legs are lower.
  bool first_pair_is_arms;
  if (first_to_head != second_to_head) {
    first_pair_is_arms = first_to_head > second_to_head;
  } else {
    float first_height = 0.0f, second_height = 0.0f;
    for (int f : frames) {
      first_height += height(f, tips[paired[0]]) + height(f, tips[paired[1]]);
      second_height += height(f, tips[paired[2]]) + height(f, tips[paired[3]]);
    }
    first_pair_is_arms = first_height > second_height;
  }
  const std::array<int, 2> arm_tips = first_pair_is_arms ? std::array{tips[paired[0]], tips[paired[1]]}
                                                         : std::array{tips[paired[2]], tips[paired[3]]};
  const std::array<int, 2> leg_tips = first_pair_is_arms ? std::array{tips[paired[2]], tips[paired[3]]}
                                                         : std::array{tips[paired[0]], tips[paired[1]]};
  auto attach_of = [&](int tip) { return attach[std::find(tips.begin(), tips.end(), tip) - tips.begin()]; };

  // 5. Landmarks on limb chains: the distal end of the more distal of the two longest bones.
  auto limb_joint = [&](int tip, int* joint_out, int* middle_out) -> absl::Status {
    const int top = metric.ChildToward(attach_of(tip), tip);
    const std::vector<int> path = metric.Path(top, tip);
    if (path.size() < 3) {
      return absl::FailedPreconditionError(
          StrCat("limb starting at '", skeleton.joint(top).name, "' has fewer than two bones"));
    }
    // Segments between the joints where the chain really bends: a joint with one child that keeps
    // its two bones in line in every frame (a split bone, a roll joint) does not end a segment.
    // With too few frames to tell, every joint ends one.
    std::vector<int> segment_end;       // index into path
    std::vector<float> segment_length;
    float running = 0.0f;
    for (size_t i = 1; i < path.size(); ++i) {
      running += bone[path[i]];
      bool straight_through = false;
      if (i + 1 < path.size() && frames.size() >= 10 && children[path[i]].size() == 1) {
        straight_through = true;
        for (int f : frames) {
          const Eigen::Vector3f in = position(f, path[i]) - position(f, path[i - 1]);
          const Eigen::Vector3f out = position(f, path[i + 1]) - position(f, path[i]);
          if (in.norm() < 1e-6f || out.norm() < 1e-6f) continue;
          // A split bone stays in line to rounding; a real joint held straight still wobbles.
          if (in.normalized().dot(out.normalized()) < std::cos(0.035f)) {  // bends by more than 2 deg
            straight_through = false;
            break;
          }
        }
      }
      if (!straight_through) {
        segment_end.push_back(static_cast<int>(i));
        segment_length.push_back(running);
        running = 0.0f;
      }
    }
    if (segment_end.size() < 2) {
      return absl::FailedPreconditionError(
          StrCat("limb starting at '", skeleton.joint(top).name, "' does not bend: fewer than two segments"));
    }
    std::vector<int> order(segment_end.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return segment_length[a] > segment_length[b]; });
    *joint_out = path[segment_end[std::max(order[0], order[1])]];
    *middle_out = path[segment_end[std::min(order[0], order[1])]];  // elbow / knee
    return absl::OkStatus();
  };
  std::array<int, 2> wrists{}, ankles{}, elbows{}, knees{};
  for (int i = 0; i < 2; ++i) {
    if (auto s = limb_joint(arm_tips[i], &wrists[i], &elbows[i]); !s.ok()) return s;
    if (auto s = limb_joint(leg_tips[i], &ankles[i], &knees[i]); !s.ok()) return s;
  }

  // Forward: ankle -> next joint toward the toes, on the ground plane; else the travel direction.
  auto horizontal = [&](const Eigen::Vector3f& v) -> Eigen::Vector3f { return v - up * v.dot(up); };
  // Two anatomical cues, summed unnormalised so that strong frames weigh more: knees bend forward
  // (knee minus its projection on the hip-ankle line), and toes point forward from the ankle in
  // stance (only frames where the toe is near its lowest: a foot kicked back in a run points its
  // toes backwards).
  Eigen::Vector3f forward = Eigen::Vector3f::Zero();
  for (int i = 0; i < 2; ++i) {
    const int hip = metric.ChildToward(attach_of(leg_tips[i]), leg_tips[i]);
    for (int f : frames) {
      float along;
      const Eigen::Vector3f a = position(f, hip), b = position(f, ankles[i]), k = position(f, knees[i]);
      PointSegmentDistance(k, a, b, &along);
      forward += horizontal(k - (a + along * (b - a)));
    }
  }
  float foot_length = 0.0f;
  for (int i = 0; i < 2; ++i) {
    if (ankles[i] == leg_tips[i]) continue;
    const int toe = metric.ChildToward(ankles[i], leg_tips[i]);
    float lowest_toe = std::numeric_limits<float>::infinity();
    for (int f : frames) lowest_toe = std::min(lowest_toe, height(f, toe));
    for (int f : frames) {
      const Eigen::Vector3f foot = position(f, toe) - position(f, ankles[i]);
      foot_length = std::max(foot_length, foot.norm());
      if (height(f, toe) < lowest_toe + 0.05f * body_size) forward += horizontal(foot);
    }
  }
  if (forward.norm() < 0.1f * std::max(foot_length, 0.05f * body_size)) {
    forward = horizontal(position(motion.num_frames() - 1, pelvis) - position(0, pelvis));
    if (forward.norm() < 0.05f * body_size) {
      return absl::FailedPreconditionError(
          "cannot tell left from right: the feet have no toe joints and the clip does not travel");
    }
  }
  topology.forward = forward.normalized();
  const Eigen::Vector3f left = up.cross(topology.forward);

  auto lateral = [&](int tip) {
    const int a = attach_of(tip);
    const int top = metric.ChildToward(a, tip);
    float sum = 0.0f;
    for (int f : frames) sum += (position(f, top) - position(f, a)).dot(left);
    return sum;
  };
  const bool arm0_left = lateral(arm_tips[0]) > lateral(arm_tips[1]);
  const bool leg0_left = lateral(leg_tips[0]) > lateral(leg_tips[1]);
  topology.landmarks.left_wrist = wrists[arm0_left ? 0 : 1];
  topology.landmarks.right_wrist = wrists[arm0_left ? 1 : 0];
  topology.landmarks.left_ankle = ankles[leg0_left ? 0 : 1];
  topology.landmarks.right_ankle = ankles[leg0_left ? 1 : 0];
  topology.landmarks.left_elbow = elbows[arm0_left ? 0 : 1];
  topology.landmarks.right_elbow = elbows[arm0_left ? 1 : 0];
  topology.landmarks.left_knee = knees[leg0_left ? 0 : 1];
  topology.landmarks.right_knee = knees[leg0_left ? 1 : 0];

  // Head landmark: the first branching joint on the head chain, else its end.
  {
    const int top = metric.ChildToward(attach_of(head_tip), head_tip);
    topology.landmarks.head = head_tip;
    for (int j : metric.Path(top, head_tip)) {
      if (representative[j] == j && virtual_children[j].size() >= 2) {
        topology.landmarks.head = j;
        break;
      }
    }
  }

  // Groups: the subtree of each limb's top joint; everything else is spine.
  topology.group_of_joint.assign(joints, BodyGroup::kSpine);
  topology.group_top.fill(0);
  topology.group_end.fill(0);
  auto assign = [&](int tip, BodyGroup group) {
    const int top = metric.ChildToward(attach_of(tip), tip);
    topology.group_top[static_cast<int>(group)] = top;
    topology.group_end[static_cast<int>(group)] = tip;
    for (int j = top; j < joints; ++j) {
      int a = j;
      while (a > top) a = skeleton.parent(a);
      if (a == top) topology.group_of_joint[j] = group;
    }
  };
  assign(head_tip, BodyGroup::kHead);
  assign(arm_tips[arm0_left ? 0 : 1], BodyGroup::kLeftArm);
  assign(arm_tips[arm0_left ? 1 : 0], BodyGroup::kRightArm);
  assign(leg_tips[leg0_left ? 0 : 1], BodyGroup::kLeftLeg);
  assign(leg_tips[leg0_left ? 1 : 0], BodyGroup::kRightLeg);
  topology.group_end[static_cast<int>(BodyGroup::kSpine)] = pelvis;

  // Sizes and units.
  float leg_sum = 0.0f;
  for (int i = 0; i < 2; ++i) {
    const int top = metric.ChildToward(attach_of(leg_tips[i]), leg_tips[i]);
    for (int j : metric.Path(top, ankles[i])) {
      if (j != top) leg_sum += bone[j];
    }
  }
  topology.leg_length = leg_sum / 2;
  std::vector<float> pelvis_heights;
  float floor = std::numeric_limits<float>::infinity();
  // Lowest point per frame over the leg groups (a static node above the hips, as Bandai's
  // joint_Root at the origin, must not count as the floor).
  std::vector<int> leg_joints;
  for (int j = 0; j < joints; ++j) {
    if (topology.group_of_joint[j] == BodyGroup::kLeftLeg || topology.group_of_joint[j] == BodyGroup::kRightLeg) {
      leg_joints.push_back(j);
    }
  }
  for (int f = 0; f < motion.num_frames(); ++f) {
    float lowest = std::numeric_limits<float>::infinity();
    for (int j : leg_joints) lowest = std::min(lowest, height(f, j));
    floor = std::min(floor, lowest);
    pelvis_heights.push_back(height(f, pelvis) - lowest);
  }
  std::nth_element(pelvis_heights.begin(), pelvis_heights.begin() + pelvis_heights.size() / 2, pelvis_heights.end());
  topology.standing_pelvis_height = pelvis_heights[pelvis_heights.size() / 2];
  topology.floor_height = floor;
  topology.unit_detected = !options.unit.has_value();
  topology.unit = options.unit ? *options.unit : DetectUnitFromLegLength(topology.leg_length);
  return topology;
}

}  // namespace mocap

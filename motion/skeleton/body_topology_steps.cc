#include "motion/skeleton/body_topology_steps.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>

#include "motion/core/str_cat.h"

namespace mocap::body_topology {
namespace {

// Distance from `p` to the segment a-b; `along` receives the unclamped position of p's projection
// on the line (0 at a, 1 at b).
float PointSegmentDistance(const Eigen::Vector3f& p, const Eigen::Vector3f& a, const Eigen::Vector3f& b, float* along) {
  const Eigen::Vector3f ab = b - a;
  const float length_sq = ab.squaredNorm();
  const float t = length_sq > 0 ? (p - a).dot(ab) / length_sq : 0.0f;
  *along = t;
  return (p - (a + std::clamp(t, 0.0f, 1.0f) * ab)).norm();
}

// The chain of kept joints from `top` down to the merged tree's leaf below it, or empty when the
// chain branches further.
std::vector<int> LeafChain(const MergedTree& tree, int top) {
  std::vector<int> chain = {top};
  while (tree.children[chain.back()].size() == 1) chain.push_back(tree.children[chain.back()][0]);
  if (!tree.children[chain.back()].empty()) return {};
  return chain;
}

// True when every joint of `chain` stays along the bone into `sibling` over the sampled frames.
bool LiesAlongBone(const Skeleton& skeleton, const std::vector<int>& chain, int sibling, const GlobalPoses& poses,
                   const std::vector<int>& frames) {
  float worst = 0.0f;
  bool inside = true;
  float sibling_length = 0.0f;
  for (int joint : chain) {
    float mean_distance = 0.0f;
    for (int f : frames) {
      float along;
      // From the sibling's real parent: the merged node may stand for a collapsed joint elsewhere
      // (e.g. a static root above moving hips).
      const Eigen::Vector3f a = poses.position(f, skeleton.parent(sibling)), b = poses.position(f, sibling);
      sibling_length = std::max(sibling_length, (b - a).norm());
      mean_distance += PointSegmentDistance(poses.position(f, joint), a, b, &along);
      if (along < -0.1f || along > 1.1f) inside = false;
    }
    worst = std::max(worst, mean_distance / frames.size());
  }
  return inside && sibling_length > 0 && worst < kOverlayDistanceFraction * sibling_length;
}

// True when joint `i` of `path` (neither end) keeps its bones in and out within 2 degrees of
// straight in every sampled frame: a split bone stays in line to rounding, a real joint held
// straight still wobbles.
bool StaysStraight(const std::vector<int>& path, size_t i, const GlobalPoses& poses, const std::vector<int>& frames) {
  for (int f : frames) {
    const Eigen::Vector3f in = poses.position(f, path[i]) - poses.position(f, path[i - 1]);
    const Eigen::Vector3f out = poses.position(f, path[i + 1]) - poses.position(f, path[i]);
    if (in.norm() < 1e-6f || out.norm() < 1e-6f) continue;
    if (in.normalized().dot(out.normalized()) < std::cos(0.035f)) return false;  // bends by more than 2 deg
  }
  return true;
}

}  // namespace

TreeMetric::TreeMetric(const Skeleton& skeleton, const Eigen::VectorXf& bone) : skeleton_(skeleton) {
  const int joints = skeleton.num_joints();
  path_length_.assign(joints, 0.0f);
  depth_.assign(joints, 0);
  for (int j = 1; j < joints; ++j) {
    path_length_[j] = path_length_[skeleton.parent(j)] + bone[j];
    depth_[j] = depth_[skeleton.parent(j)] + 1;
  }
}

int TreeMetric::Lca(int a, int b) const {
  while (depth_[a] > depth_[b]) a = skeleton_.parent(a);
  while (depth_[b] > depth_[a]) b = skeleton_.parent(b);
  while (a != b) {
    a = skeleton_.parent(a);
    b = skeleton_.parent(b);
  }
  return a;
}

int TreeMetric::ChildToward(int ancestor, int descendant) const {
  while (skeleton_.parent(descendant) != ancestor) descendant = skeleton_.parent(descendant);
  return descendant;
}

std::vector<int> TreeMetric::Path(int top, int end) const {
  std::vector<int> path;
  for (int j = end; j != top; j = skeleton_.parent(j)) path.push_back(j);
  path.push_back(top);
  std::reverse(path.begin(), path.end());
  return path;
}

std::vector<int> SampleFrames(int frames) {
  std::vector<int> sample;
  const int count = std::min(frames, kMaxFramesSampled);
  for (int i = 0; i < count; ++i) sample.push_back(static_cast<int>(static_cast<long long>(i) * frames / count));
  return sample;
}

float MeanDistance(const GlobalPoses& poses, const std::vector<int>& frames, int a, int b) {
  if (frames.empty()) return 0.0f;
  float sum = 0.0f;
  for (int f : frames) sum += (poses.position(f, a) - poses.position(f, b)).norm();
  return sum / static_cast<float>(frames.size());
}

Eigen::VectorXf StaticBoneLengths(const LocalMotion& motion) {
  Eigen::VectorXf bone = BoneLengths(motion);
  bone[0] = 0.0f;
  for (int j = 1; j < motion.num_joints(); ++j) {
    const float range = std::max({motion.tx.col(j).maxCoeff() - motion.tx.col(j).minCoeff(),
                                  motion.ty.col(j).maxCoeff() - motion.ty.col(j).minCoeff(),
                                  motion.tz.col(j).maxCoeff() - motion.tz.col(j).minCoeff()});
    // Relative tolerance: rounding in the file's position channels is not motion.
    if (range > 1e-3f * (1.0f + bone[j])) bone[j] = 0.0f;
  }
  return bone;
}

float BodySize(const TreeMetric& metric) {
  const int joints = metric.num_joints();
  int far = 0;
  for (int j = 0; j < joints; ++j) {
    if (metric.Distance(0, j) > metric.Distance(0, far)) far = j;
  }
  float body_size = 0.0f;
  for (int j = 0; j < joints; ++j) body_size = std::max(body_size, 0.5f * metric.Distance(far, j));
  return body_size;
}

MergedTree MergeShortBones(const Skeleton& skeleton, const Eigen::VectorXf& bone, float body_size) {
  const int joints = skeleton.num_joints();
  MergedTree tree;
  tree.representative.assign(joints, 0);
  tree.children.assign(joints, {});
  for (int j = 1; j < joints; ++j) {
    const bool collapsed = bone[j] < kCollapseFraction * body_size;
    tree.representative[j] = collapsed ? tree.representative[skeleton.parent(j)] : j;
    if (!collapsed) tree.children[tree.representative[skeleton.parent(j)]].push_back(j);
  }
  return tree;
}

std::vector<bool> FindOverlayChains(const Skeleton& skeleton, const MergedTree& tree, const GlobalPoses& poses,
                                    const std::vector<int>& frames) {
  const int joints = skeleton.num_joints();
  std::vector<bool> overlay(joints, false);
  for (int v = 0; v < joints; ++v) {
    const std::vector<int>& kids = tree.children[v];
    if (kids.size() < 2) continue;
    for (int chain_top : kids) {
      const std::vector<int> chain = LeafChain(tree, chain_top);
      if (chain.empty()) continue;  // branches further: not an overlay
      for (int sibling : kids) {
        if (sibling == chain_top || overlay[sibling]) continue;  // of two duplicates, keep one
        if (LiesAlongBone(skeleton, chain, sibling, poses, frames)) {
          for (int joint : chain) overlay[joint] = true;
          break;
        }
      }
    }
  }
  return overlay;
}

std::vector<int> LimbEndCandidates(const MergedTree& tree, const std::vector<bool>& overlay) {
  std::vector<int> leaves;
  for (int j = 1; j < static_cast<int>(tree.representative.size()); ++j) {
    if (tree.representative[j] == j && tree.children[j].empty() && !overlay[j]) leaves.push_back(j);
  }
  return leaves;
}

std::array<int, 5> PickLimbEnds(const std::vector<int>& candidates, const TreeMetric& metric) {
  std::array<int, 5> ends{};
  ends[0] = *std::max_element(candidates.begin(), candidates.end(),
                              [&](int a, int b) { return metric.path_length(a) < metric.path_length(b); });
  for (size_t picked = 1; picked < ends.size(); ++picked) {
    int best = -1;
    float best_distance = -1.0f;
    for (int leaf : candidates) {
      float nearest = std::numeric_limits<float>::infinity();
      for (size_t i = 0; i < picked; ++i) nearest = std::min(nearest, metric.Distance(leaf, ends[i]));
      if (nearest > best_distance) {
        best_distance = nearest;
        best = leaf;
      }
    }
    ends[picked] = best;
  }
  return ends;
}

std::optional<int> ExtraLimb(const std::vector<int>& candidates, const std::array<int, 5>& ends,
                             const TreeMetric& metric) {
  // A leaf's branch: its distance to the nearest path between two of the ends (in a tree, the
  // distance from c to the path a–b is (|ca| + |cb| − |ab|) / 2), skipping end `skip`.
  auto branch = [&](int leaf, int skip) {
    float shortest = std::numeric_limits<float>::infinity();
    for (int i = 0; i < 5; ++i) {
      for (int j = i + 1; j < 5; ++j) {
        if (i == skip || j == skip) continue;
        shortest = std::min(shortest, 0.5f * (metric.Distance(leaf, ends[i]) + metric.Distance(leaf, ends[j]) -
                                              metric.Distance(ends[i], ends[j])));
      }
    }
    return shortest;
  };
  std::array<float, 5> limb{};
  for (int k = 0; k < 5; ++k) limb[k] = branch(ends[k], k);
  std::sort(limb.begin(), limb.end());
  const float shortest_limb = limb[1];  // limb[0] is the head's (neck and head): the shortest
  std::optional<int> extra;
  float longest = kExtraLimbFraction * shortest_limb;
  for (int leaf : candidates) {
    if (std::find(ends.begin(), ends.end(), leaf) != ends.end()) continue;
    if (const float length = branch(leaf, -1); length >= longest) {
      longest = length;
      extra = leaf;
    }
  }
  return extra;
}

HeadAndPairs FindHeadAndPairs(const std::array<int, 5>& ends, const TreeMetric& metric) {
  std::array<Limb, 5> limbs;
  std::array<float, 5> limb_length{};
  for (int i = 0; i < 5; ++i) {
    int deepest = 0;
    for (int k = 0; k < 5; ++k) {
      if (k == i) continue;
      const int lca = metric.Lca(ends[i], ends[k]);
      // Ties (joints merged by zero-length bones): the later joint, the one nearer the limb.
      if (metric.path_length(lca) > metric.path_length(deepest) ||
          (metric.path_length(lca) == metric.path_length(deepest) && lca > deepest)) {
        deepest = lca;
      }
    }
    limbs[i] = Limb{.branch = deepest, .top = metric.ChildToward(deepest, ends[i]), .end = ends[i]};
    limb_length[i] = metric.path_length(ends[i]) - metric.path_length(deepest);
  }
  const int head_index =
      static_cast<int>(std::min_element(limb_length.begin(), limb_length.end()) - limb_length.begin());
  std::array<int, 4> others{};
  for (int i = 0, n = 0; i < 5; ++i) {
    if (i != head_index) others[n++] = i;
  }
  // The three ways to split four limbs into two pairs; the score is the depth of both pairs'
  // common ancestors (ties: the earlier split).
  const int pairings[3][4] = {{0, 1, 2, 3}, {0, 2, 1, 3}, {0, 3, 1, 2}};
  float best_score = -1.0f;
  std::array<int, 4> paired{};
  for (const auto& p : pairings) {
    const float score = metric.path_length(metric.Lca(ends[others[p[0]]], ends[others[p[1]]])) +
                        metric.path_length(metric.Lca(ends[others[p[2]]], ends[others[p[3]]]));
    if (score > best_score) {
      best_score = score;
      paired = {others[p[0]], others[p[1]], others[p[2]], others[p[3]]};
    }
  }
  HeadAndPairs body;
  body.head = limbs[head_index];
  body.first_pair = {limbs[paired[0]], limbs[paired[1]]};
  body.second_pair = {limbs[paired[2]], limbs[paired[3]]};
  body.pelvis = metric.Lca(metric.Lca(body.first_pair[0].end, body.second_pair[0].end), body.head.end);
  return body;
}

UpAxis NearestAxis(const Eigen::Vector3f& direction) {
  Eigen::Index index;
  direction.cwiseAbs().maxCoeff(&index);
  UpAxis up;
  up.axis = static_cast<int>(index);
  up.sign = direction[index] >= 0 ? 1 : -1;
  const float norm = direction.norm();
  up.alignment = norm > 0 ? std::abs(direction[index]) / norm : 0.0f;
  return up;
}

UpAxis MeasureUp(const GlobalPoses& poses, const std::vector<int>& frames, int pelvis, int head_end) {
  Eigen::Vector3f body_axis = Eigen::Vector3f::Zero();
  for (int f : frames) body_axis += (poses.position(f, head_end) - poses.position(f, pelvis)).normalized();
  return NearestAxis(body_axis);
}

UpAxis RestUp(const Skeleton& skeleton, int pelvis, int head_end) {
  const GlobalPoses rest = ForwardKinematics(skeleton, RestMotion(skeleton));
  return NearestAxis(rest.position(0, head_end) - rest.position(0, pelvis));
}

ArmsAndLegs SplitArmsAndLegs(const HeadAndPairs& body, const TreeMetric& metric, const GlobalPoses& poses,
                             const std::vector<int>& frames, const Eigen::Vector3f& up) {
  const float first_to_head = metric.path_length(metric.Lca(body.head.end, body.first_pair[0].end));
  const float second_to_head = metric.path_length(metric.Lca(body.head.end, body.second_pair[0].end));
  bool first_pair_is_arms;
  if (first_to_head != second_to_head) {
    first_pair_is_arms = first_to_head > second_to_head;
  } else {
    auto height = [&](int frame, int joint) { return poses.position(frame, joint).dot(up); };
    float first_height = 0.0f, second_height = 0.0f;
    for (int f : frames) {
      first_height += height(f, body.first_pair[0].end) + height(f, body.first_pair[1].end);
      second_height += height(f, body.second_pair[0].end) + height(f, body.second_pair[1].end);
    }
    first_pair_is_arms = first_height > second_height;
  }
  if (first_pair_is_arms) return ArmsAndLegs{.arms = body.first_pair, .legs = body.second_pair};
  return ArmsAndLegs{.arms = body.second_pair, .legs = body.first_pair};
}

absl::StatusOr<LimbJoints> FindLimbJoints(const Skeleton& skeleton, const TreeMetric& metric,
                                          const Eigen::VectorXf& bone, const Limb& limb, const GlobalPoses& poses,
                                          const std::vector<int>& frames, const Limb* mirror,
                                          float min_start_separation) {
  const std::vector<int> path = metric.Path(limb.top, limb.end);
  std::vector<int> mirror_path;
  if (mirror != nullptr) mirror_path = metric.Path(mirror->top, mirror->end);
  const bool mirrored = mirror_path.size() == path.size();
  if (path.size() < 3) {
    return absl::FailedPreconditionError(
        StrCat("limb starting at '", skeleton.joint(limb.top).name, "' has fewer than two bones"));
  }
  std::vector<int> segment_end;  // index into path
  std::vector<float> segment_length;
  float running = 0.0f;
  for (size_t i = 1; i < path.size(); ++i) {
    running += bone[path[i]];
    const bool straight_through = i + 1 < path.size() && frames.size() >= 10 &&
                                  skeleton.Children(path[i]).size() == 1 && StaysStraight(path, i, poses, frames) &&
                                  (!mirrored || StaysStraight(mirror_path, i, poses, frames));
    if (!straight_through) {
      segment_end.push_back(static_cast<int>(i));
      segment_length.push_back(running);
      running = 0.0f;
    }
  }
  if (segment_end.size() < 2) {
    return absl::FailedPreconditionError(
        StrCat("limb starting at '", skeleton.joint(limb.top).name, "' does not bend: fewer than two segments"));
  }
  // The upper long segment starts at the shoulder (hip), lateral on the body: skip the leading
  // segments that start nearer the mirror limb than `min_start_separation` (a clavicle from the
  // middle of the chest, longer than the forearm on some rigs), as long as two segments remain.
  int first = 0;
  if (mirrored && min_start_separation > 0.0f) {
    const int last_allowed = static_cast<int>(segment_end.size()) - 2;  // two segments remain
    while (first <= last_allowed) {
      const int start = first == 0 ? 0 : segment_end[first - 1];
      if (MeanDistance(poses, frames, path[start], mirror_path[start]) >= min_start_separation) break;
      // A clavicle is never the limb's longest bone: on a body whose shoulders are not wider than
      // its hips, the upper arm (longest) stays.
      if (segment_length[first] >= *std::max_element(segment_length.begin() + first + 1, segment_length.end())) break;
      ++first;
    }
    if (first > last_allowed) first = 0;  // no segment starts wide enough: the rule says nothing
  }
  std::vector<int> order(segment_end.size() - first);
  std::iota(order.begin(), order.end(), first);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return segment_length[a] > segment_length[b]; });
  const int upper = std::min(order[0], order[1]);
  return LimbJoints{.end = path[segment_end[std::max(order[0], order[1])]],
                    .middle = path[segment_end[upper]],
                    .start = upper > 0 ? path[segment_end[upper - 1]] : path[0]};
}

Eigen::Vector3f Horizontal(const Eigen::Vector3f& v, const Eigen::Vector3f& up) { return v - up * v.dot(up); }

void AddKneeBendCue(const std::array<Limb, 2>& legs, const std::array<LimbJoints, 2>& leg_joints,
                    const GlobalPoses& poses, const std::vector<int>& frames, const Eigen::Vector3f& up,
                    std::vector<Eigen::Vector3f>* per_frame) {
  for (int i = 0; i < 2; ++i) {
    // From the hip joint where the thigh starts (past a hip offset), else the leg's first joint.
    const int hip = leg_joints[i].start >= 0 ? leg_joints[i].start : legs[i].top;
    for (size_t k = 0; k < frames.size(); ++k) {
      const int f = frames[k];
      float along;
      const Eigen::Vector3f a = poses.position(f, hip), b = poses.position(f, leg_joints[i].end),
                            knee = poses.position(f, leg_joints[i].middle);
      PointSegmentDistance(knee, a, b, &along);
      (*per_frame)[k] += Horizontal(knee - (a + along * (b - a)), up);
    }
  }
}

float AddToeCue(const std::array<Limb, 2>& legs, const std::array<LimbJoints, 2>& leg_joints, const TreeMetric& metric,
                const GlobalPoses& poses, const std::vector<int>& frames, const Eigen::Vector3f& up, float body_size,
                std::vector<Eigen::Vector3f>* per_frame) {
  auto height = [&](int frame, int joint) { return poses.position(frame, joint).dot(up); };
  float foot_length = 0.0f;
  for (int i = 0; i < 2; ++i) {
    const int ankle = leg_joints[i].end;
    const std::optional<Eigen::Vector3f>& end_site = metric.skeleton().joint(ankle).end_site;
    const bool toe_joint = ankle != legs[i].end;
    if (!toe_joint && !(end_site && end_site->norm() > 0.0f)) continue;
    const int toe = toe_joint ? metric.ChildToward(ankle, legs[i].end) : -1;
    // Ankle -> toe in frame f.
    auto foot = [&](int f) -> Eigen::Vector3f {
      if (toe_joint) return poses.position(f, toe) - poses.position(f, ankle);
      return poses.rotation(f, ankle) * *end_site;
    };
    auto toe_height = [&](int f) { return height(f, ankle) + foot(f).dot(up); };
    float lowest_toe = std::numeric_limits<float>::infinity();
    for (int f : frames) lowest_toe = std::min(lowest_toe, toe_height(f));
    for (size_t k = 0; k < frames.size(); ++k) {
      const int f = frames[k];
      const Eigen::Vector3f ankle_to_toe = foot(f);
      foot_length = std::max(foot_length, ankle_to_toe.norm());
      if (toe_height(f) < lowest_toe + 0.05f * body_size) (*per_frame)[k] += Horizontal(ankle_to_toe, up);
    }
  }
  return foot_length;
}

std::vector<Eigen::Vector3f> PairLines(const std::array<LimbJoints, 2>& joints, const GlobalPoses& poses,
                                       const std::vector<int>& frames, const Eigen::Vector3f& up) {
  // "Apart" against the middles' separation, so that rounding in coinciding joints does not count.
  const bool starts_apart = MeanDistance(poses, frames, joints[0].start, joints[1].start) >
                            1e-4f * MeanDistance(poses, frames, joints[0].middle, joints[1].middle);
  const int a = starts_apart ? joints[0].start : joints[0].middle;
  const int b = starts_apart ? joints[1].start : joints[1].middle;
  std::vector<Eigen::Vector3f> lines;
  lines.reserve(frames.size());
  for (int f : frames) lines.push_back(Horizontal(poses.position(f, a) - poses.position(f, b), up));
  return lines;
}

absl::StatusOr<Sides> FindSides(const ArmsAndLegs& limbs, const std::array<LimbJoints, 2>& arm_joints,
                                const std::array<LimbJoints, 2>& leg_joints, int pelvis, const TreeMetric& metric,
                                const GlobalPoses& poses, const std::vector<int>& frames, const Eigen::Vector3f& up,
                                float body_size) {
  // Per sampled frame: the facing if the first leg is the left one (hip line x up, unit).
  const std::vector<Eigen::Vector3f> hip_lines = PairLines(leg_joints, poses, frames, up);
  std::vector<Eigen::Vector3f> facing(frames.size());
  for (size_t k = 0; k < frames.size(); ++k) {
    const Eigen::Vector3f& hips = hip_lines[k];
    facing[k] = hips.norm() > 0.0f ? Eigen::Vector3f(hips.normalized().cross(up)) : Eigen::Vector3f::Zero();
  }
  std::vector<Eigen::Vector3f> cue(frames.size(), Eigen::Vector3f::Zero());
  AddKneeBendCue(limbs.legs, leg_joints, poses, frames, up, &cue);
  const float foot_length = AddToeCue(limbs.legs, leg_joints, metric, poses, frames, up, body_size, &cue);
  float evidence = 0.0f;  // > 0: the first leg is the left one
  for (size_t k = 0; k < frames.size(); ++k) evidence += cue[k].dot(facing[k]);
  if (std::abs(evidence) < 0.1f * std::max(foot_length, 0.05f * body_size)) {
    // No anatomical cue: the pelvis' travel, each step against its own frame's facing.
    evidence = 0.0f;
    for (size_t k = 0; k + 1 < frames.size(); ++k) {
      const Eigen::Vector3f step = poses.position(frames[k + 1], pelvis) - poses.position(frames[k], pelvis);
      evidence += Horizontal(step, up).dot(facing[k]);
    }
    if (std::abs(evidence) < 0.05f * body_size) {
      return absl::FailedPreconditionError(
          "cannot tell left from right: the feet have no toe joints and the clip does not travel");
    }
  }
  Sides sides;
  sides.first_leg_is_left = evidence > 0.0f;
  const float sign = sides.first_leg_is_left ? 1.0f : -1.0f;
  // The arms against the same per-frame body: left = sign * hip line.
  const std::vector<Eigen::Vector3f> shoulder_lines = PairLines(arm_joints, poses, frames, up);
  float arm_evidence = 0.0f;
  Eigen::Vector3f mean_forward = Eigen::Vector3f::Zero();
  for (size_t k = 0; k < frames.size(); ++k) {
    const Eigen::Vector3f left = sign * up.cross(facing[k]);
    arm_evidence += shoulder_lines[k].dot(left);
    mean_forward += sign * facing[k];
  }
  sides.first_arm_is_left = arm_evidence > 0.0f;
  mean_forward /= static_cast<float>(std::max<size_t>(frames.size(), 1));
  if (mean_forward.norm() < 0.5f && !facing.empty()) mean_forward = sign * facing[0];
  if (mean_forward.norm() > 0.0f) sides.forward = mean_forward.normalized();
  return sides;
}

int HeadLandmark(const Limb& head, const TreeMetric& metric, const MergedTree& tree) {
  for (int j : metric.Path(head.top, head.end)) {
    if (tree.representative[j] == j && tree.children[j].size() >= 2) return j;
  }
  return head.end;
}

void AssignGroups(const Skeleton& skeleton, const SidedLimbs& limbs, int pelvis, BodyTopology* topology) {
  const int joints = skeleton.num_joints();
  topology->group_of_joint.assign(joints, BodyGroup::kSpine);
  topology->group_top.fill(0);
  topology->group_end.fill(0);
  auto assign = [&](const Limb& limb, BodyGroup group) {
    topology->group_top[static_cast<int>(group)] = limb.top;
    topology->group_end[static_cast<int>(group)] = limb.end;
    // Parents come before children: the subtree of `top` lies at indices >= top.
    for (int j = limb.top; j < joints; ++j) {
      int a = j;
      while (a > limb.top) a = skeleton.parent(a);
      if (a == limb.top) topology->group_of_joint[j] = group;
    }
  };
  assign(limbs.head, BodyGroup::kHead);
  assign(limbs.left_arm, BodyGroup::kLeftArm);
  assign(limbs.right_arm, BodyGroup::kRightArm);
  assign(limbs.left_leg, BodyGroup::kLeftLeg);
  assign(limbs.right_leg, BodyGroup::kRightLeg);
  topology->group_end[static_cast<int>(BodyGroup::kSpine)] = pelvis;
}

float LegLength(const std::array<Limb, 2>& legs, const std::array<LimbJoints, 2>& leg_joints, const TreeMetric& metric,
                const Eigen::VectorXf& bone) {
  float sum = 0.0f;
  for (int i = 0; i < 2; ++i) {
    for (int j : metric.Path(legs[i].top, leg_joints[i].end)) {
      if (j != legs[i].top) sum += bone[j];
    }
  }
  return sum / 2;
}

Heights MeasureHeights(const std::vector<BodyGroup>& group_of_joint, int pelvis, const GlobalPoses& poses,
                       const Eigen::Vector3f& up) {
  auto height = [&](int frame, int joint) { return poses.position(frame, joint).dot(up); };
  std::vector<int> leg_joints;
  for (int j = 0; j < static_cast<int>(group_of_joint.size()); ++j) {
    if (group_of_joint[j] == BodyGroup::kLeftLeg || group_of_joint[j] == BodyGroup::kRightLeg) leg_joints.push_back(j);
  }
  std::vector<float> pelvis_heights;
  float floor = std::numeric_limits<float>::infinity();
  for (int f = 0; f < poses.num_frames(); ++f) {
    float lowest = std::numeric_limits<float>::infinity();
    for (int j : leg_joints) lowest = std::min(lowest, height(f, j));
    floor = std::min(floor, lowest);
    pelvis_heights.push_back(height(f, pelvis) - lowest);
  }
  std::nth_element(pelvis_heights.begin(), pelvis_heights.begin() + pelvis_heights.size() / 2, pelvis_heights.end());
  return Heights{.standing_pelvis = pelvis_heights[pelvis_heights.size() / 2], .floor = floor};
}

}  // namespace mocap::body_topology

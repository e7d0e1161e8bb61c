// AnkleDagStep: the inner loop of METHOD.md A4's dynamic programme (Algorithm 1), K1 × K1 edges
// per frame. Exact: it returns what scanning every edge with AnkleEdgeCost would (the same float
// costs, and on equal costs the predecessor with the lowest path cost first, in the order a
// std::sort by path cost gives). Fast because
//   - predecessors are laid out as float columns sorted by path cost and scanned eight at a time
//     (GCC vector extensions; an AVX2 clone is picked at run time, SSE2 otherwise);
//   - the slide term's exp is needed only for pairs that slide, which the vector pass flags: for
//     every other pair the vector pass's value is the exact cost. For a sliding pair the vector
//     pass puts a lower bound of std::exp in its place; float rounding is monotone, so the total
//     bounds the exact cost from below, and the exact cost (with std::exp, as AnkleEdgeCost has
//     it) is computed only when that bound can still win;
//   - with SlideRule::kContact a node whose ankles are both above the contact ceiling never slides,
//     so its scan skips the slide term entirely;
//   - branch and bound: edge costs are ≥ 0, so once a block's cheapest path cost reaches the best
//     total found, no later block can win.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <numeric>

#include "motion/reconstruct/ankle_edge_cost.h"
#include "motion/reconstruct/ankle_path.h"

namespace mocap {
namespace {

constexpr int kLanes = 8;
constexpr int kBlock = 64;  // predecessors per bound check; a multiple of kLanes
// Explicitly 32-byte aligned: without AVX enabled for the whole file, GCC would give these types
// 16-byte alignment while the AVX2 clone's aligned loads need 32.
typedef float Floats __attribute__((vector_size(kLanes * sizeof(float)), aligned(32)));
typedef int32_t Masks __attribute__((vector_size(kLanes * sizeof(int32_t)), aligned(32)));
struct alignas(32) FloatLanes {  // element type for std::vector (which drops attributes)
  Floats v;
};
struct alignas(32) MaskLanes {
  Masks v;
};
constexpr float kInfinity = std::numeric_limits<float>::infinity();

// The previous frame's nodes sorted by path cost, one column of lanes per coordinate (aligned
// vectors: whole loads, no split or store-forwarded ones), padded to whole blocks (padding:
// infinite path cost, never chosen).
struct SortedPredecessors {
  int count = 0;
  int padded = 0;
  std::vector<int> node;                // index into `previous`, per sorted position
  std::vector<float> cost;              // path cost, per sorted position
  std::vector<FloatLanes> path;         // the same, as vectors
  std::vector<FloatLanes> predicted[6];  // y + Δt·ẏ: left x, y, z, right x, y, z
  std::vector<FloatLanes> position[6];   // y
  std::vector<MaskLanes> low[2];         // ~0 when that ankle is below the contact ceiling
};

SortedPredecessors SortPredecessors(const std::vector<AnkleCandidate>& previous, const std::vector<float>& previous_cost,
                                    float dt, float ceiling) {
  SortedPredecessors p;
  p.count = static_cast<int>(previous.size());
  p.padded = (p.count + kBlock - 1) / kBlock * kBlock;
  p.node.resize(p.count);
  std::iota(p.node.begin(), p.node.end(), 0);
  std::sort(p.node.begin(), p.node.end(), [&](int a, int b) { return previous_cost[a] < previous_cost[b]; });
  const int vectors = p.padded / kLanes;
  p.cost.assign(p.padded, kInfinity);
  p.path.assign(vectors, FloatLanes{Floats{} + kInfinity});
  for (auto& column : p.predicted) column.assign(vectors, FloatLanes{});
  for (auto& column : p.position) column.assign(vectors, FloatLanes{});
  for (auto& column : p.low) column.assign(vectors, MaskLanes{});
  for (int i = 0; i < p.count; ++i) {
    const AnkleCandidate& c = previous[p.node[i]];
    const int v = i / kLanes, lane = i % kLanes;
    p.cost[i] = previous_cost[p.node[i]];
    p.path[v].v[lane] = p.cost[i];
    for (int side = 0; side < 2; ++side) {
      const Eigen::Vector3f predicted = c.position[side] + dt * c.velocity[side];  // as AnkleEdgeCost rounds it
      for (int axis = 0; axis < 3; ++axis) {
        p.predicted[3 * side + axis][v].v[lane] = predicted[axis];
        p.position[3 * side + axis][v].v[lane] = c.position[side][axis];
      }
      p.low[side][v].v[lane] = c.position[side].y() < ceiling ? ~0 : 0;
    }
  }
  return p;
}

inline float LowestLane(const Floats& v) {
  float lowest = v[0];
  for (int i = 1; i < kLanes; ++i) lowest = std::min(lowest, v[i]);
  return lowest;
}

// A lower bound of std::exp(x) for every float x: e^x ≥ max(1 + x, 0), shrunk by 2^-20 to cover
// the rounding of both sides. Cheap, and tight where it matters: a slide of a few cm (x ≈ w_s·d²
// small) costs little more than 1 + x, and a long one already misses the motion prior badly.
inline void ExpLowerBound(Floats* x) {
  const Floats line = *x + 1.0f;
  *x = (line > 0.0f ? line : Floats{}) * (1.0f - 0x1p-20f);
}

struct StepConstants {
  float prior_factor;  // β·s²
  float slide_factor;  // 1 − β
  float slide_distance_sq;
  float slide_height;
  float slide_weight;  // w_s
};

// One foot's share of a block of 8 predecessors (vector v) for a target ankle t: the squared
// miss of the motion prior, and (when the foot may slide) where it slides and a lower bound of its
// exp. kCanSlide false: the foot never slides for this target.
template <SlideRule kRule, bool kCanSlide>
[[gnu::always_inline]] inline void FootTerms(const SortedPredecessors& p, int side, int v, const float* t,
                                             const StepConstants& c, Floats* miss_sq, Masks* slides, Floats* exp_bound) {
  const Floats dx = p.predicted[3 * side][v].v - t[0];
  const Floats dy = p.predicted[3 * side + 1][v].v - t[1];
  const Floats dz = p.predicted[3 * side + 2][v].v - t[2];
  *miss_sq = dx * dx + (dy * dy + dz * dz);  // rounded as Eigen's squaredNorm of a Vector3f
  if constexpr (kCanSlide) {
    const Floats sx = t[0] - p.position[3 * side][v].v;
    const Floats sy = t[1] - p.position[3 * side + 1][v].v;
    const Floats sz = t[2] - p.position[3 * side + 2][v].v;
    const Floats distance_sq = sx * sx + (sy * sy + sz * sz);
    Masks moves = distance_sq > c.slide_distance_sq;
    if constexpr (kRule == SlideRule::kPatent) {
      *slides = moves & (sy < c.slide_height) & (sy > -c.slide_height);
    } else {
      *slides = moves & p.low[side][v].v;
    }
    *exp_bound = c.slide_weight * distance_sq;
    ExpLowerBound(exp_bound);
  }
}

// Best predecessor of `target` (whose ankles are `y`): cost and sorted position. kLeft/kRight:
// whether that foot can slide at all (always with kPatent).
template <SlideRule kRule, bool kLeft, bool kRight>
[[gnu::always_inline]] inline void BestPredecessor(const SortedPredecessors& p, const std::vector<AnkleCandidate>& previous,
                                                   const AnkleCandidate& target, const float* y, const StepConstants& c,
                                                   float dt, const AnklePathOptions& options, float* best_cost,
                                                   int* best_at) {
  constexpr int kVectors = kBlock / kLanes;
  float best = kInfinity;
  int at = 0;
  Floats exact[kVectors];  // cost of a pair that does not slide, else +inf
  Floats bound[kVectors];  // lower bound of the cost of a pair that slides, else +inf
  const Floats infinity = Floats{} + kInfinity;
  for (int begin = 0; begin < p.padded; begin += kBlock) {
    if (p.cost[begin] >= best) break;
    Floats exact_min = infinity, bound_min = infinity;
    for (int i = 0; i < kVectors; ++i) {
      const int v = begin / kLanes + i;
      Floats left_sq, right_sq, left_exp = {}, right_exp = {};
      Masks left_slides = {}, right_slides = {};
      FootTerms<kRule, kLeft>(p, 0, v, y, c, &left_sq, &left_slides, &left_exp);
      FootTerms<kRule, kRight>(p, 1, v, y + 3, c, &right_sq, &right_slides, &right_exp);
      const Floats prior = left_sq + right_sq;
      if constexpr (kLeft || kRight) {
        const Floats slide = (left_slides ? left_exp : Floats{}) + (right_slides ? right_exp : Floats{});
        const Masks fires = left_slides | right_slides;
        // Where nothing slides, slide = 0 and this is exactly AnkleEdgeCost's rounding.
        const Floats total = p.path[v].v + (c.prior_factor * prior + c.slide_factor * slide);
        exact[i] = fires ? infinity : total;
        bound[i] = fires ? total : infinity;
        bound_min = bound[i] < bound_min ? bound[i] : bound_min;
      } else {
        exact[i] = p.path[v].v + (c.prior_factor * prior + c.slide_factor * Floats{});
      }
      exact_min = exact[i] < exact_min ? exact[i] : exact_min;
    }
    const float block_best = LowestLane(exact_min);
    if (block_best < best) {  // earlier blocks win ties, so a strictly lower cost only
      int i = 0;
      while (exact[i / kLanes][i % kLanes] != block_best) ++i;
      best = block_best;
      at = begin + i;
    }
    if ((kLeft || kRight) && LowestLane(bound_min) <= best) {
      for (int i = 0; i < kBlock && begin + i < p.count; ++i) {
        if (!(bound[i / kLanes][i % kLanes] <= best)) continue;
        const int j = begin + i;
        const float cost = p.cost[j] + AnkleEdgeCost(previous[p.node[j]], target, dt, options);
        if (cost < best || (cost == best && j < at)) {
          best = cost;
          at = j;
        }
      }
    }
  }
  *best_cost = best;
  *best_at = at;
}

// All targets of one step. Cloned for AVX2 (chosen at load time on CPUs that have it); plain
// x86-64 (SSE2) otherwise. No FMA in either, so both round as the scalar AnkleEdgeCost does.
[[gnu::target_clones("avx2", "default")]] void ScanTargets(const SortedPredecessors& p,
                                                           const std::vector<AnkleCandidate>& previous,
                                                           const std::vector<AnkleCandidate>& current, float dt,
                                                           const AnklePathOptions& options, float* cost, int* from) {
  const StepConstants c{AnklePriorFactor(options), 1.0f - options.prior_weight,
                        options.slide_distance * options.slide_distance, options.slide_height, options.slide_weight};
  const float ceiling = AnkleContactCeiling(options);
  for (size_t k = 0; k < current.size(); ++k) {
    const AnkleCandidate& target = current[k];
    float y[6];
    for (int side = 0; side < 2; ++side) {
      for (int axis = 0; axis < 3; ++axis) y[3 * side + axis] = target.position[side][axis];
    }
    float best = kInfinity;
    int at = 0;
    if (options.slide_rule == SlideRule::kPatent) {
      BestPredecessor<SlideRule::kPatent, true, true>(p, previous, target, y, c, dt, options, &best, &at);
    } else {
      const bool left = target.position[0].y() < ceiling, right = target.position[1].y() < ceiling;
      if (left && right) {
        BestPredecessor<SlideRule::kContact, true, true>(p, previous, target, y, c, dt, options, &best, &at);
      } else if (left) {
        BestPredecessor<SlideRule::kContact, true, false>(p, previous, target, y, c, dt, options, &best, &at);
      } else if (right) {
        BestPredecessor<SlideRule::kContact, false, true>(p, previous, target, y, c, dt, options, &best, &at);
      } else {
        BestPredecessor<SlideRule::kContact, false, false>(p, previous, target, y, c, dt, options, &best, &at);
      }
    }
    cost[k] = best;
    from[k] = p.node[at];
  }
}

}  // namespace

void AnkleDagStep(const std::vector<AnkleCandidate>& previous, const std::vector<float>& previous_cost,
                  const std::vector<AnkleCandidate>& current, float dt, const AnklePathOptions& options,
                  std::vector<float>* cost, std::vector<int>* from) {
  cost->assign(current.size(), kInfinity);
  from->assign(current.size(), 0);
  if (previous.empty()) return;
  const SortedPredecessors sorted = SortPredecessors(previous, previous_cost, dt, AnkleContactCeiling(options));
  ScanTargets(sorted, previous, current, dt, options, cost->data(), from->data());
}

}  // namespace mocap

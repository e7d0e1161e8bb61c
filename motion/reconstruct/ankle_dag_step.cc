// AnkleDagStep: the inner loop of docs/method.md A4's dynamic programme (Algorithm 1), K1 × K1 edges
// per frame. Exact: it returns what scanning every edge with AnkleEdgeCost would (the same float
// costs, and on equal costs the predecessor with the lowest path cost first, in the order a
// std::sort by path cost gives). Fast because
//   - predecessors are laid out as float columns sorted by path cost and scanned eight at a time
//     with AVX2 when the CPU has it (checked at run time), else four at a time with SSE2 (GCC
//     vector extensions; no -march flag needed);
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
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>

#include "motion/reconstruct/ankle_edge_cost.h"
#include "motion/reconstruct/ankle_path.h"

namespace mocap {
namespace {

constexpr int kBlock = 64;  // predecessors per bound check; a multiple of every lane count

// Vector widths. Each kernel instance uses vectors the hardware has: 8 lanes would be split into
// scalar compares and selects without AVX.
struct Lanes8 {
  static constexpr int kCount = 8;
  typedef float Floats __attribute__((vector_size(32), aligned(32)));
  typedef int32_t Masks __attribute__((vector_size(32), aligned(32)));
};
struct Lanes4 {
  static constexpr int kCount = 4;
  typedef float Floats __attribute__((vector_size(16)));
  typedef int32_t Masks __attribute__((vector_size(16)));
};

// Columns are stored in 32-byte aligned groups of 8 and read as vectors of either width.
struct alignas(32) FloatGroup {
  float lane[8];
};
struct alignas(32) MaskGroup {
  int32_t lane[8];
};
template <class V>
[[gnu::always_inline]] inline const typename V::Floats& VectorAt(const std::vector<FloatGroup>& column, int v) {
  return reinterpret_cast<const typename V::Floats*>(column.data())[v];
}
template <class V>
[[gnu::always_inline]] inline const typename V::Masks& VectorAt(const std::vector<MaskGroup>& column, int v) {
  return reinterpret_cast<const typename V::Masks*>(column.data())[v];
}
constexpr float kInfinity = std::numeric_limits<float>::infinity();

// The previous frame's nodes sorted by path cost, one column of lanes per coordinate (aligned
// vectors: whole loads, no split or store-forwarded ones), padded to whole blocks (padding:
// infinite path cost, never chosen).
struct SortedPredecessors {
  int count = 0;
  int padded = 0;
  std::vector<int> node;                 // index into `previous`, per sorted position
  std::vector<float> cost;               // path cost, per sorted position
  std::vector<FloatGroup> path;          // the same, as vectors
  std::vector<FloatGroup> predicted[6];  // y + Δt·ẏ: left x, y, z, right x, y, z
  std::vector<FloatGroup> position[6];   // y
  std::vector<MaskGroup> low[2];         // ~0 when that ankle is below the contact ceiling
};

SortedPredecessors SortPredecessors(const std::vector<AnkleCandidate>& previous,
                                    const std::vector<float>& previous_cost, float dt, float ceiling) {
  SortedPredecessors p;
  p.count = static_cast<int>(previous.size());
  p.padded = (p.count + kBlock - 1) / kBlock * kBlock;
  p.node.resize(p.count);
  std::iota(p.node.begin(), p.node.end(), 0);
  std::sort(p.node.begin(), p.node.end(), [&](int a, int b) { return previous_cost[a] < previous_cost[b]; });
  const int groups = p.padded / 8;
  p.cost.assign(p.padded, kInfinity);
  FloatGroup infinite;
  std::fill(std::begin(infinite.lane), std::end(infinite.lane), kInfinity);
  p.path.assign(groups, infinite);
  for (auto& column : p.predicted) column.assign(groups, FloatGroup{});
  for (auto& column : p.position) column.assign(groups, FloatGroup{});
  for (auto& column : p.low) column.assign(groups, MaskGroup{});
  for (int i = 0; i < p.count; ++i) {
    const AnkleCandidate& c = previous[p.node[i]];
    const int v = i / 8, lane = i % 8;
    p.cost[i] = previous_cost[p.node[i]];
    p.path[v].lane[lane] = p.cost[i];
    for (int side = 0; side < 2; ++side) {
      const Eigen::Vector3f predicted = c.position[side] + dt * c.velocity[side];  // as AnkleEdgeCost rounds it
      for (int axis = 0; axis < 3; ++axis) {
        p.predicted[3 * side + axis][v].lane[lane] = predicted[axis];
        p.position[3 * side + axis][v].lane[lane] = c.position[side][axis];
      }
      p.low[side][v].lane[lane] = c.position[side].y() < ceiling ? ~0 : 0;
    }
  }
  return p;
}

template <class V>
[[gnu::always_inline]] inline float LowestLane(const typename V::Floats& v) {
  float lowest = v[0];
  for (int i = 1; i < V::kCount; ++i) lowest = std::min(lowest, v[i]);
  return lowest;
}

// A lower bound of std::exp(x) for every float x: e^x ≥ max(1 + x, 0), shrunk by 2^-20 to cover
// the rounding of both sides. Cheap, and tight where it matters: a slide of a few cm (x = w_s·d²
// small) costs little more than 1 + x, and a long one already misses the motion prior badly.
template <class Floats>
[[gnu::always_inline]] inline void ExpLowerBound(Floats* x) {
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

// One foot's share of 8 predecessors (vector v) for a target ankle t: the squared miss of the
// motion prior, and when the foot may slide (kCanSlide), where it slides and its exponent
// w_s·‖step‖², each rounded as AnkleEdgeCost rounds it.
template <class V, SlideRule kRule, bool kCanSlide>
[[gnu::always_inline]] inline void FootTerms(const SortedPredecessors& p, int side, int v, const float* t,
                                             const StepConstants& c, typename V::Floats* miss_sq,
                                             typename V::Masks* slides, typename V::Floats* exponent) {
  using Floats = typename V::Floats;
  using Masks = typename V::Masks;
  const Floats dx = VectorAt<V>(p.predicted[3 * side], v) - t[0];
  const Floats dy = VectorAt<V>(p.predicted[3 * side + 1], v) - t[1];
  const Floats dz = VectorAt<V>(p.predicted[3 * side + 2], v) - t[2];
  *miss_sq = dx * dx + (dy * dy + dz * dz);  // as Eigen's squaredNorm of a Vector3f
  if constexpr (kCanSlide) {
    const Floats sx = t[0] - VectorAt<V>(p.position[3 * side], v);
    const Floats sy = t[1] - VectorAt<V>(p.position[3 * side + 1], v);
    const Floats sz = t[2] - VectorAt<V>(p.position[3 * side + 2], v);
    const Floats distance_sq = sx * sx + (sy * sy + sz * sz);
    const Masks moves = distance_sq > c.slide_distance_sq;
    if constexpr (kRule == SlideRule::kPatent) {
      *slides = moves & (sy < c.slide_height) & (sy > -c.slide_height);
    } else {
      *slides = moves & VectorAt<V>(p.low[side], v);
    }
    *exponent = c.slide_weight * distance_sq;
  }
}

// Best predecessor (sorted position) of a target whose ankles are `y`, and its path cost.
// kLeft/kRight: whether that foot can slide at all (always with kPatent).
template <class V, SlideRule kRule, bool kLeft, bool kRight>
[[gnu::always_inline]] inline void BestPredecessor(const SortedPredecessors& p, const float* y, const StepConstants& c,
                                                   float* best_cost, int* best_at) {
  using Floats = typename V::Floats;
  using Masks = typename V::Masks;
  constexpr int kLanes = V::kCount;
  constexpr bool kSlides = kLeft || kRight;
  constexpr int kVectors = kBlock / kLanes;
  float best = kInfinity;
  int at = 0;
  Floats exact[kVectors];  // total of a pair that does not slide, else +inf
  Floats bound[kVectors];  // lower bound of the total of a pair that slides, else +inf
  Floats prior[kVectors], left_exponent[kVectors], right_exponent[kVectors];
  Masks left_slides[kVectors], right_slides[kVectors];
  const Floats infinity = Floats{} + kInfinity;
  for (int begin = 0; begin < p.padded; begin += kBlock) {
    if (p.cost[begin] >= best) break;
    Floats exact_min = infinity, bound_min = infinity;
    for (int i = 0; i < kVectors; ++i) {
      const int v = begin / kLanes + i;
      Floats left_sq, right_sq;
      left_exponent[i] = right_exponent[i] = Floats{};
      left_slides[i] = right_slides[i] = Masks{};
      FootTerms<V, kRule, kLeft>(p, 0, v, y, c, &left_sq, &left_slides[i], &left_exponent[i]);
      FootTerms<V, kRule, kRight>(p, 1, v, y + 3, c, &right_sq, &right_slides[i], &right_exponent[i]);
      prior[i] = left_sq + right_sq;
      if constexpr (kSlides) {
        Floats left_exp = left_exponent[i], right_exp = right_exponent[i];
        ExpLowerBound(&left_exp);
        ExpLowerBound(&right_exp);
        const Floats slide = (left_slides[i] ? left_exp : Floats{}) + (right_slides[i] ? right_exp : Floats{});
        const Masks fires = left_slides[i] | right_slides[i];
        // Where nothing slides, slide = 0 and this is exactly AnkleEdgeCost's total.
        const Floats total = VectorAt<V>(p.path, v) + (c.prior_factor * prior[i] + c.slide_factor * slide);
        exact[i] = fires ? infinity : total;
        bound[i] = fires ? total : infinity;
        bound_min = bound[i] < bound_min ? bound[i] : bound_min;
      } else {
        exact[i] = VectorAt<V>(p.path, v) + (c.prior_factor * prior[i] + c.slide_factor * Floats{});
      }
      exact_min = exact[i] < exact_min ? exact[i] : exact_min;
    }
    const float block_best = LowestLane<V>(exact_min);
    if (block_best < best) {  // earlier blocks win ties, so a strictly lower cost only
      int i = 0;
      while (exact[i / kLanes][i % kLanes] != block_best) ++i;
      best = block_best;
      at = begin + i;
    }
    if (kSlides && LowestLane<V>(bound_min) <= best) {
      for (int i = 0; i < kBlock && begin + i < p.count; ++i) {
        const int v = i / kLanes, lane = i % kLanes;
        if (!(bound[v][lane] <= best)) continue;
        // The exact slide term, summed in AnkleEdgeCost's order with std::exp.
        float slide = 0.0f;
        if (left_slides[v][lane]) slide += std::exp(left_exponent[v][lane]);
        if (right_slides[v][lane]) slide += std::exp(right_exponent[v][lane]);
        const int j = begin + i;
        const float cost = p.cost[j] + (c.prior_factor * prior[v][lane] + c.slide_factor * slide);
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

// All targets of one step with vectors V.
template <class V>
[[gnu::always_inline]] inline void ScanTargets(const SortedPredecessors& p, const std::vector<AnkleCandidate>& current,
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
      BestPredecessor<V, SlideRule::kPatent, true, true>(p, y, c, &best, &at);
    } else {
      const bool left = target.position[0].y() < ceiling, right = target.position[1].y() < ceiling;
      if (left && right) {
        BestPredecessor<V, SlideRule::kContact, true, true>(p, y, c, &best, &at);
      } else if (left) {
        BestPredecessor<V, SlideRule::kContact, true, false>(p, y, c, &best, &at);
      } else if (right) {
        BestPredecessor<V, SlideRule::kContact, false, true>(p, y, c, &best, &at);
      } else {
        BestPredecessor<V, SlideRule::kContact, false, false>(p, y, c, &best, &at);
      }
    }
    cost[k] = best;
    from[k] = p.node[at];
  }
}

// The two builds of the scan. No FMA in either, so both round as the scalar AnkleEdgeCost does.
[[gnu::target("avx2")]] void ScanTargetsAvx2(const SortedPredecessors& p, const std::vector<AnkleCandidate>& current,
                                             const AnklePathOptions& options, float* cost, int* from) {
  ScanTargets<Lanes8>(p, current, options, cost, from);
}
void ScanTargetsSse2(const SortedPredecessors& p, const std::vector<AnkleCandidate>& current,
                     const AnklePathOptions& options, float* cost, int* from) {
  ScanTargets<Lanes4>(p, current, options, cost, from);
}

bool CpuHasAvx2() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2");  // also checks that the OS saves the AVX registers
}

}  // namespace

void AnkleDagStep(const std::vector<AnkleCandidate>& previous, const std::vector<float>& previous_cost,
                  const std::vector<AnkleCandidate>& current, float dt, const AnklePathOptions& options,
                  std::vector<float>* cost, std::vector<int>* from) {
  cost->assign(current.size(), kInfinity);
  from->assign(current.size(), 0);
  if (previous.empty()) return;
  const SortedPredecessors sorted = SortPredecessors(previous, previous_cost, dt, AnkleContactCeiling(options));
  static const bool avx2 = CpuHasAvx2();
  (avx2 ? ScanTargetsAvx2 : ScanTargetsSse2)(sorted, current, options, cost->data(), from->data());
}

}  // namespace mocap

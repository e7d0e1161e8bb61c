#include "motion/frames/input_monitor.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "motion/core/str_cat.h"

namespace mocap {
namespace {

constexpr LengthUnit kUnits[] = {LengthUnit::kMetre, LengthUnit::kCentimetre, LengthUnit::kMillimetre,
                                 LengthUnit::kInch};
constexpr double kWaypointSeconds = 0.1;
// Wrist joints of one adult: from hands together to arms spread (metres), and the typical
// distance (the median over every frame of the held-out bandai-namco-2 clips: 0.54 m; 1% are
// closer than 0.2 m, none further than 1.12 m).
constexpr double kPlausibleSeparation[2] = {0.05, 2.0};
constexpr double kTypicalSeparation = 0.54;

std::string_view LongUnitName(LengthUnit unit) {
  switch (unit) {
    case LengthUnit::kMetre:
      return "metres";
    case LengthUnit::kCentimetre:
      return "centimetres";
    case LengthUnit::kMillimetre:
      return "millimetres";
    case LengthUnit::kInch:
      return "inches";
    case LengthUnit::kCmuUnit:
      return "CMU units (1/0.45 inch)";
  }
  return "?";
}

// The units other than the declared one under which `caller_units` of wrist separation is a
// body's (kPlausibleSeparation), the likeliest first (nearest the typical separation on a log
// scale), as "centimetres or millimetres declared as metres?"; empty when none is.
std::string UnitHint(double caller_units, LengthUnit declared) {
  std::vector<std::pair<double, LengthUnit>> candidates;
  for (LengthUnit unit : kUnits) {
    const double metres = caller_units * MetresPerUnit(unit);
    if (unit == declared || !(metres >= kPlausibleSeparation[0] && metres <= kPlausibleSeparation[1])) continue;
    candidates.emplace_back(std::abs(std::log(metres / kTypicalSeparation)), unit);
  }
  if (candidates.empty()) return {};
  std::sort(candidates.begin(), candidates.end());
  candidates.resize(std::min<size_t>(candidates.size(), 2));  // the two likeliest say enough
  std::string hint = ": ";
  for (size_t i = 0; i < candidates.size(); ++i) hint += StrCat(i ? " or " : "", LongUnitName(candidates[i].second));
  return StrCat(hint, " declared as ", LongUnitName(declared), "?");
}

std::string Rounded(double value) {
  const double magnitude = std::abs(value);
  const double step = magnitude >= 100 ? 1.0 : magnitude >= 1 ? 0.01 : 0.0001;
  return StrCat(std::round(value / step) * step);
}

bool BothTracked(const WristSample& sample) { return sample.tracked[0] && sample.tracked[1]; }

float Median(std::vector<float> values) {
  if (values.empty()) return 0.0f;
  const size_t middle = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<long>(middle), values.end());
  return values[middle];
}

}  // namespace

std::optional<std::string> WristSeparationProblem(double separation_metres, LengthUnit declared) {
  if (separation_metres <= kMaxWristSeparationMetres) return std::nullopt;
  const double caller_units = separation_metres / MetresPerUnit(declared);
  std::string message = StrCat("wrist samples ", Rounded(caller_units), " units apart (", Rounded(separation_metres),
                               " m as declared in ", UnitName(declared), ", more than ", kMaxWristSeparationMetres,
                               " m: not one person's wrists)");
  return message + UnitHint(caller_units, declared);
}

InputMonitor::InputMonitor(const FrameConvention& convention, bool calibrate_floor, const InputMonitorOptions& options)
    : convention_(convention), calibrate_floor_(calibrate_floor), options_(options) {
  if (!(options_.body_height > 0.0f)) options_.body_height = kDefaultBodyHeight;  // a rig without a measurable height
}

void InputMonitor::Add(const WristSample& sample, long index, std::vector<MonitoredSample>* ready,
                       std::vector<InputWarning>* warnings) {
  if (!window_done_) {
    if (!first_time_) first_time_ = sample.time;
    if (sample.time - *first_time_ <= options_.window_seconds) {
      window_.push_back({sample, index});
      if (!calibrate_floor_) {
        ready->push_back(window_.back());
        Track(sample, warnings);
      }
      return;
    }
    CloseWindow(ready, warnings);
  }
  WristSample shifted = sample;
  shifted.left.y() -= calibrated_floor_;
  shifted.right.y() -= calibrated_floor_;
  ready->push_back({shifted, index});
  Track(shifted, warnings);
}

void InputMonitor::Track(const WristSample& sample, std::vector<InputWarning>* warnings) {
  if (!BothTracked(sample)) return;  // a lost hand's position says nothing about the input
  TrackSides(sample, warnings);
  TrackHeight(sample, warnings);
}

void InputMonitor::Finish(std::vector<MonitoredSample>* ready, std::vector<InputWarning>* warnings) {
  if (!window_done_ && !window_.empty()) CloseWindow(ready, warnings);
}

void InputMonitor::CloseWindow(std::vector<MonitoredSample>* ready, std::vector<InputWarning>* warnings) {
  window_done_ = true;
  const float height = options_.body_height;
  std::vector<float> separations, lower_heights;
  for (const MonitoredSample& s : window_) {
    if (!BothTracked(s.sample)) continue;
    separations.push_back((s.sample.left - s.sample.right).norm());
    lower_heights.push_back(std::min(s.sample.left.y(), s.sample.right.y()));
  }
  if (calibrate_floor_) {
    // A window where a hand was lost throughout tells nothing: the floor stays as declared.
    if (!lower_heights.empty()) calibrated_floor_ = Median(lower_heights) - kWristHangFraction * height;
    for (MonitoredSample& s : window_) {
      s.sample.left.y() -= calibrated_floor_;
      s.sample.right.y() -= calibrated_floor_;
      ready->push_back(s);
      Track(s.sample, warnings);
    }
  }
  if (separations.empty()) {
    window_.clear();
    window_.shrink_to_fit();
    return;
  }
  const std::string seconds = StrCat(Rounded(options_.window_seconds), " s");
  const float separation = Median(separations);
  if (separation < kMinWristSeparationFraction * height) {
    const double caller_units = separation / MetresPerUnit(convention_.unit);
    std::string message = StrCat("wrists ", Rounded(caller_units), " units apart on median over the first ", seconds,
                                 " (", Rounded(separation), " m as declared in ", UnitName(convention_.unit),
                                 "; one person's wrists are at least ", Rounded(kMinWristSeparationFraction * height),
                                 " m apart at a height of ", Rounded(height), " m)");
    message += UnitHint(caller_units, convention_.unit);
    warnings->push_back({InputWarning::Kind::kUnits, std::move(message)});
  }
  if (!calibrate_floor_) {
    const float lower = Median(lower_heights);
    // Another axis holding the wrists at hanging height names the likelier mistake.
    const std::optional<std::string> other_up = UpAxisHoldingHangingWrists();
    const std::string other_up_hint = other_up
                                          ? StrCat(", or ", *other_up, " up declared as ", UpAxisName(convention_.up),
                                                   " up: along it the wrists hang where hands do; --up ", *other_up)
                                          : "";
    if (lower < -kBelowFloorFraction * height) {
      warnings->push_back(
          {InputWarning::Kind::kBelowFloor,
           StrCat("wrists below the floor: the lower wrist is ", Rounded(-lower), " m below it on median over ",
                  "the first ", seconds, " (wrong floor height, or the up axis ", UpAxisName(convention_.up),
                  " the wrong way round", other_up_hint, "?)")});
    } else if (lower > kAboveFloorFraction * height) {
      warnings->push_back(
          {InputWarning::Kind::kAboveFloor,
           StrCat("wrists far above the floor: the lower wrist is ", Rounded(lower), " m above it on median ",
                  "over the first ", seconds, ", higher than a raised hand reaches at a height of ", Rounded(height),
                  " m (floor declared too low? 'calibrate' estimates it", other_up_hint, ")")});
    } else if (lower < kUpAxisFloorFraction * height && other_up) {
      up_axis_reported_ = true;
      warnings->push_back(
          {InputWarning::Kind::kUpAxis,
           StrCat("the up axis looks wrong: along the declared up axis ", UpAxisName(convention_.up),
                  " the lower wrist is ", Rounded(lower), " m from the floor on median over the first ", seconds,
                  ", where no hand hangs, but along ", *other_up, " it is where hanging hands are (",
                  Rounded(kHangBand[0] * height), "-", Rounded(kHangBand[1] * height), " m at a height of ",
                  Rounded(height), " m): ", *other_up, " up declared as ", UpAxisName(convention_.up),
                  " up? (declare the up axis: --up ", *other_up, ", InputFrame.up)")});
    }
  }
  window_.clear();
  window_.shrink_to_fit();
}

std::string InputMonitor::CallerAxisName(int index, float sign) const {
  const Eigen::Vector3f caller =
      NativeBasis(convention_.up, convention_.handedness).transpose() * (sign * Eigen::Vector3f::Unit(index));
  Eigen::Index axis = 0;
  caller.cwiseAbs().maxCoeff(&axis);
  return StrCat(caller[axis] > 0 ? "+" : "-", std::string(1, static_cast<char>('X' + axis)));
}

std::optional<std::string> InputMonitor::UpAxisHoldingHangingWrists() const {
  // A horizontal native axis (and sign) along which the lower wrist's median sits where hanging
  // hands are, nearest the typical hang; the floor taken at 0 on it.
  const float height = options_.body_height;
  std::optional<std::string> best;
  float best_distance = 0.0f;
  for (int index : {0, 2}) {
    for (float sign : {1.0f, -1.0f}) {
      std::vector<float> lower;
      for (const MonitoredSample& s : window_) {
        if (BothTracked(s.sample)) lower.push_back(std::min(sign * s.sample.left[index], sign * s.sample.right[index]));
      }
      const float median = Median(std::move(lower));
      if (!(median >= kHangBand[0] * height && median <= kHangBand[1] * height)) continue;
      const float distance = std::abs(median - kWristHangFraction * height);
      if (!best || distance < best_distance) {
        best = CallerAxisName(index, sign);
        best_distance = distance;
      }
    }
  }
  return best;
}

void InputMonitor::TrackHeight(const WristSample& sample, std::vector<InputWarning>* warnings) {
  if (up_axis_reported_) return;
  if (!heights_.empty() && !(sample.time - heights_.back().time >= 0.2)) return;
  heights_.push_back({sample.time, 0.5f * (sample.left + sample.right)});
  while (heights_.size() > 2 && sample.time - heights_[1].time >= kVerticalTravelSeconds) heights_.pop_front();
  const Waypoint& first = heights_.front();
  const Waypoint& last = heights_.back();
  const float rise = last.middle.y() - first.middle.y();
  if (!(std::abs(rise) > kVerticalTravelFraction * options_.body_height)) return;
  // The true up axis: the horizontal one holding the wrists' midpoint at a hanging hand's height
  // (its floor taken at 0), else the one that moved least meanwhile.
  float low[3], high[3], mean[3];
  for (int axis : {0, 2}) {
    low[axis] = high[axis] = first.middle[axis];
    mean[axis] = 0.0f;
    for (const Waypoint& w : heights_) {
      low[axis] = std::min(low[axis], w.middle[axis]);
      high[axis] = std::max(high[axis], w.middle[axis]);
      mean[axis] += w.middle[axis] / static_cast<float>(heights_.size());
    }
  }
  const auto hangs = [&](int axis) {
    const float level = std::abs(mean[axis]) / options_.body_height;
    return level >= kHangBand[0] && level <= kHangBand[1];
  };
  int index = high[0] - low[0] < high[2] - low[2] ? 0 : 2;
  if (hangs(0) != hangs(2)) index = hangs(0) ? 0 : 2;
  const float level = mean[index];
  const std::string other_up = CallerAxisName(index, level >= 0.0f ? 1.0f : -1.0f);
  up_axis_reported_ = true;
  warnings->push_back(
      {InputWarning::Kind::kUpAxis,
       StrCat("the up axis looks wrong: the wrists ", rise > 0 ? "rose " : "sank ", Rounded(std::abs(rise)),
              " m along the declared up axis ", UpAxisName(convention_.up), " within ", Rounded(last.time - first.time),
              " s, faster than anyone climbs (the body travels along it, so it is ", "horizontal): ", other_up,
              " up declared as ", UpAxisName(convention_.up), " up? (declare the up axis: --up ", other_up,
              ", InputFrame.up)")});
}

void InputMonitor::TrackSides(const WristSample& sample, std::vector<InputWarning>* warnings) {
  if (swap_reported_) return;
  const Eigen::Vector3f middle = 0.5f * (sample.left + sample.right);
  if (waypoint_count_ > 0) {
    const Waypoint& last = waypoints_[(waypoint_count_ - 1) % kWaypoints];
    if (!(sample.time - last.time >= kWaypointSeconds)) return;
  }
  waypoints_[waypoint_count_ % kWaypoints] = {sample.time, middle};
  ++waypoint_count_;
  if (waypoint_count_ < kWaypoints) return;
  const Waypoint& oldest = waypoints_[waypoint_count_ % kWaypoints];  // kWaypoints − 1 steps back
  Eigen::Vector3f travel = (middle - oldest.middle) / static_cast<float>(sample.time - oldest.time);
  travel.y() = 0.0f;
  const float speed = travel.norm();
  if (!(speed > kTravelSpeed)) return;
  const Eigen::Vector3f along = travel / speed;
  const Eigen::Vector3f left_of_travel(along.z(), 0.0f, -along.x());  // up × travel
  const Eigen::Vector3f apart = sample.left - sample.right;
  // Walking backwards also puts the left wrist on the right of the travel. What tells it from a
  // swap: the wrist ahead of the body swings higher (the elbow bends on the forward swing), so the
  // wrist leading along the travel is the higher one while walking forwards, whichever label it
  // carries. A swap is voted only while that says "forwards" clearly, or at a speed nobody walks
  // backwards (running, elbows bent, also raises the hand behind: the cue only holds for walks);
  // a correct side is voted either way.
  const float lead_times_rise = 0.5f * apart.dot(along) * apart.y();
  facing_evidence_ = (1.0f - kFacingSmoothing) * facing_evidence_ + kFacingSmoothing * lead_times_rise;
  facing_scale_ = (1.0f - kFacingSmoothing) * facing_scale_ + kFacingSmoothing * std::abs(lead_times_rise);
  const float side = apart.dot(left_of_travel);
  if (std::abs(side) < kMinSideOffsetFraction * options_.body_height) return;
  const bool forwards = speed > kBackwardsWalkSpeed || facing_evidence_ > kMinForwardEvidence * facing_scale_;
  if (side < 0 && !forwards) return;
  ++votes_;
  if (side < 0) ++swapped_votes_;
  if (votes_ < kSwapVotes) return;
  if (static_cast<float>(swapped_votes_) >= kSwapVoteShare * static_cast<float>(votes_)) {
    swap_reported_ = true;
    warnings->push_back(
        {InputWarning::Kind::kSwapped,
         StrCat("left and right look swapped: while the body travelled, the left wrist was on its right in ",
                swapped_votes_, " of ", votes_, " looks (left and right samples exchanged, or a mirrored frame: ",
                convention_.handedness == Handedness::kRight ? "left" : "right", "-handed, not ",
                HandednessName(convention_.handedness), "-handed as declared?)")});
  }
  votes_ = swapped_votes_ = 0;
}

}  // namespace mocap

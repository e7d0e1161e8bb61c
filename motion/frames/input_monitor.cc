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
        TrackSides(sample, warnings);
      }
      return;
    }
    CloseWindow(ready, warnings);
  }
  WristSample shifted = sample;
  shifted.left.y() -= calibrated_floor_;
  shifted.right.y() -= calibrated_floor_;
  ready->push_back({shifted, index});
  TrackSides(shifted, warnings);
}

void InputMonitor::Finish(std::vector<MonitoredSample>* ready, std::vector<InputWarning>* warnings) {
  if (!window_done_ && !window_.empty()) CloseWindow(ready, warnings);
}

void InputMonitor::CloseWindow(std::vector<MonitoredSample>* ready, std::vector<InputWarning>* warnings) {
  window_done_ = true;
  const float height = options_.body_height;
  std::vector<float> separations, lower_heights;
  for (const MonitoredSample& s : window_) {
    separations.push_back((s.sample.left - s.sample.right).norm());
    lower_heights.push_back(std::min(s.sample.left.y(), s.sample.right.y()));
  }
  if (calibrate_floor_) {
    calibrated_floor_ = Median(lower_heights) - kWristHangFraction * height;
    for (MonitoredSample& s : window_) {
      s.sample.left.y() -= calibrated_floor_;
      s.sample.right.y() -= calibrated_floor_;
      ready->push_back(s);
      TrackSides(s.sample, warnings);
    }
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
    if (lower < -kBelowFloorFraction * height) {
      warnings->push_back(
          {InputWarning::Kind::kBelowFloor,
           StrCat("wrists below the floor: the lower wrist is ", Rounded(-lower), " m below it on median over ",
                  "the first ", seconds, " (wrong floor height, or the up axis ", UpAxisName(convention_.up),
                  " the wrong way round?)")});
    } else if (lower > kAboveFloorFraction * height) {
      warnings->push_back(
          {InputWarning::Kind::kAboveFloor,
           StrCat("wrists far above the floor: the lower wrist is ", Rounded(lower), " m above it on median ",
                  "over the first ", seconds, ", higher than a raised hand reaches at a height of ", Rounded(height),
                  " m (floor declared too low? 'calibrate' estimates it)")});
    }
  }
  window_.clear();
  window_.shrink_to_fit();
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

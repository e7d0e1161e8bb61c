#include "html_view/view_clip.h"

#include <cmath>
#include <iomanip>
#include <sstream>

#include <spdlog/spdlog.h>
#include <Eigen/Geometry>

#include "motion/bvh/bvh_reader.h"
#include "motion/bvh/bvh_writer.h"
#include "motion/core/frame_clock.h"
#include "motion/core/units.h"
#include "motion/skeleton/body_topology.h"
#include "motion/skeleton/local_motion.h"

namespace mocap::html_view {
namespace {

std::string Note(const BvhClip& clip) {
  std::ostringstream note;
  note << clip.num_frames() << " frames at " << std::setprecision(3) << clip.frame_rate() << " fps";
  return note.str();
}

// 0.1 mm is finer than any capture: keeps the page small.
double Rounded(double metres) { return std::round(metres * 1e4) / 1e4; }

// The BVH frame of each JSON frame: the BVH `mocap reconstruct` writes plays on the input's clock,
// the frame times of a dropout too long to bridge filled (motion/core/frame_clock.h), where the
// JSON has only the frames made. Frame for frame where the JSON has no frame rate or times (a
// file from before).
std::vector<long> ClockSlots(const nlohmann::json& reconstruction, const nlohmann::json& frames) {
  const nlohmann::json* started = reconstruction.contains("started") ? &reconstruction["started"] : nullptr;
  const double rate =
      started && started->is_object() && started->contains("frame_rate") && (*started)["frame_rate"].is_number()
          ? (*started)["frame_rate"].get<double>()
          : 0.0;
  auto time = [](const nlohmann::json& frame) {  // proto JSON leaves out a time of 0
    return frame.is_object() && frame.contains("time") && frame["time"].is_number() ? frame["time"].get<double>() : 0.0;
  };
  std::vector<long> slots(frames.size(), 0);
  for (size_t f = 1; f < frames.size(); ++f) {
    const long missing = rate > 0.0 ? FrameTimesMissing(time(frames[f]) - time(frames[f - 1]), 1.0 / rate) : 0;
    slots[f] = slots[f - 1] + 1 + missing;
  }
  return slots;
}

}  // namespace

nlohmann::json ClipJson(std::string_view name, std::string_view bvh_text) {
  nlohmann::json clip = {{"name", name}, {"bvh", bvh_text}};
  absl::StatusOr<BvhClip> parsed = ParseBvh(bvh_text, name);
  if (!parsed.ok()) {
    clip["error"] = std::string(parsed.status().message());
    return clip;
  }
  // The page reads what the product read: the clip as it writes files (the root's position as
  // this reader decided it, root_convention.h), on which three.js's BVHLoader agrees.
  clip["bvh"] = FormatBvh(*parsed);
  clip["note"] = Note(*parsed);
  const LocalMotion motion = MotionFromChannels(parsed->skeleton, parsed->channels, parsed->frame_time);
  absl::StatusOr<BodyTopology> body = AnalyseBody(parsed->skeleton, motion);
  if (!body.ok()) {
    spdlog::warn("{}: not read as a humanoid ({}); the page guesses its unit and takes +Y as up", name,
                 std::string(body.status().message()));
    return clip;
  }
  const Eigen::Quaternionf to_y_up = Eigen::Quaternionf::FromTwoVectors(body->up(), Eigen::Vector3f::UnitY());
  clip["metresPerUnit"] = MetresPerUnit(body->unit);
  clip["toYUp"] = {to_y_up.x(), to_y_up.y(), to_y_up.z(), to_y_up.w()};
  clip["pelvis"] = parsed->skeleton.joint(body->landmarks.pelvis).name;
  clip["head"] = parsed->skeleton.joint(body->landmarks.head).name;
  nlohmann::json landmarks = nlohmann::json::array();
  for (int joint : BodyLandmarkJoints(body->landmarks))
    landmarks.push_back(joint >= 0 ? parsed->skeleton.joint(joint).name : std::string());
  clip["landmarks"] = std::move(landmarks);
  return clip;
}

absl::StatusOr<nlohmann::json> ReconstructionTraces(const nlohmann::json& reconstruction) {
  const nlohmann::json* frames =
      reconstruction.is_object() && reconstruction.contains("frames") ? &reconstruction["frames"] : nullptr;
  if (!frames || !frames->is_array() || frames->empty())
    return absl::InvalidArgumentError("no \"frames\" to draw traces from");
  struct Field {
    const char* key;
    const char* label;
    const char* kind;
  };
  static constexpr Field kFields[] = {{"left_wrist", "left wrist (input)", "wrist"},
                                      {"right_wrist", "right wrist (input)", "wrist"},
                                      {"left_ankle", "left ankle (estimated)", "ankle"},
                                      {"right_ankle", "right ankle (estimated)", "ankle"}};
  const std::vector<long> slots = ClockSlots(reconstruction, *frames);
  nlohmann::json traces = nlohmann::json::array();
  try {
    for (const Field& field : kFields) {
      nlohmann::json points = nlohmann::json::array();
      double last[3] = {0, 0, 0};
      bool seen = false;
      for (size_t f = 0; f < frames->size(); ++f) {
        const nlohmann::json& frame = (*frames)[f];
        const nlohmann::json* p = frame.is_object() && frame.contains(field.key) ? &frame[field.key] : nullptr;
        double next[3] = {last[0], last[1], last[2]};
        if (p && p->is_object()) {  // proto JSON leaves out a point never set: repeat the last one
          next[0] = p->value("x", 0.0), next[1] = p->value("y", 0.0), next[2] = p->value("z", 0.0);
        }
        // Across a filled dropout the trace goes straight, as the BVH's body does.
        const long filled = f > 0 ? slots[f] - slots[f - 1] - 1 : 0;
        for (long k = 1; k <= filled; ++k) {
          const double s = static_cast<double>(k) / static_cast<double>(filled + 1);
          for (int i = 0; i < 3; ++i) points.push_back(Rounded(last[i] + s * (next[i] - last[i])));
        }
        seen = seen || (p && p->is_object());
        for (int i = 0; i < 3; ++i) points.push_back(Rounded(last[i] = next[i]));
      }
      if (seen) traces.push_back({{"label", field.label}, {"kind", field.kind}, {"points", std::move(points)}});
    }
  } catch (const nlohmann::json::exception& error) {
    return absl::InvalidArgumentError(std::string("a frame's point is not {x, y, z} numbers: ") + error.what());
  }
  return traces;
}

absl::StatusOr<nlohmann::json> ReconstructionConfidence(const nlohmann::json& reconstruction) {
  const nlohmann::json* frames =
      reconstruction.is_object() && reconstruction.contains("frames") ? &reconstruction["frames"] : nullptr;
  if (!frames || !frames->is_array() || frames->empty())
    return absl::InvalidArgumentError("no \"frames\" to take expected errors from");
  const std::vector<long> slots = ClockSlots(reconstruction, *frames);
  nlohmann::json errors = nlohmann::json::array();
  bool seen = false;
  try {
    for (size_t f = 0; f < frames->size(); ++f) {
      const nlohmann::json& frame = (*frames)[f];
      // A filled dropout's frames have no expected error of their own: 0, no halo.
      const long filled = f > 0 ? slots[f] - slots[f - 1] - 1 : 0;
      for (long k = 0; k < filled * kNumBodyLandmarks; ++k) errors.push_back(0.0);
      const nlohmann::json* e =
          frame.is_object() && frame.contains("expected_error") ? &frame["expected_error"] : nullptr;
      seen = seen || (e && e->is_object());
      // Proto JSON leaves out a landmark whose error is 0.
      for (const char* name : kBodyLandmarkNames)
        errors.push_back(e && e->is_object() ? Rounded(e->value(name, 0.0)) : 0.0);
    }
  } catch (const nlohmann::json::exception& error) {
    return absl::InvalidArgumentError(std::string("an expected error is not a number: ") + error.what());
  }
  if (!seen) return absl::NotFoundError("no frame has expected errors (a server from before them)");
  return errors;
}

}  // namespace mocap::html_view

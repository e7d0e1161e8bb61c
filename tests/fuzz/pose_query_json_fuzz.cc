// libFuzzer target: a `--query-pose` JSON file (mocap similar, mocapd similar) through the
// parser and, when it parses, the named pose's body points (docs/method.md B3–B4), as a search does.
#include <cstddef>
#include <cstdint>

#include <nlohmann/json.hpp>

#include "motion/similarity/named_pose.h"
#include "server/named_pose_convert.h"
#include "tools/similar_json/similar_json.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const nlohmann::json json = nlohmann::json::parse(data, data + size, nullptr, /*allow_exceptions=*/false);
  if (json.is_discarded()) return 0;
  absl::StatusOr<mocap::v1::NamedPose> parsed = mocap::NamedPoseFromJson(json);
  if (!parsed.ok()) return 0;
  // The proto as the server receives it, in the engine's terms.
  const mocap::NamedPose pose = mocap::FromProto(*parsed);
  (void)mocap::NamedPosePoints(pose, {});
  return 0;
}

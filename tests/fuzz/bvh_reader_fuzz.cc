// libFuzzer target: BVH text through the reader and, when it parses, the importer's analysis
// (rig model from the clip, the clip prepared on it), as an import of an untrusted file does.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "motion/bvh/bvh_reader.h"
#include "motion/preprocess/clip_preprocessor.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  // Small limits keep each input fast; the reader's own limits are tested elsewhere.
  absl::StatusOr<mocap::BvhClip> clip = mocap::ParseBvh(text, "fuzz.bvh", {.max_frames = 2000});
  if (!clip.ok()) return 0;
  absl::StatusOr<mocap::RigModel> rig = mocap::BuildRigModel(*clip, {});
  if (!rig.ok()) return 0;
  (void)mocap::PrepareClip(*clip, *rig, {});
  return 0;
}

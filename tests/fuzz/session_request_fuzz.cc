// libFuzzer target: a reconstruction request as the service handles it in-process: the bytes are
// a ReconstructTrajectoryRequest (session config + samples); the SessionDriver validates the
// config, pushes the samples in the slices the reactors use, and finishes, on a small synthetic
// database. Any config field and any sample values (NaN, huge, out of order, gaps) are reached.
#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "mocap/v1/reconstruction.pb.h"
#include "server/session_driver.h"
#include "tests/support/synthetic_database.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static mocap::ServerMetrics metrics;
  mocap::v1::ReconstructTrajectoryRequest request;
  if (!request.ParseFromArray(data, static_cast<int>(size))) return 0;
  // Bound the work per input (the service bounds it by message size and fair scheduling).
  if (request.samples().size() > 300) return 0;
  mocap::v1::SessionConfig config = request.config();
  if (config.overrides().ankle_candidates() > 64 || config.overrides().pose_neighbours() > 64) return 0;
  if (!config.overrides().has_ankle_candidates()) config.mutable_overrides()->set_ankle_candidates(32);
  if (!config.overrides().has_pose_neighbours()) config.mutable_overrides()->set_pose_neighbours(16);
  mocap::SessionLimits limits;
  limits.max_window_frames = 120;
  auto driver = mocap::SessionDriver::Create(config, mocap::testing::SharedSyntheticReconstructionSetup().database,
                                             "fuzz", limits, metrics);
  if (!driver.ok()) return 0;
  std::vector<mocap::v1::ReconstructResponse> replies;
  mocap::v1::WristSamples samples;
  *samples.mutable_samples() = request.samples();
  for (int begin = 0; begin < samples.samples_size(); begin += 4) {
    if (!(*driver)->Push(samples, begin, std::min(samples.samples_size(), begin + 4), &replies).ok()) return 0;
  }
  (void)(*driver)->Finish(&replies);
  return 0;
}

// Wrist trajectories for the reconstruction service, read on the client side: from a CSV of
// timestamped tracker samples, or from a BVH clip's forward kinematics (what mocap-eval feeds the
// engine, docs/method.md A8 / the standard split's input). Used by `mocap reconstruct` and `mocap-load`.
#pragma once

#include <array>
#include <filesystem>
#include <istream>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "mocap/v1/reconstruction.pb.h"

namespace mocap {

// Samples of a CSV file (comma-separated, one sample per line). The first non-blank line is the
// header, exactly
//   time,left_x,left_y,left_z,right_x,right_y,right_z[,left_confidence,right_confidence
//   [,left_qw,left_qx,left_qy,left_qz,right_qw,right_qx,right_qy,right_qz]]
// (spaces around names and values are ignored). Time in seconds, positions in the session's
// declared input frame (by default metres, world Y up); the quaternions are the tracked devices'
// orientations (SessionConfig.input_frame.tracked_device), an empty cell leaving them unset.
// Blank lines and lines starting with '#' are skipped. Values are decimal numbers; "nan" and "inf"
// (any case, optional sign) are accepted as data — the server refuses such samples itself. With
// the confidence columns, an empty cell leaves that confidence unset (the server reads 1); a
// finite confidence must lie in 0..1. Samples are returned in file order, as written (timestamps
// are not checked: the server reports samples that do not increase).
// Errors: NotFound when the file cannot be read; InvalidArgument "FILE:LINE: what was expected"
// for a bad header, a wrong number of fields or a value that is not a number; InvalidArgument when
// the file holds no samples.
absl::StatusOr<std::vector<v1::WristSample>> WristsFromCsv(const std::filesystem::path& path);
// The same from a stream; `name` stands for the file in messages.
absl::StatusOr<std::vector<v1::WristSample>> WristsFromCsv(std::istream& in, const std::string& name);

// The two wrist trajectories of a BVH clip on any humanoid rig: the clip is read with motion/bvh,
// its rig analysed (landmarks, units, up axis) and converted to metres and Y up as an import does
// (BuildRigModel + PrepareClip, at the clip's own frame rate), and the wrist landmarks' positions
// taken by forward kinematics. Sample f has time f / frame rate (seconds from 0). Each coordinate
// gets Gaussian noise of σ = noise_cm centimetres (0: none) from a std::mt19937 seeded with `seed`,
// drawn in mocap-eval's order (per frame, per axis: left then right), so the same clip, σ and seed
// give the same samples as mocap-eval's input for a clip run at the clip's rate.
// Errors: those of ReadBvhFile (NotFound, InvalidArgument "FILE:LINE: ..."), those of the rig
// analysis (no humanoid found), InvalidArgument for a negative or non-finite noise_cm.
absl::StatusOr<std::vector<v1::WristSample>> WristsFromBvh(const std::filesystem::path& path, double noise_cm,
                                                           unsigned seed);

// Moves every sample by one offset so that the first sample with finite positions has its wrists'
// midpoint at the origin on the two axes other than `up_axis` (0, 1, 2 for X, Y, Z; the height is
// kept, so a declared floor stays right). For trackers that report a game engine's world, where
// positions kilometres from the origin are normal and the server refuses them (`mocap reconstruct
// --recenter`). The reconstruction does not depend on where the body stands, so only the output's
// position moves with it. Returns the offset subtracted (caller units; zero when no sample is finite).
std::array<double, 3> RecenterHorizontally(std::vector<v1::WristSample>* samples, int up_axis);

}  // namespace mocap

// The reconstruction's tunables, one row each (issue #22): the option a row sets
// (ReconstructionOptions, docs/method.md), its field of MethodOverrides (reconstruction.proto),
// the range a client may ask for, and the `mocap reconstruct` flag that asks for it. The server
// applies, checks and echoes a session's overrides from this table, and the CLI makes its flags
// from it: a new tunable is one row here and one proto field.
#pragma once

#include <span>
#include <string_view>

#include "absl/status/status.h"
#include "mocap/v1/reconstruction.pb.h"
#include "motion/reconstruct/reconstruction_options.h"

namespace mocap {

inline constexpr int kMaxAnkleCandidates = 5000;
inline constexpr int kMaxPoseNeighbours = 2000;

struct MethodTunable {
  std::string_view field;  // MethodOverrides field
  std::string_view flag;   // `mocap reconstruct` flag; empty: none
  std::string_view help;   // what it is, for the flag's --help
  double min, max;         // allowed values, both included
  double (*get)(const ReconstructionOptions&);
  void (*set)(ReconstructionOptions&, double);
};

// Every numeric (and boolean, as 0/1) field of MethodOverrides; `foot_contacts`, an enum, is
// converted apart.
std::span<const MethodTunable> MethodTunables();

// The fields set in `overrides` written into `options`, then every tunable's value checked
// against its range: InvalidArgument naming the first out of range ("overrides.FIELD must be in
// [min, max], not value").
absl::Status ApplyMethodOverrides(const v1::MethodOverrides& overrides, ReconstructionOptions* options);
// Every tunable's value in `options` written to its field (the effective configuration).
void WriteMethodOverrides(const ReconstructionOptions& options, v1::MethodOverrides* overrides);
// One tunable's field set to `value` (rounded for an integer field).
void SetMethodOverride(const MethodTunable& tunable, double value, v1::MethodOverrides* overrides);

}  // namespace mocap

// What `mocap reconstruct` says about samples the server refused (issue #25, "honest answers"):
// refusals grouped by what was wrong, so 4,551 refused samples read as one cause with its count,
// and for a run that produced nothing, one message naming the cause and the fix.
#pragma once

#include <string>
#include <vector>

#include "mocap/v1/reconstruction.pb.h"

namespace mocap {

struct RefusalGroup {
  std::string reason;  // the first refusal of the group, as the server worded it
  long count = 0;
  long first_sample = 0;  // index of its first sample
};

// Grouped by the reason's words (numbers aside: "a wrist coordinate of 12003 m" and "... of 12004
// m" are one group), the largest group first.
std::vector<RefusalGroup> GroupRefusals(const google::protobuf::RepeatedPtrField<v1::SampleRejected>& rejected);

// Lines for stderr: each group with its count and first sample, at most `max_groups` of them.
std::string DescribeRefusals(const std::vector<RefusalGroup>& groups, size_t max_groups = 5);

// The error of a run where no frame came out of `samples_sent` samples: every cause with its
// count and what to do about it.
std::string NothingReconstructedMessage(const std::vector<RefusalGroup>& groups, long samples_sent);

}  // namespace mocap

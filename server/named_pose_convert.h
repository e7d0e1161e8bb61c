// mocap.v1.NamedPose <-> NamedPose (motion/similarity/named_pose.h): a pose given as named joint
// positions with its landmarks, as PoseSearch queries and `--query-pose` JSON files carry it.
#pragma once

#include "mocap/v1/pose_search.pb.h"
#include "motion/similarity/named_pose.h"

namespace mocap {

NamedPose FromProto(const v1::NamedPose& pose);
void ToProto(const NamedPose& pose, v1::NamedPose* out);

}  // namespace mocap

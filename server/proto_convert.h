// Domain <-> mocap.v1 messages, in one place (docs/STYLE.md: conversion at each boundary).
#pragma once

#include "mocap/v1/motion_store.pb.h"
#include "motion/preprocess/clip_preprocessor.h"
#include "storage/import_writer.h"
#include "storage/motion_store.h"

namespace mocap {

void ToProto(const DatabaseSummary& summary, v1::DatabaseSummary* out);
// Skeleton offsets in metres (rig offsets are in the source unit).
void ToProto(const RigModel& rig, v1::Skeleton* out);
void ToProto(const ClipSummary& clip, v1::Clip* out);
void ToProto(const std::string& database, const ImportTotals& totals, v1::ImportBvhResponse* out);

}  // namespace mocap

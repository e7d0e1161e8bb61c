// Early-return helpers for absl::Status / absl::StatusOr, the error type used throughout mocap.
#pragma once

#include "absl/status/status.h"
#include "absl/status/statusor.h"

#define MOCAP_CONCAT_INNER_(a, b) a##b
#define MOCAP_CONCAT_(a, b) MOCAP_CONCAT_INNER_(a, b)

// Returns the status from the enclosing function when `expr` is not OK.
#define MOCAP_RETURN_IF_ERROR(expr)                                                     \
  do {                                                                                  \
    if (absl::Status _mocap_status = (expr); !_mocap_status.ok()) return _mocap_status; \
  } while (false)

// `lhs = value of expr`, or return its status from the enclosing function.
#define MOCAP_ASSIGN_OR_RETURN(lhs, expr) \
  MOCAP_ASSIGN_OR_RETURN_IMPL_(MOCAP_CONCAT_(_mocap_statusor_, __LINE__), lhs, expr)
#define MOCAP_ASSIGN_OR_RETURN_IMPL_(tmp, lhs, expr) \
  auto tmp = (expr);                                 \
  if (!tmp.ok()) return std::move(tmp).status();     \
  lhs = std::move(tmp).value()

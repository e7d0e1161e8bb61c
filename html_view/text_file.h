// Whole-file text input and output for the page writers (BVH and JSON in, HTML out).
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "absl/status/status.h"
#include "absl/status/statusor.h"

namespace mocap::html_view {

// NotFound when the file cannot be read.
absl::StatusOr<std::string> ReadTextFile(const std::filesystem::path& path);

// DataLoss when the file cannot be written.
absl::Status WriteTextFile(const std::filesystem::path& path, std::string_view text);

}  // namespace mocap::html_view

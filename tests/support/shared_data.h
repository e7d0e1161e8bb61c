// Access to ../shared/data for tests (over eval/datasets): unpacks a set on first use, or tells why it cannot.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mocap::testing {

// Folder holding the unpacked set `name` ("bandai-namco-1", "bandai-namco-2", "cmu-cc"), unpacking
// it with shared/data/unpack.sh into the cache folder when needed. nullopt (with `why`) when the
// shared data is not there. Thread-safe for gtest's one-thread use.
std::optional<std::filesystem::path> SharedDataSet(std::string_view name, std::string* why);

// Sorted .bvh files of a folder.
std::vector<std::filesystem::path> BvhFilesIn(const std::filesystem::path& folder);

// tests/testdata in the source tree.
std::filesystem::path TestDataDir();

}  // namespace mocap::testing

// Declares `var` as the set's folder or skips the test with a clear message.
#define MOCAP_REQUIRE_SHARED_DATA(var, name)                                         \
  std::filesystem::path var;                                                         \
  {                                                                                  \
    std::string mocap_why;                                                           \
    auto mocap_dir = ::mocap::testing::SharedDataSet(name, &mocap_why);              \
    if (!mocap_dir) GTEST_SKIP() << "shared motion data unavailable: " << mocap_why; \
    var = *mocap_dir;                                                                \
  }

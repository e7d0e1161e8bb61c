// Where `mocap reconstruct -o OUTPUT` writes: OUTPUT.bvh and OUTPUT.json. A user who names the
// BVH itself (`-o walk.bvh`, as `mocap export -o FILE.bvh` and `mocap view -o view.html` take a
// file) means walk.bvh and walk.json, not walk.bvh.bvh.
#pragma once

#include <string>

namespace mocap::cli {

struct ReconstructionOutputPaths {
  std::string bvh, json;
};

// OUTPUT with a trailing ".bvh" or ".json" (any case) taken off, then each file's extension added.
ReconstructionOutputPaths OutputPathsOf(const std::string& output);

}  // namespace mocap::cli

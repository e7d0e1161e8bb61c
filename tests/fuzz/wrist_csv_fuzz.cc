// libFuzzer target: the wrist CSV reader of `mocap reconstruct --csv` and mocap-load.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "client/wrist_input/wrist_source.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  (void)mocap::WristsFromCsv(in, "fuzz.csv");
  return 0;
}

// The runs mocap-eval can make (eval/experiments.h): device runs of every experiment when asked
// for by name, only the method and the lookup by default.
#include "eval/experiments.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

namespace mocap::eval {
namespace {

bool Has(const std::vector<Experiment>& runs, const std::string& name) {
  return std::any_of(runs.begin(), runs.end(), [&](const Experiment& e) { return e.name == name; });
}

TEST(ExperimentsTest, EveryRunCanBeAskedForOnADeviceButNoiseLevels) {
  const ReconstructionOptions base;
  const std::vector<Experiment> by_default = MakeDeviceExperiments(base);
  EXPECT_TRUE(Has(by_default, "full@phone_ar"));
  EXPECT_TRUE(Has(by_default, "nearest_neighbour@phone_ar"));
  EXPECT_FALSE(Has(by_default, "lag_5@phone_ar"));
  const std::vector<Experiment> every = MakeDeviceExperiments(base, true);
  for (const char* name :
       {"full@phone_ar", "lag_5@tracker_90hz", "full_no_collars@controllers_72hz", "window_50@dropout_2s"}) {
    EXPECT_TRUE(Has(every, name)) << name;
  }
  for (const Experiment& e : every) {
    EXPECT_EQ(e.group, "device") << e.name;
    EXPECT_EQ(e.name.find("noise_"), std::string::npos) << e.name;  // the device is the noise
    EXPECT_EQ(e.noise_cm, 0.0) << e.name;
  }
  // The run keeps its options: a fixed lag on a device is still a fixed lag.
  const auto lag =
      std::find_if(every.begin(), every.end(), [](const Experiment& e) { return e.name == "lag_5@phone_ar"; });
  ASSERT_NE(lag, every.end());
  EXPECT_EQ(lag->options.mode, StreamMode::kFixedLag);
  EXPECT_EQ(lag->options.lag, 5);
}

}  // namespace
}  // namespace mocap::eval

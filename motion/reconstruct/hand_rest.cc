#include "motion/reconstruct/hand_rest.h"

namespace mocap {

bool HandRestDetector::Update(double time, const Eigen::Vector3f& hand, const Eigen::Vector3f& other_hand) {
  if (put_down_) {
    if ((hand - rest_place_).norm() <= kPickUpDistance) return true;
    put_down_ = false;  // picked up
    window_.clear();
  }
  window_.push_back({time, hand, other_hand});
  while (window_.size() > 1 && time - window_[1].time >= kPutDownSeconds) window_.pop_front();
  if (time - window_.front().time < kPutDownSeconds) return false;
  Eigen::Vector3f mean = Eigen::Vector3f::Zero();
  for (const Sample& s : window_) mean += s.hand;
  mean /= static_cast<float>(window_.size());
  float other_travel = 0.0f;
  for (size_t i = 0; i < window_.size(); ++i) {
    if ((window_[i].hand - mean).norm() > kStillRadius) return false;
    if (i > 0) other_travel += (window_[i].other - window_[i - 1].other).norm();
  }
  if (other_travel < kOtherHandTravel) return false;
  put_down_ = true;
  rest_place_ = mean;
  return true;
}

}  // namespace mocap

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
  if (wrist_span_ > 0.0f && (other_hand - hand).norm() > kOutOfReachMargin * wrist_span_) {
    // The still run up to this sample, and how far the other hand went along it.
    size_t first = window_.size() - 1;
    float other_travel = 0.0f;
    while (first > 0 && (window_[first - 1].hand - hand).norm() <= kStillRadius) {
      other_travel += (window_[first].other - window_[first - 1].other).norm();
      --first;
    }
    if (time - window_[first].time >= kEarlyStillSeconds && other_travel >= kOtherHandTravel) {
      SetDown(hand, window_[first].other, other_hand);
      return true;
    }
  }
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
  Eigen::Vector3f walked = window_.back().other - window_.front().other;
  walked.y() = 0.0f;
  if (walked.norm() < kWalkedAway) return false;
  SetDown(mean, window_.front().other, window_.back().other);
  return true;
}

void HandRestDetector::SetDown(const Eigen::Vector3f& place, const Eigen::Vector3f& other_then,
                               const Eigen::Vector3f& other_now) {
  put_down_ = true;
  rest_place_ = place;
  other_travel_ = other_now - other_then;
  other_travel_.y() = 0.0f;
}

}  // namespace mocap

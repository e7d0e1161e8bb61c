// FrameHistory<T>: one value per frame of a segment, addressed by the frame's number in the
// segment, that forgets frames nobody will read again. A streaming session runs for hours; its
// per-frame state must be bounded by the window and lag it looks back over, not by its length
// (issue #14: a session grew ~118 kB per 1,000 frames).
//
// Storage is contiguous (a span of the kept frames feeds the A2 fit) and compacted in amortised
// O(1): the forgotten prefix is erased once it is at least as long as what is kept.
#pragma once

#include <algorithm>
#include <cassert>
#include <span>
#include <vector>

namespace mocap {

template <typename T>
class FrameHistory {
 public:
  // Frames in the segment so far (forgotten ones included): the next frame's number.
  int size() const { return first_ + static_cast<int>(items_.size()) - dropped_; }
  bool empty() const { return size() == 0; }
  // The first frame still held.
  int first() const { return first_; }

  void push_back(T value) { items_.push_back(std::move(value)); }
  template <typename It>
  void append(It begin, It end) {
    items_.insert(items_.end(), begin, end);
  }

  const T& operator[](int frame) const { return items_[Slot(frame)]; }
  T& operator[](int frame) { return items_[Slot(frame)]; }
  const T& back() const { return items_.back(); }
  T& back() { return items_.back(); }

  // Frames [from, size()) as one contiguous span (from ≥ first()).
  std::span<const T> Since(int from) const { return std::span<const T>(items_).subspan(Slot(from)); }

  // Frames before `frame` will not be read again.
  void ForgetBefore(int frame) {
    if (frame <= first_) return;
    if (frame > size()) frame = size();
    dropped_ += frame - first_;
    first_ = frame;
    const size_t kept = items_.size() - static_cast<size_t>(dropped_);
    if (static_cast<size_t>(dropped_) >= std::max<size_t>(kept, 64)) {
      items_.erase(items_.begin(), items_.begin() + dropped_);
      dropped_ = 0;
    }
  }

  // Values stored, the forgotten prefix awaiting compaction included.
  int stored() const { return static_cast<int>(items_.size()); }

 private:
  size_t Slot(int frame) const {
    assert(frame >= first_ && frame < size());
    return static_cast<size_t>(frame - first_ + dropped_);
  }

  std::vector<T> items_;
  int first_ = 0;    // frame number of the first held frame
  int dropped_ = 0;  // forgotten items still at the front of items_
};

}  // namespace mocap

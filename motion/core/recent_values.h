// The last values of a per-frame history, in a ring allocated once: what the causal stages keep of
// the frames before (the motion guard's hands, the jump detector's noise, the footskate cleanup's
// ankle estimates). Pushing never allocates, so the per-frame loop stays allocation-free.
#pragma once

#include <algorithm>
#include <cassert>
#include <cstddef>
#include <span>
#include <vector>

namespace mocap {

template <typename T>
class RecentValues {
 public:
  explicit RecentValues(size_t capacity = 0) : values_(capacity) {}

  // Keeps up to `capacity` values from now on, forgetting every value kept (allocates).
  void Resize(size_t capacity) {
    values_.assign(capacity, T{});
    Clear();
  }
  void Clear() {
    next_ = 0;
    size_ = 0;
  }
  // Adds the newest value; past capacity the oldest is forgotten. A ring of capacity 0 keeps none.
  void Push(const T& value) {
    if (values_.empty()) return;
    values_[next_] = value;
    next_ = (next_ + 1) % values_.size();
    size_ = std::min(size_ + 1, values_.size());
  }

  size_t size() const { return size_; }
  size_t capacity() const { return values_.size(); }
  bool empty() const { return size_ == 0; }

  // The value `back` pushes before the newest: Back(0) is the newest, Back(size() - 1) the oldest
  // kept.
  const T& Back(size_t back) const {
    assert(back < size_);
    return values_[(next_ + values_.size() - 1 - back) % values_.size()];
  }
  // Every value kept, in no particular order (for order-free summaries: a median, a maximum).
  std::span<const T> Unordered() const { return {values_.data(), size_}; }

 private:
  std::vector<T> values_;
  size_t next_ = 0;  // where the next value goes
  size_t size_ = 0;
};

}  // namespace mocap

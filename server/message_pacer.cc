#include "server/message_pacer.h"

#include <algorithm>
#include <cmath>

namespace mocap {
namespace {

using Duration = MessagePacer::Clock::duration;

Duration Seconds(double seconds) {
  return std::chrono::duration_cast<Duration>(std::chrono::duration<double>(seconds));
}

// Tenants whose budget is full again are forgotten once the table holds this many.
constexpr size_t kPruneAbove = 1024;

}  // namespace

MessagePacer::MessagePacer(const MessagePacing& pacing)
    : interval_(pacing.messages_per_second > 0 ? Seconds(1.0 / pacing.messages_per_second) : Duration::zero()),
      tolerance_(interval_ *
                 static_cast<Duration::rep>(std::max(
                     0.0, std::floor(pacing.burst > 0 ? pacing.burst : pacing.messages_per_second / 10) - 1.0))) {}

MessagePacer::Clock::time_point MessagePacer::Charge(Key key, Clock::time_point now) {
  if (!enabled()) return now;
  MutexLock lock(&mutex_);
  if (paid_until_.size() > kPruneAbove)
    std::erase_if(paid_until_, [now](const auto& entry) { return entry.second <= now; });
  Clock::time_point& paid = paid_until_[key];
  paid = std::max(paid, now) + interval_;
  // The next message conforms once the paid time is within the burst's tolerance of the clock.
  return paid - tolerance_;
}

size_t MessagePacer::tracked_tenants() const {
  MutexLock lock(&mutex_);
  return paid_until_.size();
}

}  // namespace mocap

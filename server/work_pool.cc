#include "server/work_pool.h"

#include <sched.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <exception>

#include <spdlog/spdlog.h>

namespace mocap {

namespace {

// Pool threads run below gRPC's own threads: reading, writing and answering calls is short work
// that must not queue behind compute, or one tenant's saturating flood delays every other
// tenant's replies in the transport, whatever the pool's fair order (issue #14: the victim's p99).
// Bulk work runs below compute (Priority::kBulk).
constexpr int kComputeNiceness = 5;
constexpr int kBulkNiceness = 10;

// The pool whose task this thread runs (AnotherKeyWaits), null outside a pool thread.
thread_local const std::atomic<bool>* this_threads_key_waits = nullptr;

// A compute thread under a real-time policy: its priority there, and whether the task it runs now
// left it (a backlogged key's: work_pool.h).
struct RealTimeCompute {
  bool active = false;
  int policy = SCHED_OTHER;
  int priority = 0;
  bool demoted = false;
};
thread_local RealTimeCompute real_time_compute;

// Runs the calling compute thread's next task at SCHED_OTHER (nice as compute elsewhere) when its
// key is backlogged, at the thread's real-time priority otherwise (false also before the thread
// waits for work); a syscall only on a change.
void RunNextTaskInItsClass(bool backlogged) {
  RealTimeCompute& lane = real_time_compute;
  if (!lane.active || backlogged == lane.demoted) return;
  sched_param param{};
  param.sched_priority = backlogged ? 0 : lane.priority;
  if (sched_setscheduler(0, backlogged ? SCHED_OTHER : lane.policy, &param) != 0) {
    spdlog::warn("cannot move a compute thread {} the real-time policy: {}", backlogged ? "out of" : "back into",
                 std::strerror(errno));
    return;
  }
  if (backlogged) setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), kComputeNiceness);
  lane.demoted = backlogged;
}

// A server started under a real-time policy (`chrt --rr P mocapd serve`, systemd's
// CPUSchedulingPolicy=rr) keeps the same order in it: gRPC's threads and the prompt lane at P (as
// started), compute at P − 1, and bulk work out of it, at SCHED_OTHER's nice 10. Nice values mean
// nothing to a real-time thread, and a real-time policy keeps the server strictly above the host's
// other work: a SCHED_IDLE or nice-19 batch job sharing the cores still gets a share of the CPU
// beside a runnable normal thread (a server thread waited 4.8 ms behind one, `perf sched`), never
// beside a real-time one ([deployment.md](../docs/deployment.md#sizing)). Returns whether it set
// the thread's priority; false leaves it to its nice value.
bool RunThisThreadAtRealTime(WorkPool::Priority priority) {
  const int policy = sched_getscheduler(0);
  if (policy != SCHED_RR && policy != SCHED_FIFO) return false;
  sched_param param{};
  if (priority == WorkPool::Priority::kBulk) {  // back to SCHED_OTHER, then nice 10 as elsewhere
    if (sched_setscheduler(0, SCHED_OTHER, &param) != 0) {
      spdlog::warn("cannot take a bulk thread out of the real-time policy: {}", std::strerror(errno));
    }
    return false;
  }
  if (sched_getparam(0, &param) != 0) return false;
  param.sched_priority = std::max(sched_get_priority_min(policy), param.sched_priority - 1);
  if (sched_setscheduler(0, policy, &param) != 0) {
    spdlog::warn("cannot set a server thread's real-time priority: {}", std::strerror(errno));
    return true;
  }
  real_time_compute = {.active = true, .policy = policy, .priority = param.sched_priority, .demoted = false};
  return true;
}

}  // namespace

void RunThisThreadAt(WorkPool::Priority priority) {
  if (RunThisThreadAtRealTime(priority)) return;
  const int niceness = priority == WorkPool::Priority::kBulk ? kBulkNiceness : kComputeNiceness;
  if (setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), niceness) != 0) {
    spdlog::warn("cannot lower a server thread's priority: {}", std::strerror(errno));
  }
}

WorkPool::WorkPool(int threads, PromptLane prompt_lane, Clock clock, Clock work_clock, Priority priority)
    : clock_(std::move(clock)),
      work_clock_(std::move(work_clock)),
      thread_count_(threads),
      has_prompt_lane_(prompt_lane == PromptLane::kYes) {
  for (int i = 0; i < threads; ++i) {
    threads_.emplace_back([this, priority] {
      RunThisThreadAt(priority);
      Work(/*prompt_lane=*/false);
    });
  }
  if (has_prompt_lane_) threads_.emplace_back([this] { Work(/*prompt_lane=*/true); });
}

WorkPool::~WorkPool() {
  {
    MutexLock lock(&mutex_);
    stopping_ = true;
  }
  ready_.notify_all();
  prompt_ready_.notify_all();
  for (std::thread& thread : threads_) thread.join();
}

std::int64_t WorkPool::ThreadCpuNanoseconds() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<std::int64_t>(now.tv_sec) * 1'000'000'000 + now.tv_nsec;
}

std::int64_t WorkPool::SteadyNanoseconds() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

void WorkPool::Post(Key key, std::function<void()> task) {
  bool for_prompt_lane = false;
  {
    MutexLock lock(&mutex_);
    const std::int64_t now = clock_();
    KeyState& state = keys_[key];
    if (state.queue.empty() && state.running.empty()) state.busy_since = now;
    state.queue.push_back({next_sequence_++, std::move(task)});
    ++queued_;
    for_prompt_lane = ForPromptLaneLocked(state, now);
    UpdateKeyWaitsLocked(now);
  }
  if (for_prompt_lane) {
    prompt_ready_.notify_one();
  } else {
    ready_.notify_one();
  }
}

bool WorkPool::QuietLocked(const KeyState& state, std::int64_t now) {
  return state.queue.size() == 1 && state.running.empty() && state.long_until <= now;
}

bool WorkPool::ForPromptLaneLocked(const KeyState& state, std::int64_t now) const {
  return has_prompt_lane_ && !prompt_busy_ && running_ >= thread_count_ && QuietLocked(state, now);
}

bool WorkPool::LongKeysWaitLocked() const { return thread_count_ >= 2 && long_running_ >= thread_count_ - 1; }

bool WorkPool::AnotherKeyWaits() {
  return this_threads_key_waits != nullptr && this_threads_key_waits->load(std::memory_order_relaxed);
}

size_t WorkPool::queued() const {
  MutexLock lock(&mutex_);
  return queued_;
}

size_t WorkPool::running() const {
  MutexLock lock(&mutex_);
  return static_cast<size_t>(running_) + (prompt_busy_ ? 1 : 0);
}

std::map<WorkPool::Key, WorkPool::KeyState>::iterator WorkPool::PickLocked(std::int64_t now, bool prompt_lane,
                                                                           std::int64_t* tag) {
  const bool long_keys_wait = LongKeysWaitLocked();
  // The lane runs only while every other thread is busy: a free thread takes any key's task.
  if (prompt_lane && running_ < thread_count_) return keys_.end();
  auto best = keys_.end();
  std::int64_t best_tag = 0;
  for (auto it = keys_.begin(); it != keys_.end();) {
    KeyState& state = it->second;
    if (state.queue.empty()) {
      // Idle, owing nothing and short: forgotten (it would restart at the virtual time anyway).
      if (state.running.empty() && state.finish <= virtual_time_ && state.long_until <= now) {
        it = keys_.erase(it);
      } else {
        ++it;
      }
      continue;
    }
    if (prompt_lane && !QuietLocked(state, now)) {
      ++it;
      continue;
    }
    if (!prompt_lane && long_keys_wait && state.long_until > now) {
      ++it;
      continue;
    }
    std::int64_t key_tag = std::max(virtual_time_, state.finish);
    for (const Running& task : state.running) {
      key_tag += std::max<std::int64_t>(0, now - task.started - kMinimumCharge);
    }
    if (best == keys_.end() || key_tag < best_tag ||
        (key_tag == best_tag && state.queue.front().sequence < best->second.queue.front().sequence)) {
      best = it;
      best_tag = key_tag;
    }
    ++it;
  }
  *tag = best_tag;
  return best;
}

void WorkPool::FinishedLocked(Key key, const Running& task, std::int64_t now, std::int64_t worked) {
  auto it = keys_.find(key);
  KeyState& state = it->second;
  state.running.erase(std::find_if(state.running.begin(), state.running.end(), [&](const Running& r) {
    return r.started == task.started && r.long_key == task.long_key;
  }));
  const std::int64_t cost = now - task.started;
  state.finish += std::max<std::int64_t>(0, cost - kMinimumCharge);
  if (worked > kLongTask) state.long_until = now + kLongMemory;
  if (task.long_key) {
    --long_running_;
    ready_.notify_all();  // a thread may wait for the long keys' turn
  }
  if (state.queue.empty() && state.running.empty() && state.finish <= virtual_time_ && state.long_until <= now) {
    keys_.erase(it);
  }
}

void WorkPool::UpdateKeyWaitsLocked(std::int64_t now) {
  bool waits = false;
  if (running_ >= thread_count_) {
    const bool long_keys_wait = LongKeysWaitLocked();
    for (const auto& [key, state] : keys_) {
      // A long key held back by the long rule waits for a long task, not for the one asking; a
      // quiet key goes to the idle prompt lane.
      if (!state.queue.empty() && state.running.empty() && !(long_keys_wait && state.long_until > now) &&
          !ForPromptLaneLocked(state, now)) {
        waits = true;
        break;
      }
    }
  }
  key_waits_.store(waits, std::memory_order_relaxed);
}

void WorkPool::Work(bool prompt_lane) {
  this_threads_key_waits = &key_waits_;
  std::condition_variable& ready = prompt_lane ? prompt_ready_ : ready_;
  while (true) {
    std::function<void()> task;
    Key key = kSharedKey;
    Running running;
    bool backlogged = false;
    {
      MutexLock lock(&mutex_);
      auto picked = keys_.end();
      std::int64_t tag = 0;
      mutex_.Await(ready, [&]() ABSL_NO_THREAD_SAFETY_ANALYSIS {
        if (queued_ > 0) {
          running.started = clock_();
          picked = PickLocked(running.started, prompt_lane, &tag);
          if (picked != keys_.end()) return true;
        } else if (stopping_) {
          return true;
        }
        // A thread that left the real-time policy for a backlogged task waits at its real-time
        // priority: woken as a normal thread for a live session's task, it waited for a core
        // behind the very work it had left the policy for (the server's reply up to 20 ms beside
        // the rigs flood, stop 70). Only when it would wait: a syscall pair after every task cost
        // a flood of 3.5 MB messages a quarter of its frames.
        if (!prompt_lane) RunNextTaskInItsClass(false);
        return false;
      });
      if (queued_ == 0) return;  // stopping and drained
      key = picked->first;
      KeyState& state = picked->second;
      state.finish = std::max(state.finish, virtual_time_) + kMinimumCharge;  // the rest when it ends
      virtual_time_ = tag;
      running.long_key = state.long_until > running.started;
      backlogged = running.started - state.busy_since > kBackloggedAfter;
      if (running.long_key) ++long_running_;
      task = std::move(state.queue.front().task);
      state.queue.pop_front();
      state.running.push_back(running);
      --queued_;
      if (prompt_lane) {
        prompt_busy_ = true;
      } else {
        ++running_;
      }
      UpdateKeyWaitsLocked(running.started);
      if (stopping_ && queued_ == 0) {  // the threads that could not take the rest may end
        ready_.notify_all();
        prompt_ready_.notify_all();
      }
    }
    if (!prompt_lane) RunNextTaskInItsClass(backlogged);
    const std::int64_t work_began = work_clock_();
    try {
      task();
    } catch (const std::exception& error) {
      spdlog::error("work pool: a task threw and was dropped: {}", error.what());
    } catch (...) {
      spdlog::error("work pool: a task threw a non-standard exception and was dropped");
    }
    task = nullptr;  // its captures go before the charge: their destructors are the task's work
    const std::int64_t worked = work_clock_() - work_began;
    MutexLock lock(&mutex_);
    const std::int64_t now = clock_();
    FinishedLocked(key, running, now, worked);
    if (prompt_lane) {
      prompt_busy_ = false;
    } else {
      --running_;
    }
    UpdateKeyWaitsLocked(now);
  }
}

}  // namespace mocap

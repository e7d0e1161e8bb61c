// WorkPool: a fixed set of threads running queued tasks. gRPC callback handlers post their store,
// parsing and compute work here, so no gRPC thread blocks and no call owns a thread while it
// waits for its client.
//
// Fair sharing by cost (issue #24): every task is posted under a queue key (the services use the
// tenant). A key is charged the time its tasks run, measured, not counted: a tenant whose tasks
// take 100 ms each gets one for every hundred 1 ms tasks of another tenant, where turns by task
// gave it half the pool. This is start-time fair queueing: each key has a virtual finish time
// (what it has been charged); a free thread starts the head task of the key whose finish time,
// plus what its running tasks have used so far, is least, never below the pool's virtual time
// (the tag of the last task started), so a key that was idle banks no credit and a key that
// over-spent waits until the others have caught up. Ties go to the task posted first; every
// task is charged at least kMinimumCharge, so cheap tasks of several keys take turns one each.
// Within a key, first in first out. A task still holds its thread until it returns: long work
// must be cut into short tasks (a reconstruction runs a few samples per task, a pose search a few
// milliseconds of comparisons), which bounds how long another key waits for a thread.
//
// Where work is not cut (a task that turns out long: an import's batch, a caller's mistake), one
// thread is kept for short work: a key whose task worked longer than kLongTask in the last
// kLongMemory is "long", and with more than one thread long keys hold at most all threads but
// one. The other thread serves short keys (a live stream's slices) at once, or waits for one;
// long work of a tenant alone uses the rest of the pool. A task's work is its thread's CPU time, not the wall time it
// took: on a loaded machine a short task preempted for 20 ms would make its key long, and a tenant of 30 live streams
// then held one thread where it needed two (the queue, and its latency, grew to seconds).
//
// A task that has more to do than one slice (a session's backlog, a pose search) ends its slice
// early when another key waits for a thread (`AnotherKeyWaits`): the pool can only choose between
// keys when a task returns, so without this a live stream's sample waited for whatever was left
// of a slice another tenant had started (up to 20 ms; a sample alone takes ~1 ms).
//
// The prompt lane (optional): one more thread, at gRPC's priority, that runs only the task of a
// quiet key (that task alone queued, nothing of the key running, not long: a live session's next
// message) and only while every other thread is busy. The other threads run below gRPC's (see
// work_pool.cc), so beside a tenant whose thousands of messages a second keep gRPC's threads busy,
// a quiet tenant's sample waited for a slice to yield and then got a quarter of a core (perf
// sched, stop 60); the lane starts it at once at gRPC's priority. A key with work running or
// queued behind is served by the fair order on the other threads, so a tenant cannot hold the
// lane by sending more; and while a thread is free the lane stays out of the way (taking one
// tenant's streams at gRPC's priority whenever they were quiet cost that tenant's own p99 at 30
// streams 7.4 -> 11.0 ms: the lane then preempted the transport of its other streams).
//
// Under a real-time policy (work_pool.cc) a compute thread runs a backlogged key's task — one whose
// tasks have been queued or running without a break for kBackloggedAfter: a flood, a long search,
// a message of 80,000 samples — at SCHED_OTHER, and returns to its real-time priority for the next
// key that is not, or before it waits for work. Real-time work that fills every core starves everything at SCHED_OTHER
// (the kernel's workers, the network's softirq thread, a co-located client), and the kernel then runs those for up to
// 50 ms of each second above every real-time thread, the live sessions' too
// (`perf sched`, stop 70: the victim's thread waited 41 ms once a second beside such a flood).
#pragma once

#include <atomic>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <thread>
#include <utility>
#include <vector>
#include "motion/core/mutex.h"

namespace mocap {

class WorkPool {
 public:
  using Key = std::uint64_t;
  static constexpr Key kSharedKey = 0;  // work not attributed to a tenant (yet)
  // Nanoseconds of a monotonic clock; tests pass a clock their tasks advance.
  using Clock = std::function<std::int64_t()>;
  static constexpr std::int64_t kMinimumCharge = 50'000;  // ns
  // Longer than any sliced task, and than a live session's setup (16–34 ms measured on a loaded
  // 2-core machine: at 20 ms a setup made a live stream long for kLongMemory).
  static constexpr std::int64_t kLongTask = 50'000'000;       // ns
  static constexpr std::int64_t kLongMemory = 2'000'000'000;  // ns
  // Longer than a live session's message or setup: a key busy this long without a break is
  // backlogged (under a real-time policy its tasks leave it).
  static constexpr std::int64_t kBackloggedAfter = 100'000'000;  // ns

  enum class PromptLane { kNo, kYes };
  // How far below gRPC's priority the pool's threads run (work_pool.cc): compute (nice 5) below
  // the transport, and bulk work (nice 10: imports, exports, the store's calls) below compute, so
  // that one tenant's imports do not halve the core a live session of another tenant computes on
  // (issue #24: 2.1× its p99 beside two import loops when both ran at nice 5).
  enum class Priority { kCompute, kBulk };

  // `clock` times the fair shares; `work_clock` what a task itself worked (the calling thread's
  // CPU time; tests pass the clock their tasks advance for both).
  explicit WorkPool(int threads, Clock clock = SteadyNanoseconds, Clock work_clock = ThreadCpuNanoseconds)
      : WorkPool(threads, PromptLane::kNo, std::move(clock), std::move(work_clock)) {}
  // `threads` below gRPC's priority, and with kYes the prompt lane's thread beside them.
  WorkPool(int threads, PromptLane prompt_lane, Clock clock = SteadyNanoseconds,
           Clock work_clock = ThreadCpuNanoseconds, Priority priority = Priority::kCompute);
  WorkPool(int threads, Priority priority)
      : WorkPool(threads, PromptLane::kNo, SteadyNanoseconds, ThreadCpuNanoseconds, priority) {}
  // Runs the queued tasks, then joins the threads.
  ~WorkPool();
  WorkPool(const WorkPool&) = delete;
  WorkPool& operator=(const WorkPool&) = delete;

  // Thread-safe. A task that throws is logged and dropped (last resort: callers catch their own).
  void Post(std::function<void()> task) { Post(kSharedKey, std::move(task)); }
  void Post(Key key, std::function<void()> task);

  // Tasks queued and not yet started, over all keys.
  size_t queued() const;
  // Tasks running now; a task counts until its cost is charged to its key.
  size_t running() const;

  // Whether, on a thread of this pool, a task of another key waits for a thread now (every
  // thread is busy, and the key has nothing running): the calling task should end its slice at
  // the next point where it can. Lock-free; false outside a pool thread.
  static bool AnotherKeyWaits();

  static std::int64_t SteadyNanoseconds();
  static std::int64_t ThreadCpuNanoseconds();

 private:
  struct Queued {
    std::uint64_t sequence;  // posting order, over all keys
    std::function<void()> task;
  };
  struct Running {
    std::int64_t started = 0;
    bool long_key = false;  // a long key's: counted in long_running_
  };
  struct KeyState {
    std::deque<Queued> queue;
    std::int64_t finish = 0;       // virtual time: what the key's finished tasks were charged
    std::vector<Running> running;  // its tasks running now
    std::int64_t long_until = 0;   // a task of it ran longer than kLongTask: long until then
    std::int64_t busy_since = 0;   // when it last got a task with none queued or running
  };

  void Work(bool prompt_lane);
  // The key whose head task starts next on the prompt lane's thread or another, and its start tag;
  // end() when no queued task may start there.
  std::map<Key, KeyState>::iterator PickLocked(std::int64_t now, bool prompt_lane, std::int64_t* tag)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  // A quiet key: its one task queued and nothing running, and not long (the prompt lane's work).
  static bool QuietLocked(const KeyState& state, std::int64_t now);
  // Whether the idle prompt lane takes the key's task: it is quiet and every other thread is busy.
  bool ForPromptLaneLocked(const KeyState& state, std::int64_t now) const ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  // Charges a finished task that worked `worked` ns and forgets idle keys with nothing owed.
  void FinishedLocked(Key key, const Running& task, std::int64_t now, std::int64_t worked)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  // Whether long keys hold every thread they may (all but one): the others then wait.
  bool LongKeysWaitLocked() const ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  // Sets key_waits_ from the keys' queues and the threads' work, after any change of either.
  void UpdateKeyWaitsLocked(std::int64_t now) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);

  const Clock clock_;
  const Clock work_clock_;
  mutable Mutex mutex_;
  std::condition_variable ready_;                         // a task was queued, or the pool is stopping
  std::condition_variable prompt_ready_;                  // the same for the prompt lane's thread
  std::map<Key, KeyState> keys_ ABSL_GUARDED_BY(mutex_);  // keys with queued or running tasks, or owing time
  std::int64_t virtual_time_ ABSL_GUARDED_BY(mutex_) = 0;
  std::uint64_t next_sequence_ ABSL_GUARDED_BY(mutex_) = 0;
  size_t queued_ ABSL_GUARDED_BY(mutex_) = 0;
  int long_running_ ABSL_GUARDED_BY(mutex_) = 0;      // tasks of long keys running
  int running_ ABSL_GUARDED_BY(mutex_) = 0;           // tasks running on the threads not of the prompt lane
  bool prompt_busy_ ABSL_GUARDED_BY(mutex_) = false;  // the prompt lane runs a task
  std::atomic<bool> key_waits_{false};                // AnotherKeyWaits(), written under mutex_
  bool stopping_ ABSL_GUARDED_BY(mutex_) = false;
  const int thread_count_;  // not counting the prompt lane's
  const bool has_prompt_lane_;
  std::vector<std::thread> threads_;
};

// Runs the calling thread at `priority`'s niceness, as a pool's threads run: for the server's
// threads that do such work outside a pool (VersionRegistry's index builds, bulk).
void RunThisThreadAt(WorkPool::Priority priority);

}  // namespace mocap

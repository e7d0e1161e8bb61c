// The project's mutex (server, storage, the algorithm library; the client SDK keeps to the standard
// library): std::mutex with clang's lock annotations. ThreadSanitizer sees std::mutex
// (libstdc++ calls pthreads, which TSan intercepts) but not Debian's abseil, which is built without
// TSan, so absl::Mutex would hide every hand-off from it; clang's -Wthread-safety sees annotated
// types only, which std::mutex is not. This type serves both: members it guards carry
// ABSL_GUARDED_BY, functions that expect it held ABSL_EXCLUSIVE_LOCKS_REQUIRED.
#pragma once

#include <chrono>
#include <condition_variable>
#include <mutex>

#include "absl/base/thread_annotations.h"

namespace mocap {

class ABSL_LOCKABLE Mutex {
 public:
  void Lock() ABSL_EXCLUSIVE_LOCK_FUNCTION() { mutex_.lock(); }
  void Unlock() ABSL_UNLOCK_FUNCTION() { mutex_.unlock(); }

  // With the mutex held: waits on `wake` until `ready()` (the mutex is released meanwhile and held
  // again on return). `ready` runs with the mutex held; clang cannot see that inside a lambda, so
  // it reads guarded members through a function marked ABSL_EXCLUSIVE_LOCKS_REQUIRED.
  template <typename Ready>
  void Await(std::condition_variable& wake, Ready ready) ABSL_EXCLUSIVE_LOCKS_REQUIRED(this) {
    std::unique_lock lock(mutex_, std::adopt_lock);
    wake.wait(lock, ready);
    lock.release();
  }
  // The same for at most `timeout`; returns ready().
  template <typename Ready, typename Rep, typename Period>
  bool AwaitFor(std::condition_variable& wake, std::chrono::duration<Rep, Period> timeout, Ready ready)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(this) {
    std::unique_lock lock(mutex_, std::adopt_lock);
    const bool result = wake.wait_for(lock, timeout, ready);
    lock.release();
    return result;
  }

 private:
  std::mutex mutex_;
};

// Holds a Mutex for its scope.
class ABSL_SCOPED_LOCKABLE MutexLock {
 public:
  explicit MutexLock(Mutex* mutex) ABSL_EXCLUSIVE_LOCK_FUNCTION(mutex) : mutex_(mutex) { mutex_->Lock(); }
  ~MutexLock() ABSL_UNLOCK_FUNCTION() { mutex_->Unlock(); }
  MutexLock(const MutexLock&) = delete;
  MutexLock& operator=(const MutexLock&) = delete;

 private:
  Mutex* mutex_;
};

}  // namespace mocap

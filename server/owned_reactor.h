// The self-deleting reactor of gRPC's callback API, in one place. gRPC creates no object for a
// call: the service news a reactor, gRPC calls its OnDone() once after the last reaction, and the
// reactor deletes itself there.
//
// A call's work runs on our pools while gRPC reacts on its own threads. Every pool step and every
// reaction that touches the reactor holds mutex_, so OnDone() takes mutex_ once before deleting:
// the step that called Finish() has then left the reactor. (The steps already follow one another —
// a read or write starts only when a step ends — but that order lives inside gRPC's uninstrumented
// library; the lock states it where ThreadSanitizer and clang's -Wthread-safety can see it.)
#pragma once

#include "motion/core/mutex.h"

namespace mocap {

template <typename GrpcReactor>
class OwnedReactor : public GrpcReactor {
 public:
  void OnDone() final {
    BeforeDelete();
    { MutexLock barrier(&mutex_); }
    delete this;
  }

 protected:
  OwnedReactor() = default;
  ~OwnedReactor() override = default;
  // Last words before the reactor is deleted (e.g. the session-end log line); mutex_ not held.
  virtual void BeforeDelete() {}

  Mutex mutex_;  // the reactor's state: held by every pool step and every reaction
};

}  // namespace mocap

// A shutdown that ends: SIGTERM must stop the server within its drain time and a margin whatever a
// call's work does (issue #24), so the caller waits for the drain only so long.
#pragma once

#include <signal.h>

#include <chrono>
#include <functional>

namespace mocap {

// Runs `shutdown` on a thread of its own and waits for it. True once it has returned; false when
// `limit` passed first or one of `signals` (blocked in every thread) arrived meanwhile — a second
// SIGTERM or Ctrl-C — and the caller should exit without it (its thread is left running, detached).
bool WaitForShutdown(std::function<void()> shutdown, std::chrono::milliseconds limit, const sigset_t& signals);

}  // namespace mocap

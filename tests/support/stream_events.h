// Waiting on a reconstruction stream's own events (a reply, the end of the call) instead of
// sleeping against the server's timers. The `guard` only bounds a failing test: when the event has
// not come by then, the stream is cancelled (which unblocks the pending read) and nullopt is
// returned, so a broken server fails the test instead of hanging it.
#pragma once

#include <chrono>
#include <future>
#include <optional>

#include "mocap/client.h"

namespace mocap::testing {

// Reads until the call ends (the server ended it, or its summary came): the number of replies
// read before that.
inline std::optional<int> RepliesUntilTheCallEnds(client::ReconstructionStream& stream,
                                                  std::chrono::seconds guard = std::chrono::seconds(60)) {
  auto replies = std::async(std::launch::async, [&stream] {
    int count = 0;
    while (true) {
      auto reply = stream.Read();
      if (!reply.ok() || !*reply) return count;
      ++count;
    }
  });
  if (replies.wait_for(guard) == std::future_status::ready) return replies.get();
  stream.Cancel();
  replies.wait();
  return std::nullopt;
}

// The stream's next reply: a frame, a refused sample or an input report, proof that the server is
// working on the session. nullopt when the call ends first.
inline std::optional<v1::ReconstructResponse> NextReply(client::ReconstructionStream& stream,
                                                        std::chrono::seconds guard = std::chrono::seconds(60)) {
  auto reply = std::async(std::launch::async, [&stream]() -> std::optional<v1::ReconstructResponse> {
    auto read = stream.Read();
    if (!read.ok() || !*read) return std::nullopt;
    return **read;
  });
  if (reply.wait_for(guard) == std::future_status::ready) return reply.get();
  stream.Cancel();
  reply.wait();
  return std::nullopt;
}

}  // namespace mocap::testing

// A real `mocapd serve` in a child process on 127.0.0.1 with port 0, for integration tests.
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <string>
#include <vector>

namespace mocap::testing {

class ServerProcess {
 public:
  // Starts `mocapd serve --store STORE --listen 127.0.0.1:0 EXTRA...`; stderr goes to `log`.
  // address() is empty when it did not start (the log says why).
  // `max_file_bytes` > 0: no file the server writes may grow past it (RLIMIT_FSIZE, with SIGXFSZ
  // ignored so writes fail as on a full disk).
  ServerProcess(const std::string& mocapd, const std::filesystem::path& store, const std::filesystem::path& log,
                const std::vector<std::string>& extra = {}, long max_file_bytes = 0);
  // SIGTERM, then waits for the exit.
  ~ServerProcess();
  ServerProcess(const ServerProcess&) = delete;
  ServerProcess& operator=(const ServerProcess&) = delete;

  const std::string& address() const { return address_; }
  // Sends SIGTERM and returns the exit status (the exit code, or -1 when killed by a signal).
  int Stop();
  // SIGKILL: no shutdown at all, as a crash or an OOM kill.
  void Kill();
  pid_t pid() const { return pid_; }

 private:
  pid_t pid_ = -1;
  std::string address_;
};

}  // namespace mocap::testing

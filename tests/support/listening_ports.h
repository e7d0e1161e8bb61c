// The TCP ports a process listens on (Linux /proc: its socket descriptors matched against the
// LISTEN entries of /proc/PID/net/tcp and tcp6), to check what a server opened and nothing more.
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

namespace mocap::testing {

// "self" or a process id.
inline std::set<int> ListeningPorts(const std::string& process = "self") {
  namespace fs = std::filesystem;
  const fs::path proc = fs::path("/proc") / process;
  std::set<std::string> inodes;  // of the process's sockets
  std::error_code error;
  for (const auto& fd : fs::directory_iterator(proc / "fd", error)) {
    const std::string target = fs::read_symlink(fd.path(), error).string();
    if (!error && target.rfind("socket:[", 0) == 0) inodes.insert(target.substr(8, target.size() - 9));
  }
  std::set<int> ports;
  for (const char* table : {"net/tcp", "net/tcp6"}) {
    std::ifstream in(proc / table);
    std::string line;
    std::getline(in, line);  // the header
    while (std::getline(in, line)) {
      // sl local_address rem_address st tx_queue:rx_queue tr:tm->when retrnsmt uid timeout inode
      std::istringstream fields(line);
      std::string slot, local, remote, state, queues, timer, retransmits, uid, timeout, inode;
      fields >> slot >> local >> remote >> state >> queues >> timer >> retransmits >> uid >> timeout >> inode;
      if (state != "0A" || inodes.count(inode) == 0) continue;  // 0A: LISTEN
      ports.insert(std::stoi(local.substr(local.rfind(':') + 1), nullptr, 16));
    }
  }
  return ports;
}

inline std::set<int> ListeningPorts(pid_t pid) { return ListeningPorts(std::to_string(pid)); }

}  // namespace mocap::testing

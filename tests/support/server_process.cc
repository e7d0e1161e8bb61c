#include "tests/support/server_process.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>

namespace mocap::testing {

ServerProcess::ServerProcess(const std::string& mocapd, const std::filesystem::path& store,
                             const std::filesystem::path& log, const std::vector<std::string>& extra,
                             long max_file_bytes) {
  int out[2];
  if (pipe(out) != 0) return;
  std::vector<std::string> args = {mocapd, "serve", "--store", store.string(), "--listen", "127.0.0.1:0"};
  args.insert(args.end(), extra.begin(), extra.end());
  pid_ = fork();
  if (pid_ == 0) {
    dup2(out[1], STDOUT_FILENO);
    const int err = open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    if (err >= 0) dup2(err, STDERR_FILENO);
    close(out[0]);
    if (max_file_bytes > 0) {
      signal(SIGXFSZ, SIG_IGN);  // kept across exec: writes past the limit fail with EFBIG
      const rlimit limit{static_cast<rlim_t>(max_file_bytes), static_cast<rlim_t>(max_file_bytes)};
      setrlimit(RLIMIT_FSIZE, &limit);
    }
    std::vector<char*> argv;
    for (std::string& arg : args) argv.push_back(arg.data());
    argv.push_back(nullptr);
    execv(argv[0], argv.data());
    _exit(127);
  }
  close(out[1]);
  // The server's one stdout line: "listening on HOST:PORT".
  FILE* stream = fdopen(out[0], "r");
  char line[256] = {};
  if (stream != nullptr && fgets(line, sizeof(line), stream) != nullptr) {
    std::string text(line);
    const std::string prefix = "listening on ";
    if (text.rfind(prefix, 0) == 0)
      address_ = text.substr(prefix.size(), text.find_last_not_of("\r\n") + 1 - prefix.size());
  }
  if (stream != nullptr) fclose(stream);
}

ServerProcess::~ServerProcess() { Stop(); }

void ServerProcess::Kill() {
  if (pid_ <= 0) return;
  kill(pid_, SIGKILL);
  waitpid(pid_, nullptr, 0);
  pid_ = -1;
}

int ServerProcess::Stop() {
  if (pid_ <= 0) return -1;
  kill(pid_, SIGTERM);
  int status = 0;
  waitpid(pid_, &status, 0);
  pid_ = -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace mocap::testing

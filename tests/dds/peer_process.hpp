// Starting and ending dds_loopback_peer (loopback_peer.cpp), the other process of the loopback
// test and of bench_dds's cross-process benchmark. PA_DDS_LOOPBACK_PEER is its path (set by the
// build).
#pragma once

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <thread>
#include <vector>

extern char** environ;

namespace dds_test {

// Starts the peer with `args`; -1 when it cannot be started.
inline pid_t start_peer(const std::vector<std::string>& args) {
  std::vector<char*> argv{const_cast<char*>(PA_DDS_LOOPBACK_PEER)};
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t peer = -1;
  if (posix_spawn(&peer, PA_DDS_LOOPBACK_PEER, nullptr, nullptr, argv.data(), environ) != 0) return -1;
  return peer;
}

// Waits up to `timeout` for the peer to exit and returns its exit code; kills it when it has not
// exited by then (-1, as for a peer ended by a signal).
inline int wait_exit(pid_t peer, std::chrono::seconds timeout) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  int status = 0;
  while (waitpid(peer, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() > end) {
      kill(peer, SIGKILL);
      waitpid(peer, &status, 0);
      return -1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace dds_test

#include "hil/trials/worker_pool.hpp"

#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace hil::trials {
namespace {

bool write_all(int fd, const std::string& text) {
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}

// A worker: runs the k-th item, the (k + jobs)-th, ... and writes "<item>\t<report>\n" for each.
[[noreturn]] void work(int first, int items, int jobs, int k, int fd,
                       const std::function<std::string(int)>& run) {
  int status = 0;
  try {
    for (int i = first + k - 1; i < first + items && status == 0; i += jobs) {
      if (!write_all(fd, std::to_string(i) + "\t" + run(i) + "\n")) status = 1;
    }
  } catch (...) {
    status = 3;
  }
  ::close(fd);
  std::fflush(nullptr);
  ::_exit(status);
}

}  // namespace

void run_on_workers(int items, int jobs, const std::function<std::string(int)>& run,
                    const std::function<void(int, const std::string&)>& on_report, const std::string& noun,
                    int first) {
  if (items < 1 || jobs < 1) throw std::runtime_error("the workers need " + noun + "s and jobs >= 1");
  jobs = std::min(jobs, items);
  struct Worker {
    pid_t pid = -1;
    int fd = -1;
    std::string pending;
  };
  std::vector<Worker> workers(static_cast<std::size_t>(jobs));
  std::fflush(nullptr);  // nothing buffered is written twice by a child
  for (int k = 1; k <= jobs; ++k) {
    int fds[2];
    if (::pipe(fds) != 0)
      throw std::runtime_error(std::string("cannot create a pipe: ") + std::strerror(errno));
    const pid_t pid = ::fork();
    if (pid < 0) throw std::runtime_error(std::string("cannot start a worker: ") + std::strerror(errno));
    if (pid == 0) {
      ::close(fds[0]);
      for (int j = 0; j < k - 1; ++j) ::close(workers[static_cast<std::size_t>(j)].fd);
      work(first, items, jobs, k, fds[1], run);
    }
    ::close(fds[1]);
    workers[static_cast<std::size_t>(k - 1)] = Worker{pid, fds[0], {}};
  }

  std::vector<bool> reported(static_cast<std::size_t>(items), false);
  int open = jobs;
  while (open > 0) {
    std::vector<pollfd> polls;
    for (const Worker& w : workers) {
      if (w.fd >= 0) polls.push_back(pollfd{w.fd, POLLIN, 0});
    }
    if (::poll(polls.data(), polls.size(), -1) < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error(std::string("poll: ") + std::strerror(errno));
    }
    for (Worker& w : workers) {
      if (w.fd < 0) continue;
      const auto it = std::find_if(polls.begin(), polls.end(), [&](const pollfd& p) { return p.fd == w.fd; });
      if (it == polls.end() || it->revents == 0) continue;
      char buffer[65536];
      const ssize_t n = ::read(w.fd, buffer, sizeof buffer);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        ::close(w.fd);
        w.fd = -1;
        --open;
        continue;
      }
      w.pending.append(buffer, static_cast<std::size_t>(n));
      for (std::size_t eol; (eol = w.pending.find('\n')) != std::string::npos;) {
        const std::string line = w.pending.substr(0, eol);
        w.pending.erase(0, eol + 1);
        const std::size_t tab = line.find('\t');
        int i = 0;
        if (tab == std::string::npos || std::sscanf(line.c_str(), "%d", &i) != 1 || i < first ||
            i >= first + items)
          throw std::runtime_error("a worker reported an unreadable result: '" + line + "'");
        reported[static_cast<std::size_t>(i - first)] = true;
        on_report(i, line.substr(tab + 1));
      }
    }
  }
  bool workers_ok = true;
  for (const Worker& w : workers) {
    int status = 0;
    if (::waitpid(w.pid, &status, 0) != w.pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
      workers_ok = false;
  }
  for (std::size_t i = 0; i < reported.size(); ++i) {
    if (!reported[i])
      throw std::runtime_error("a worker died without reporting " + noun + " " +
                               std::to_string(first + static_cast<int>(i)));
  }
  if (!workers_ok) throw std::runtime_error("a worker failed after reporting its " + noun + "s");
}

}  // namespace hil::trials

#include "hil/sil/campaign.hpp"

#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "hil/plant/randomisation.hpp"

namespace hil::sil {
namespace {

// What the ground station learns from one throw on the nominal plant (see the header).
gs::runtime::Learnt warm_up(const CampaignConfig& config) {
  SeriesConfig series;
  series.plant = config.plant;
  series.arena.radio.loss = config.plant.radio_loss_probability;
  series.seed = config.seed;
  SeriesRunner runner(series);
  runner.run({AttemptPlan{false}});
  return runner.ground_station().learnt();
}

CampaignAttempt fly(const CampaignConfig& config, const gs::runtime::Learnt& learnt, int attempt) {
  CampaignAttempt a;
  a.seed = attempt_seed(config.seed, attempt);
  a.plant = randomised(config.plant, a.seed);
  SeriesConfig series;
  series.plant = a.plant;
  series.arena.radio.loss = a.plant.radio_loss_probability;
  series.seed = a.seed;
  series.ground_station.learnt = learnt;
  SeriesRunner runner(series);
  a.result = runner.run({AttemptPlan{}}).front();
  a.result.throw_number = attempt;
  return a;
}

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

// A worker: flies attempts k, k + jobs, ... and writes "<attempt>\t<result>\n" for each.
[[noreturn]] void work(const CampaignConfig& config, const gs::runtime::Learnt& learnt, int k, int fd) {
  int status = 0;
  try {
    for (int i = k; i <= config.attempts && status == 0; i += config.jobs) {
      const CampaignAttempt a = fly(config, learnt, i);
      if (!write_all(fd, std::to_string(i) + "\t" + encode_result(a.result) + "\n")) status = 1;
    }
  } catch (...) {
    status = 3;
  }
  ::close(fd);
  std::fflush(nullptr);
  ::_exit(status);
}

}  // namespace

std::uint64_t attempt_seed(std::uint64_t seed, int attempt) {
  return seed * 1000003ULL + static_cast<std::uint64_t>(attempt);
}

std::string encode_result(const AttemptResult& r) {
  char numbers[256];
  std::snprintf(numbers, sizeof numbers, "%.17g\t%.17g\t%.17g\t%.17g\t%.17g\t%.17g\t%d\t%d", r.flight_s,
                r.catch_height_m, r.catch_x_m, r.catch_y_m, r.travel_m, r.energy_error_J, r.impact ? 1 : 0,
                r.vehicle_crashed ? 1 : 0);
  return r.outcome + "\t" + numbers + "\t" + r.abort_reason;
}

bool decode_result(const std::string& line, AttemptResult& r) {
  std::vector<std::string> fields;
  std::stringstream in(line);
  std::string field;
  while (std::getline(in, field, '\t')) fields.push_back(field);
  if (line.empty() || line.back() == '\t') fields.emplace_back();
  if (fields.size() != 10) return false;
  try {
    r.outcome = fields[0];
    r.flight_s = std::stod(fields[1]);
    r.catch_height_m = std::stod(fields[2]);
    r.catch_x_m = std::stod(fields[3]);
    r.catch_y_m = std::stod(fields[4]);
    r.travel_m = std::stod(fields[5]);
    r.energy_error_J = std::stod(fields[6]);
    r.impact = fields[7] == "1";
    r.vehicle_crashed = fields[8] == "1";
    r.abort_reason = fields[9];
  } catch (const std::exception&) {
    return false;
  }
  return true;
}

std::vector<CampaignAttempt> run_campaign(
    const CampaignConfig& config,
    const std::function<void(const std::vector<const CampaignAttempt*>&)>& progress) {
  if (config.attempts < 1 || config.jobs < 1)
    throw std::runtime_error("a campaign needs attempts and jobs >= 1");
  const gs::runtime::Learnt learnt = warm_up(config);

  // The plants are drawn here too (a draw is cheap and deterministic): the workers report only
  // the referee's results.
  std::vector<CampaignAttempt> attempts(static_cast<std::size_t>(config.attempts));
  for (int i = 1; i <= config.attempts; ++i) {
    CampaignAttempt& a = attempts[static_cast<std::size_t>(i - 1)];
    a.seed = attempt_seed(config.seed, i);
    a.plant = randomised(config.plant, a.seed);
    a.result.throw_number = i;
  }

  const int jobs = std::min(config.jobs, config.attempts);
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
      work(config, learnt, k, fds[1]);
    }
    ::close(fds[1]);
    workers[static_cast<std::size_t>(k - 1)] = Worker{pid, fds[0], {}};
  }

  std::vector<bool> reported(attempts.size(), false);
  std::vector<const CampaignAttempt*> done;
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
      char buffer[4096];
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
        AttemptResult r;
        if (tab == std::string::npos || std::sscanf(line.c_str(), "%d", &i) != 1 || i < 1 ||
            i > config.attempts || !decode_result(line.substr(tab + 1), r)) {
          throw std::runtime_error("a worker reported an unreadable result: '" + line + "'");
        }
        r.throw_number = i;
        CampaignAttempt& a = attempts[static_cast<std::size_t>(i - 1)];
        a.result = r;
        reported[static_cast<std::size_t>(i - 1)] = true;
        done.push_back(&a);
        if (progress) progress(done);
      }
    }
  }
  bool workers_ok = true;
  for (const Worker& w : workers) {
    int status = 0;
    if (::waitpid(w.pid, &status, 0) != w.pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
      workers_ok = false;
  }
  for (std::size_t i = 0; i < attempts.size(); ++i) {
    if (!reported[i]) {
      throw std::runtime_error("a worker died without reporting attempt " + std::to_string(i + 1));
    }
  }
  if (!workers_ok) throw std::runtime_error("a worker failed after reporting its attempts");
  return attempts;
}

}  // namespace hil::sil

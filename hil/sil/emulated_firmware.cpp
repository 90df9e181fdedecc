#include "hil/sil/emulated_firmware.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <type_traits>

namespace hil::sil {
namespace {

using pa::proto::Frame;
using pa::proto::Type;
using Clock = std::chrono::steady_clock;

static_assert(std::is_trivially_copyable_v<fw::VehicleConfig>,
              "pil_vehicle.cfg carries the raw bytes of fw::VehicleConfig");

constexpr const char* kConfigFile = "pil_vehicle.cfg";
constexpr const char* kSocketFile = "pil.sock";
constexpr const char* kLogFile = "qemu.log";  // QEMU's stdout and stderr (the image's console)
constexpr std::size_t kOutputTail = 2000;     // characters of it quoted in an error

bool is_type(const Frame& f, Type type) {
  return pa::proto::id_type(f.id) == static_cast<std::uint8_t>(type);
}

std::string errno_text(const char* what) { return std::string(what) + ": " + std::strerror(errno); }

Clock::time_point after(double seconds) {
  return Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}

// Milliseconds left until `deadline` for poll(), at least 0.
int ms_until(Clock::time_point deadline) {
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
  return left <= 0 ? 0 : static_cast<int>(std::min<long long>(left, 1000));
}

std::string describe_status(int status) {
  if (WIFEXITED(status)) return "exited with status " + std::to_string(WEXITSTATUS(status));
  if (WIFSIGNALED(status)) return std::string("was killed by signal ") + strsignal(WTERMSIG(status));
  return "stopped";
}

}  // namespace

EmulatedFirmware::EmulatedFirmware(const fw::VehicleConfig& config, const EmulatorConfig& emulator)
    : node_(config.link.vehicle.node()), emulator_(emulator) {
  if (emulator_.image.empty()) throw std::invalid_argument("emulated firmware: no image given");
  if (!emulator_.icount_shift)
    throw std::invalid_argument(
        "emulated firmware: no -icount shift (the build could not read the image's PA_MPS2_ICOUNT_SHIFT; give it)");
  if (!(emulator_.connect_timeout_s > 0.0) || !(emulator_.answer_timeout_s > 0.0))
    throw std::invalid_argument("emulated firmware: the timeouts must be positive");
  std::error_code ec;
  const std::filesystem::path image = std::filesystem::absolute(emulator_.image, ec);
  if (ec || !std::filesystem::is_regular_file(image, ec))
    throw EmulatedFirmwareError("emulated firmware: no image file '" + emulator_.image + "'");

  // The private folder: QEMU's working directory, with the configuration and the socket.
  std::string folder = (std::filesystem::temp_directory_path(ec) / "pa-pil-XXXXXX").string();
  if (ec) folder = "/tmp/pa-pil-XXXXXX";
  if (mkdtemp(folder.data()) == nullptr)
    throw EmulatedFirmwareError(errno_text("emulated firmware: mkdtemp"));
  folder_ = folder;
  log_path_ = folder_ + "/" + kLogFile;
  try {
    {
      std::ofstream file(folder_ + "/" + kConfigFile, std::ios::binary);
      // "PAVC", then sizeof(fw::VehicleConfig) as a little-endian u32.
      const auto size = static_cast<std::uint32_t>(sizeof(fw::VehicleConfig));
      std::array<char, 8> header{'P', 'A', 'V', 'C'};
      for (std::size_t i = 0; i < 4; ++i) header[4 + i] = static_cast<char>((size >> (8 * i)) & 0xFFu);
      file.write(header.data(), header.size());
      file.write(reinterpret_cast<const char*>(&config), sizeof config);
      if (!file.flush())
        throw EmulatedFirmwareError("emulated firmware: cannot write " + folder_ + "/" + kConfigFile);
    }

    const std::string socket_path = folder_ + "/" + kSocketFile;
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    if (socket_path.size() >= sizeof address.sun_path)
      throw EmulatedFirmwareError("emulated firmware: the socket path '" + socket_path +
                                  "' is too long for a unix socket (set TMPDIR to a shorter folder)");
    std::memcpy(address.sun_path, socket_path.c_str(), socket_path.size() + 1);
    listen_fd_ = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
    if (listen_fd_ < 0) throw EmulatedFirmwareError(errno_text("emulated firmware: socket"));
    if (bind(listen_fd_, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0 ||
        listen(listen_fd_, 1) != 0)
      throw EmulatedFirmwareError(errno_text(("emulated firmware: listening on " + socket_path).c_str()));

    spawn({emulator_.qemu, "-M", "mps2-an386", "-cpu", "cortex-m4", "-nographic", "-monitor", "none",
           "-icount", "shift=" + std::to_string(*emulator_.icount_shift), "-semihosting-config",
           "enable=on,target=native", "-kernel", image.string(), "-chardev",
           "socket,id=pil,path=" + socket_path, "-serial", "chardev:pil"});
    accept_connection(emulator_.connect_timeout_s);
  } catch (...) {
    stop();
    remove_folder();
    if (log_fd_ >= 0) close(log_fd_);
    throw;
  }
}

EmulatedFirmware::~EmulatedFirmware() {
  stop();
  remove_folder();
  if (log_fd_ >= 0) close(log_fd_);
}

void EmulatedFirmware::spawn(const std::vector<std::string>& args) {
  // Everything the child needs is made before fork(): between fork() and exec() it makes only
  // system calls.
  std::vector<char*> argv;
  argv.reserve(args.size() + 1);
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const int log = open(log_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  log_fd_ = open(log_path_.c_str(), O_RDONLY | O_CLOEXEC);  // QEMU's output, read in errors
  const int null = open("/dev/null", O_RDONLY | O_CLOEXEC);
  int exec_error[2] = {-1, -1};
  if (log < 0 || log_fd_ < 0 || null < 0 || pipe2(exec_error, O_CLOEXEC) != 0) {
    const std::string error = errno_text("emulated firmware: preparing QEMU's output");
    if (log >= 0) close(log);
    if (null >= 0) close(null);
    throw EmulatedFirmwareError(error);
  }
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid == 0) {
    // QEMU dies with the thread that started it, and at once if that is already gone.
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(126);
    if (chdir(folder_.c_str()) != 0 || dup2(null, 0) < 0 || dup2(log, 1) < 0 || dup2(log, 2) < 0) {
      const int e = errno;
      (void)!write(exec_error[1], &e, sizeof e);
      _exit(126);
    }
    execvp(argv[0], argv.data());
    const int e = errno;
    (void)!write(exec_error[1], &e, sizeof e);
    _exit(127);
  }
  const int fork_errno = errno;
  close(log);
  close(null);
  close(exec_error[1]);
  if (pid < 0) {
    close(exec_error[0]);
    errno = fork_errno;
    throw EmulatedFirmwareError(errno_text("emulated firmware: fork"));
  }
  pid_ = pid;
  // The pipe closes on a successful exec; an errno comes through it otherwise.
  int child_errno = 0;
  ssize_t n;
  do {
    n = read(exec_error[0], &child_errno, sizeof child_errno);
  } while (n < 0 && errno == EINTR);
  close(exec_error[0]);
  if (n == static_cast<ssize_t>(sizeof child_errno))
    throw EmulatedFirmwareError("emulated firmware: cannot run '" + emulator_.qemu +
                                "': " + std::strerror(child_errno));
}

void EmulatedFirmware::accept_connection(double timeout_s) {
  const Clock::time_point deadline = after(timeout_s);
  for (;;) {
    pollfd p{listen_fd_, POLLIN, 0};
    const int ready = poll(&p, 1, 50);
    if (ready > 0) {
      fd_ = accept4(listen_fd_, nullptr, nullptr, SOCK_CLOEXEC | SOCK_NONBLOCK);
      if (fd_ >= 0) break;
      if (errno != EAGAIN && errno != EINTR)
        throw EmulatedFirmwareError(errno_text("emulated firmware: accept"));
    } else if (ready < 0 && errno != EINTR) {
      throw EmulatedFirmwareError(errno_text("emulated firmware: poll"));
    }
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      exit_status_ = status;
      pid_ = -1;
      throw EmulatedFirmwareError("emulated firmware: QEMU " + describe_status(status) +
                                  " before it connected to the vehicle's serial line; its output:\n" +
                                  qemu_output());
    }
    if (Clock::now() >= deadline) {
      char seconds[32];
      std::snprintf(seconds, sizeof seconds, "%.1f", timeout_s);
      throw EmulatedFirmwareError(
          std::string("emulated firmware: QEMU did not connect to the vehicle's serial line within ") +
          seconds + " s; its output:\n" + qemu_output());
    }
  }
  close(listen_fd_);
  listen_fd_ = -1;
  unlink((folder_ + "/" + kSocketFile).c_str());
}

void EmulatedFirmware::stop() {
  if (fd_ >= 0) close(fd_);
  if (listen_fd_ >= 0) close(listen_fd_);
  fd_ = listen_fd_ = -1;
  if (pid_ > 0) {
    kill(pid_, SIGKILL);
    int status = 0;
    while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
    exit_status_ = status;
    pid_ = -1;
  }
}

std::string EmulatedFirmware::qemu_output() const {
  struct stat st {};
  if (log_fd_ < 0 || fstat(log_fd_, &st) != 0) return "(none)";
  const auto size = static_cast<std::size_t>(st.st_size);
  const std::size_t from = size > kOutputTail ? size - kOutputTail : 0;
  std::string text(size - from, '\0');
  const ssize_t n = pread(log_fd_, text.data(), text.size(), static_cast<off_t>(from));
  text.resize(n > 0 ? static_cast<std::size_t>(n) : 0);
  if (from > 0) text = "[...]" + text;
  return text.empty() ? "(none)" : text;
}

// Once the image has answered it has read its configuration: the folder goes at once, the
// output staying readable through log_fd_, so that nothing is left behind even if this process
// is killed.
void EmulatedFirmware::remove_folder() {
  if (folder_.empty()) return;
  std::error_code ec;
  std::filesystem::remove_all(folder_, ec);
  folder_.clear();
}

// QEMU's state for a message; `wait`: give an exiting QEMU a moment to finish.
std::string EmulatedFirmware::qemu_status(bool wait) {
  if (pid_ > 0) {
    int status = 0;
    const Clock::time_point deadline = after(wait ? 1.0 : 0.0);
    do {
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        exit_status_ = status;
        pid_ = -1;
        break;
      }
      if (wait) usleep(10000);
    } while (Clock::now() < deadline);
  }
  if (pid_ > 0) return "QEMU was still running";
  return "QEMU " + describe_status(exit_status_);
}

void EmulatedFirmware::fail(const std::string& what) {
  failed_ = true;
  char head[64];
  std::snprintf(head, sizeof head, "emulated firmware of vehicle %d: ", int(node_));
  failure_ = head + what;
  stop();
  failure_ += "; its output:\n" + qemu_output();
  throw EmulatedFirmwareError(failure_);
}

void EmulatedFirmware::write_bytes(const std::uint8_t* data, std::size_t size) {
  const Clock::time_point deadline = after(emulator_.answer_timeout_s);
  while (size > 0) {
    const ssize_t n = send(fd_, data, size, MSG_NOSIGNAL);
    if (n > 0) {
      data += n;
      size -= static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      if (Clock::now() >= deadline) fail("the image read nothing for the answer timeout (hung?)");
      pollfd p{fd_, POLLOUT, 0};
      poll(&p, 1, ms_until(deadline));
      continue;
    }
    const std::string error = std::strerror(errno);
    fail("writing to the serial line failed (" + error + "): " + qemu_status(true));
  }
}

void EmulatedFirmware::write_bus(const std::vector<Frame>& frames) {
  if (failed_) throw EmulatedFirmwareError(failure_);
  std::vector<std::uint8_t> bytes;
  bytes.reserve(frames.size() * pa::serial_frame::kMaxBytes);
  std::array<std::uint8_t, pa::serial_frame::kMaxBytes> encoded;
  for (const Frame& f : frames) {
    const std::size_t n = pa::serial_frame::encode(f, encoded);
    if (n == 0) continue;  // not a frame a bus could carry
    bytes.insert(bytes.end(), encoded.begin(), encoded.begin() + static_cast<std::ptrdiff_t>(n));
    observe_handed(f);
  }
  if (!bytes.empty()) write_bytes(bytes.data(), bytes.size());
}

// What the image does with the frame, mirrored: whether it completes a sample (so runs a tick,
// which is answered), and the setpoint it was handed.
void EmulatedFirmware::observe_handed(const Frame& f) {
  pa::proto::Message m;
  if (pa::proto::decode(f, m) != pa::proto::DecodeStatus::ok || m.node != node_) return;
  if (m.type == Type::hil_imu_gyro || m.type == Type::hil_imu_accel) {
    fw::ImuSample sample;
    if (imu_.on_message(m, sample)) {
      clock_us_ = sample.t_us;
      tick_awaited_ = imu_.tick();
      ++ticks_awaited_;
    }
  } else if (m.type == Type::rate_thrust) {
    observed_.setpoint = m.rate_thrust;
    has_setpoint_ = true;
    setpoint_us_ = clock_us_;
  }
}

void EmulatedFirmware::observe_sent(const Frame& f) {
  pa::proto::Message m;
  if (pa::proto::decode(f, m) != pa::proto::DecodeStatus::ok || m.node != node_) return;
  if (m.type == Type::vehicle_heartbeat) {
    observed_.mode = m.vehicle_heartbeat.mode;
    observed_.failsafe_reason = m.vehicle_heartbeat.failsafe;
  } else if (m.type == Type::telemetry_status) {
    observed_.impact_count = m.telemetry_status.impact_count;
  }
}

std::vector<Frame> EmulatedFirmware::read_answer() {
  if (failed_) throw EmulatedFirmwareError(failure_);
  std::vector<Frame> out;
  std::array<std::uint8_t, 512> buffer;
  while (ticks_awaited_ > 0) {
    const Clock::time_point deadline = after(emulator_.answer_timeout_s);
    bool answered = false;
    while (!answered) {
      const ssize_t n = recv(fd_, buffer.data(), buffer.size(), 0);
      if (n == 0)
        fail("QEMU closed the serial line awaiting tick " + std::to_string(tick_awaited_) + ": " +
             qemu_status(true));
      if (n < 0) {
        if (errno == EINTR) continue;
        if (errno != EAGAIN && errno != EWOULDBLOCK) {
          const std::string error = std::strerror(errno);
          fail("reading the serial line failed (" + error + "): " + qemu_status(true));
        }
        if (Clock::now() >= deadline) {
          char seconds[32];
          std::snprintf(seconds, sizeof seconds, "%.1f", emulator_.answer_timeout_s);
          fail("no answer to tick " + std::to_string(tick_awaited_) + " within " + seconds +
               " s (the image crashed or hung); " + qemu_status(false));
        }
        pollfd p{fd_, POLLIN, 0};
        poll(&p, 1, ms_until(deadline));
        continue;
      }
      for (ssize_t i = 0; i < n; ++i) {
        Frame f;
        if (!decoder_.push(buffer[static_cast<std::size_t>(i)], f)) continue;
        if (is_type(f, Type::hil_tick_cost)) {
          pa::proto::Message m;
          if (pa::proto::decode(f, m) == pa::proto::DecodeStatus::ok)
            pending_cost_ = m.hil_tick_cost.instructions;
          continue;
        }
        observe_sent(f);
        if (!is_type(f, Type::hil_motors) || ticks_awaited_ == 0) {
          pending_.push_back(f);  // a frame after the last answer waits for the next
          continue;
        }
        // The tick's answer is in: HIL_MOTORS first, as the core in process sends it.
        out.push_back(f);
        out.insert(out.end(), pending_.begin(), pending_.end());
        pending_.clear();
        last_tick_instructions_ = pending_cost_;
        pending_cost_.reset();
        if (ticks_answered_++ == 0) remove_folder();
        --ticks_awaited_;
        answered = true;
      }
    }
  }
  return out;
}

std::uint32_t EmulatedFirmware::setpoint_age_us(std::uint32_t now_us) const {
  if (!has_setpoint_) return kNoSetpoint;
  const auto age = static_cast<std::int32_t>(now_us - setpoint_us_);
  return age < 0 ? 0u : static_cast<std::uint32_t>(age);
}

}  // namespace hil::sil

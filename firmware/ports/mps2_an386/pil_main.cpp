// The mps2-an386 processor-in-the-loop image (fw_mps2_an386_pil): the firmware core on a
// Cortex-M4F in QEMU, driven over UART0 by a host program that steps a simulated plant in
// lockstep with it (hil/sil/emulated_firmware.*).
//
// At boot it reads its fw::VehicleConfig over semihosting from `pil_vehicle.cfg` in QEMU's
// working directory: "PAVC", a little-endian u32 equal to sizeof(fw::VehicleConfig), then the
// struct's raw bytes (the x86-64 host's layout is the Cortex-M4's: floats, u8/u32, bools and
// arrays of them). A missing or malformed file ends the run with exit status 2.
//
// Then it decodes the bytes on UART0 (QEMU's first -serial) with the project's serial framing
// (pa/serial_frame.hpp) and hands each frame to the Linux HIL port's node
// (fw::posix::HilVehicleNode): HIL_IMU_GYRO + HIL_IMU_ACCEL of one tick run Vehicle::tick,
// HIL_BATTERY is the pack's voltage, everything else goes to the core. A frame that runs a tick
// is answered, serial-framed, with every frame the core had queued, then HIL_TICK_COST (the
// tick's Vehicle::tick in guest instructions, exact under -icount), then the tick's HIL_MOTORS,
// which the host reads as the end of the answer. Any other frame is answered with nothing.
// No heap; bounded work per received byte. The console (semihosting, QEMU's stderr) says one
// line at start-up, and one more whenever an answer had to drop frames.
#include <array>
#include <cstdint>
#include <cstring>
#include <new>
#include <type_traits>

#include "console.hpp"
#include "fw/command_link.hpp"
#include "fw/config.hpp"
#include "hil_vehicle_node.hpp"
#include "instruction_counter.hpp"
#include "pa/protocol.hpp"
#include "pa/serial_frame.hpp"
#include "semihosting.hpp"
#include "uart.hpp"

// The vehicle's clock for timing its ticks: virtual nanoseconds of the instruction counter
// (40 ns per SysTick count at 25 MHz), so the core's tick_time_max_us telemetry is virtual time
// (2^PA_MPS2_ICOUNT_SHIFT ns per instruction). Never inlined, so every reading costs the same
// and the bracket's own cost can be measured through the same call (probe_overhead_ns()).
__attribute__((noinline)) std::uint64_t fw::posix::HilVehicleNode::monotonic_ns() {
  return mps2::InstructionCounter::counts() * mps2::InstructionCounter::kNsPerCount;
}

namespace {

using mps2::ConsoleLine;
using mps2::InstructionCounter;
using Node = fw::posix::HilVehicleNode;

static_assert(std::is_trivially_copyable_v<fw::VehicleConfig>,
              "pil_vehicle.cfg carries the host's raw bytes of fw::VehicleConfig");

constexpr char kConfigPath[] = "pil_vehicle.cfg";
constexpr std::array<std::uint8_t, 4> kConfigMagic = {'P', 'A', 'V', 'C'};
constexpr std::uint32_t kConfigHeaderBytes = 8;  // magic, then the u32 size
constexpr std::uint32_t kConfigFileBytes = kConfigHeaderBytes + sizeof(fw::VehicleConfig);
constexpr int kExitBadConfig = 2;

// Reads and checks pil_vehicle.cfg; on any problem says what on the console and exits with 2.
fw::VehicleConfig load_config() {
  // One byte more than a valid file, so a longer file is seen as such.
  static std::array<std::uint8_t, kConfigFileBytes + 1> file{};
  const std::int32_t length = mps2::semihosting::read_file(kConfigPath, file.data(), file.size());
  const char* problem = nullptr;
  std::uint32_t size_field = 0;
  if (length < 0) {
    problem = "cannot be opened or read in QEMU's working directory";
  } else if (static_cast<std::uint32_t>(length) < kConfigHeaderBytes ||
             std::memcmp(file.data(), kConfigMagic.data(), kConfigMagic.size()) != 0) {
    problem = "does not start with the magic \"PAVC\"";
  } else {
    size_field = static_cast<std::uint32_t>(file[4]) | (static_cast<std::uint32_t>(file[5]) << 8) |
                 (static_cast<std::uint32_t>(file[6]) << 16) | (static_cast<std::uint32_t>(file[7]) << 24);
    if (size_field != sizeof(fw::VehicleConfig))
      problem = "has a size field other than sizeof(fw::VehicleConfig)";
    else if (static_cast<std::uint32_t>(length) != kConfigFileBytes)
      problem = "is not 8 bytes of header plus sizeof(fw::VehicleConfig)";
  }
  if (problem != nullptr) {
    ConsoleLine().text("pil: fail config ").text(kConfigPath).text(" ").text(problem).emit();
    ConsoleLine()
        .text("pil: file length ")
        .i32(length)
        .text(", size field ")
        .u32(size_field)
        .text(", sizeof(fw::VehicleConfig) ")
        .u32(sizeof(fw::VehicleConfig))
        .emit();
    mps2::semihosting::exit(kExitBadConfig);
  }
  fw::VehicleConfig config;
  std::memcpy(&config, file.data() + kConfigHeaderBytes, sizeof config);
  return config;
}

// An empty bracket of two clock readings through the same out-of-line call the node makes (the
// pointer is laundered so the compiler cannot see what it calls): what the node's timing of a
// tick adds to the tick itself.
std::uint64_t probe_overhead_ns() {
  std::uint64_t least = ~std::uint64_t{0};
  for (int i = 0; i < 8; ++i) {
    std::uint64_t (*clock)() = &Node::monotonic_ns;
    asm volatile("" : "+r"(clock));
    const std::uint64_t a = clock();
    const std::uint64_t b = clock();
    if (b - a < least) least = b - a;
  }
  return least;
}

// The frames one on_frame call sends: HIL_MOTORS and at most the core's whole transmit queue.
// Frames beyond that are counted and dropped.
class Outbox {
 public:
  static constexpr std::size_t kCapacity = fw::CommandLink::kTxQueue + 1;

  void clear() { count_ = 0; }
  void push(const pa::proto::Frame& f) {
    if (count_ < kCapacity) {
      frames_[count_++] = f;
    } else {
      ++dropped_;
    }
  }
  std::size_t count() const { return count_; }
  const pa::proto::Frame& operator[](std::size_t i) const { return frames_[i]; }
  std::uint32_t dropped() const { return dropped_; }

 private:
  std::array<pa::proto::Frame, kCapacity> frames_{};
  std::size_t count_ = 0;
  std::uint32_t dropped_ = 0;
};

bool is_hil_motors(const pa::proto::Frame& f) {
  return pa::proto::id_type(f.id) == static_cast<std::uint8_t>(pa::proto::Type::hil_motors) &&
         f.len == pa::proto::find_type(static_cast<std::uint8_t>(pa::proto::Type::hil_motors))->length;
}

void write_frame(const mps2::CmsdkUart& uart, const pa::proto::Frame& f) {
  std::array<std::uint8_t, pa::serial_frame::kMaxBytes> bytes;
  const std::size_t n = pa::serial_frame::encode(f, bytes);
  uart.write(bytes.data(), static_cast<std::uint32_t>(n));
}

// Writes one tick's answer: the core's frames in order, HIL_TICK_COST, HIL_MOTORS last.
void write_answer(const mps2::CmsdkUart& uart, const Outbox& outbox, std::uint8_t node,
                  std::uint32_t tick_instructions) {
  const pa::proto::Frame* motors = nullptr;
  for (std::size_t i = 0; i < outbox.count(); ++i) {
    if (motors == nullptr && is_hil_motors(outbox[i])) {
      motors = &outbox[i];
    } else {
      write_frame(uart, outbox[i]);
    }
  }
  if (motors == nullptr) return;  // not a tick (on_frame sends only after one)
  const auto tick = static_cast<std::uint16_t>(motors->data[6] | (motors->data[7] << 8));
  pa::proto::Frame cost;
  if (pa::proto::encode(pa::proto::HilTickCost{tick, tick_instructions}, node, cost)) write_frame(uart, cost);
  write_frame(uart, *motors);
}

// Waiting for a byte with the core asleep (WFI) rather than spinning on the UART: QEMU's model
// hands over one byte at a time, and a spinning guest keeps QEMU's CPU thread busy taking the
// big lock for every status read, competing with the I/O thread that delivers the bytes (on a
// busy two-core host the round trip per tick was 1.9 ms spinning against 1.3 ms asleep; alike
// on an idle one) and burning a host core per image. UART0's receive interrupt (NVIC line 0 on
// mps2-an386) is enabled at a priority that BASEPRI masks for good: it is never taken, it only
// ends the WFI (QEMU's NVIC wakes the core for a pending interrupt whatever the masks, as the
// architecture does for PRIMASK). SysTick, at priority 0, still runs, so the instruction counter
// keeps counting its wraps.
namespace rx_wakeup {
constexpr std::uint32_t kUart0RxIrq = 0;
constexpr std::uint8_t kMaskedPriority = 0x80;
volatile std::uint32_t& nvic_iser0() { return *reinterpret_cast<volatile std::uint32_t*>(0xE000E100u); }
volatile std::uint32_t& nvic_icpr0() { return *reinterpret_cast<volatile std::uint32_t*>(0xE000E280u); }
volatile std::uint8_t& nvic_ipr(std::uint32_t irq) {
  return *reinterpret_cast<volatile std::uint8_t*>(0xE000E400u + irq);
}

void enable(const mps2::CmsdkUart& uart) {
  uart.enable(true);
  nvic_ipr(kUart0RxIrq) = kMaskedPriority;
  const std::uint32_t basepri = kMaskedPriority;
  asm volatile("msr basepri, %0" ::"r"(basepri) : "memory");
  nvic_iser0() = 1u << kUart0RxIrq;
}

// Takes the next byte, sleeping until one comes; false after a wake-up for something else
// (a SysTick wrap), and the caller asks again.
bool read(const mps2::CmsdkUart& uart, std::uint8_t& byte) {
  if (uart.read(byte)) return true;
  // Clear the latched interrupt, then look again: a byte that came in between is seen here,
  // one that comes after pends the interrupt again and the WFI returns at once.
  uart.clear_rx_interrupt();
  nvic_icpr0() = 1u << kUart0RxIrq;
  if (!uart.readable()) asm volatile("wfi" ::: "memory");
  return uart.read(byte);
}
}  // namespace rx_wakeup

// The node lives in static storage, built once the configuration is read and never destroyed
// (so no destructor is registered to run at exit).
alignas(Node) std::uint8_t g_node_storage[sizeof(Node)];
Outbox g_outbox;

}  // namespace

int main() {
  InstructionCounter::start();
  const fw::VehicleConfig config = load_config();
  const std::uint8_t node_id = config.link.vehicle.node();
  Node& node = *::new (static_cast<void*>(g_node_storage)) Node(config);
  const std::uint64_t overhead_ns = probe_overhead_ns();

  const mps2::CmsdkUart uart(mps2::CmsdkUart::kUart0);
  rx_wakeup::enable(uart);
  ConsoleLine()
      .text("pil: vehicle node ")
      .u32(node_id)
      .text(", serial frames on UART0, ticks counted with -icount shift=")
      .u32(InstructionCounter::kIcountShift)
      .text(", probe overhead ")
      .fixed(InstructionCounter::instructions(overhead_ns / InstructionCounter::kNsPerCount), 1)
      .text(" instructions")
      .emit();

  pa::serial_frame::Decoder decoder;
  std::uint32_t reported_drops = 0;
  for (;;) {
    std::uint8_t byte = 0;
    if (!rx_wakeup::read(uart, byte)) continue;
    pa::proto::Frame frame;
    if (!decoder.push(byte, frame)) continue;

    g_outbox.clear();
    node.on_frame(frame, [](const pa::proto::Frame& f) { g_outbox.push(f); });
    if (g_outbox.count() == 0) continue;

    const std::uint64_t tick_ns = node.last_tick_ns();
    const std::uint64_t net_ns = tick_ns > overhead_ns ? tick_ns - overhead_ns : 0;
    constexpr std::uint64_t kNsPerInstruction = std::uint64_t{1} << InstructionCounter::kIcountShift;
    const std::uint64_t instructions = (net_ns + kNsPerInstruction / 2) / kNsPerInstruction;
    write_answer(uart, g_outbox, node_id,
                 instructions > 0xFFFFFFFFu ? 0xFFFFFFFFu : static_cast<std::uint32_t>(instructions));

    if (g_outbox.dropped() != reported_drops) {
      reported_drops = g_outbox.dropped();
      ConsoleLine().text("pil: answer buffer full, frames dropped so far: ").u32(reported_drops).emit();
    }
  }
}

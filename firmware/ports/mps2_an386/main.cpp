// The mps2-an386 image: flies the scripted self-test (fw/selftest.hpp) on the firmware core on
// a Cortex-M4F in QEMU, measures every 1 kHz tick in guest instructions, and reports over
// semihosting. Exit status 0 when the flight passed, the instruction counter calibrated and
// the stack stayed inside its reservation; 1 otherwise.
#include <cstdint>

#include "console.hpp"
#include "cortex_m/runtime.hpp"
#include "fw/battery_compensation.hpp"
#include "fw/drivers/dshot.hpp"
#include "fw/drivers/mpu6000.hpp"
#include "fw/drivers/omnibus_f4.hpp"
#include "fw/link_guard.hpp"
#include "fw/mixer.hpp"
#include "fw/selftest.hpp"
#include "instruction_counter.hpp"
#include "pa/serial_frame.hpp"

namespace {

using mps2::ConsoleLine;
using mps2::InstructionCounter;

// Brackets each Vehicle::tick with instruction-counter readings. A tick that spans a SysTick
// wrap (one in ~300 ticks) also counts the wrap interrupt's handful of instructions.
class InstructionProbe final : public fw::selftest::TickProbe {
 public:
  void before_tick() override { start_ = InstructionCounter::counts(); }
  void after_tick() override {
    const std::uint64_t elapsed = InstructionCounter::counts() - start_;
    if (elapsed > max_counts_) {
      max_counts_ = elapsed;
      max_tick_ = ticks_;
    }
    total_counts_ += elapsed;
    ++ticks_;
  }

  std::uint64_t max_counts() const { return max_counts_; }
  std::uint64_t mean_counts() const { return ticks_ == 0 ? 0 : total_counts_ / ticks_; }
  std::uint32_t max_tick() const { return max_tick_; }  // the worst tick's number, from 0

 private:
  std::uint64_t start_ = 0;
  std::uint64_t max_counts_ = 0;
  std::uint64_t total_counts_ = 0;
  std::uint32_t ticks_ = 0;
  std::uint32_t max_tick_ = 0;
};

// The probe's own cost: an empty bracket through the same virtual calls the self-test makes
// (the pointer is laundered so the compiler cannot see which probe it calls).
std::uint64_t probe_overhead_counts() {
  std::uint64_t least = ~std::uint64_t{0};
  for (int i = 0; i < 8; ++i) {
    InstructionProbe probe;
    fw::selftest::TickProbe* p = &probe;
    asm volatile("" : "+r"(p));
    p->before_tick();
    p->after_tick();
    if (probe.max_counts() < least) least = probe.max_counts();
  }
  return least;
}

// Code of known length for calibration. The first two differ by exactly 1000 instructions
// (the calls and returns cancel); the loop runs 2 instructions per iteration and, at 400 000
// iterations, spans more than one SysTick wrap (2^24 counts = 655 360 instructions).
__attribute__((noinline)) void run_0_nops() { asm volatile(""); }
__attribute__((noinline)) void run_1000_nops() { asm volatile(".rept 1000\n\tnop\n\t.endr"); }
constexpr std::uint32_t kLoopIterations = 400000;
__attribute__((noinline)) void run_loop() {
  std::uint32_t n = kLoopIterations;
  asm volatile("1: subs %0, %0, #1\n\tbne 1b" : "+r"(n)::"cc");
}

std::uint64_t counts_for(void (*f)()) {
  const std::uint64_t start = InstructionCounter::counts();
  f();
  return InstructionCounter::counts() - start;
}

float instructions_beyond_empty_call(void (*f)()) {
  const std::uint64_t with = counts_for(f);
  const std::uint64_t without = counts_for(run_0_nops);
  return InstructionCounter::instructions(with > without ? with - without : 0);
}

// The pure driver work the STM32F405 flight image adds to each tick (its register poking
// aside): decoding the IMU burst into the body frame, four DShot frames and their pulse
// buffers, and one frame for the radio link. Inputs and outputs go through globals that escape
// to the compiler (escape()), so none of it is optimised away.
namespace flight_drivers {
namespace board = fw::drivers::omnibus_f4;
std::array<std::uint8_t, 14> g_burst = {0x00, 0x12, 0xFF, 0xE0, 0x08, 0x05, 0x0A,
                                        0x00, 0x00, 0x40, 0xFF, 0x80, 0x01, 0x00};
fw::Motors g_command = {0.41f, 0.43f, 0.39f, 0.45f};
fw::ImuSample g_sample;
std::array<fw::drivers::dshot::Pulses, 4> g_pulses;
std::array<std::uint8_t, pa::serial_frame::kMaxBytes> g_link_bytes;
pa::proto::Frame g_frame{0x131, 8, {1, 2, 3, 4, 5, 6, 7, 8}};

// Hands the globals' addresses to an empty asm that may read and write them, so the compiler
// can neither fold the inputs into constants nor drop the outputs.
void escape() {
  asm volatile("" ::"r"(&g_burst), "r"(&g_command), "r"(&g_sample), "r"(&g_pulses), "r"(&g_link_bytes),
               "r"(&g_frame)
               : "memory");
}

__attribute__((noinline)) void step() {
  escape();
  fw::drivers::mpu6000::Raw raw;
  if (fw::drivers::mpu6000::parse(g_burst, raw))
    g_sample = fw::drivers::mpu6000::to_sample(raw, board::kImuRange, board::kImuMounting, 1000);
  for (std::size_t i = 0; i < 4; ++i) {
    const std::uint16_t value = fw::drivers::dshot::value_from_command(g_command[i], true);
    g_pulses[board::kMotorPad[i]] =
        fw::drivers::dshot::pulses(fw::drivers::dshot::frame(value, false), board::kDshot600);
  }
  (void)pa::serial_frame::encode(g_frame, g_link_bytes);
  escape();
}
}  // namespace flight_drivers

// The authenticated link's work for one received ground frame in the ticks (fw/link_guard.hpp):
// the check's three steps, one per tick. The AUTH's counter is always fresh and its tag wrong,
// so every frame runs the whole check (a valid one costs the same, then a copy); the self-test
// flight's ticks include this for every frame. Queueing the pair happens between ticks.
namespace link_auth {
fw::LinkConfig config() {
  fw::LinkConfig c;
  for (std::size_t i = 0; i < c.key.size(); ++i) c.key[i] = static_cast<std::uint8_t>(0x40 + i);
  c.session_nonce = 0x12345678u;
  return c;
}
fw::LinkGuard g_guard(config());
pa::proto::Frame g_frame{0x031, 8, {0x10, 0x00, 0xF0, 0xFF, 0x00, 0x00, 0xD5, 0x13}};
pa::proto::Frame g_auth{0x071, 8, {0x01, 0x00, 0xA1, 0xB2, 0xC3, 0xD4, 0xE5, 0xF6}};

void queue_pair() {
  asm volatile("" ::"r"(&g_frame), "r"(&g_auth) : "memory");
  pa::proto::Message m;
  (void)pa::proto::decode(g_frame, m);
  g_guard.on_frame(g_frame, m, 0);
  g_guard.on_auth(g_auth);
}
__attribute__((noinline)) void step() {
  pa::proto::Message out;
  std::uint32_t received_us = 0;
  (void)g_guard.verify_next(out, received_us);
  asm volatile("" ::"r"(&out) : "memory");
}
}  // namespace link_auth

// The battery's compensation per reading (fw/battery_compensation.hpp), between ticks at 100 Hz:
// a reading filtered into a new factor and the mixer's ceiling set from it, as
// Vehicle::note_battery_mv does; the readings alternate so each one changes the factor.
namespace battery {
fw::BatteryCompensation g_battery{fw::BatteryConfig{}};
fw::Mixer g_mixer{fw::AirframeConfig{}};
std::uint32_t g_now_us = 0;
std::uint16_t g_mv = 11400;

__attribute__((noinline)) void step() {
  asm volatile("" ::"r"(&g_battery), "r"(&g_mixer), "r"(&g_mv) : "memory");
  g_now_us += 10000u;
  g_mv = g_mv == 11400 ? 11500 : 11400;
  if (g_battery.on_voltage_mv(g_mv, g_now_us)) g_mixer.set_command_factor(g_battery.factor());
  asm volatile("" ::"r"(&g_battery), "r"(&g_mixer) : "memory");
}
}  // namespace battery

bool within(float measured, float expected, float tolerance) {
  return measured > expected * (1.0f - tolerance) && measured < expected * (1.0f + tolerance);
}

// Net instructions of a bracketed span, after the probe's own cost.
float net_instructions(std::uint64_t counts, std::uint64_t overhead_counts) {
  return InstructionCounter::instructions(counts > overhead_counts ? counts - overhead_counts : 0);
}

void print_figure(const char* name, float value, int decimals) {
  ConsoleLine().text(name).text(": ").fixed(value, decimals).emit();
}

}  // namespace

int main() {
  InstructionCounter::start();
  ConsoleLine()
      .text("mps2-an386: firmware core self-test flight, instructions counted with -icount shift=")
      .u32(InstructionCounter::kIcountShift)
      .emit();

  // The instruction figure is trusted only if code of known length measures what it is: a
  // short straight run (the resolution) and a long loop across counter wraps (the widening).
  const float short_run = instructions_beyond_empty_call(run_1000_nops);
  ConsoleLine().text("calibration: measured ").fixed(short_run, 2).text(" for 1000 instructions").emit();
  const float long_run = instructions_beyond_empty_call(run_loop);
  ConsoleLine()
      .text("calibration: measured ")
      .fixed(long_run, 0)
      .text(" for ")
      .u32(2u * kLoopIterations)
      .text(" instructions across SysTick wraps")
      .emit();
  // 2 % on the short run; 0.1 % on the long one (its set-up and the wrap interrupts add a
  // few dozen instructions at most; a lost or doubled wrap would be off by 82 %).
  const bool calibrated =
      within(short_run, 1000.0f, 0.02f) && within(long_run, 2.0f * kLoopIterations, 0.001f);

  const std::uint64_t overhead = probe_overhead_counts();
  InstructionProbe probe;
  const fw::selftest::Result r = fw::selftest::run(&probe);

  ConsoleLine().text("ticks: ").u32(r.ticks).emit();
  print_figure("hover_rate_error_max_radps", r.hover_rate_error_max_radps, 4);
  print_figure("manoeuvre_rate_error_rms_radps", r.manoeuvre_rate_error_rms_radps, 4);
  print_figure("impact_detection_latency_ms", r.impact_detection_latency_ms, 1);
  print_figure("impact_timestamp_error_ms", r.impact_timestamp_error_ms, 1);
  print_figure("failsafe_hover_after_ms", r.failsafe_hover_after_ms, 1);
  print_figure("descent_after_ms", r.descent_after_ms, 1);
  print_figure("motors_off_after_landing_ms", r.motors_off_after_landing_ms, 1);
  print_figure("probe_overhead_instructions", InstructionCounter::instructions(overhead), 1);
  ConsoleLine()
      .text("tick_instructions_mean: ")
      .fixed(net_instructions(probe.mean_counts(), overhead), 0)
      .emit();
  ConsoleLine()
      .text("tick_instructions_max: ")
      .fixed(net_instructions(probe.max_counts(), overhead), 0)
      .emit();
  ConsoleLine().text("tick_instructions_max_at_tick: ").u32(probe.max_tick()).emit();
  // The flight image's tick: the worst core tick plus its drivers' pure work per sample.
  const float drivers = instructions_beyond_empty_call(flight_drivers::step);
  print_figure("flight_driver_instructions", drivers, 0);
  print_figure("flight_tick_instructions_max", net_instructions(probe.max_counts(), overhead) + drivers, 0);
  // Already inside the ticks above: one step of one frame's check per tick at most.
  link_auth::queue_pair();
  print_figure("link_auth_step1_instructions", instructions_beyond_empty_call(link_auth::step), 0);
  print_figure("link_auth_step2_instructions", instructions_beyond_empty_call(link_auth::step), 0);
  print_figure("link_auth_step3_instructions", instructions_beyond_empty_call(link_auth::step), 0);

  // Between ticks, once per voltage reading (the tick itself only reads the mixer's ceiling).
  battery::step();  // the first reading starts the filter
  print_figure("battery_reading_instructions", instructions_beyond_empty_call(battery::step), 0);

  // The start-up code painted the stack; a high-water mark at the very end of it means the
  // stack may have run into .bss and nothing above can be trusted.
  const std::uint32_t stack_used = cortex_m::stack_used_bytes();
  const std::uint32_t stack_size = cortex_m::stack_size_bytes();
  ConsoleLine().text("stack_used_bytes: ").u32(stack_used).text(" of ").u32(stack_size).emit();
  const bool stack_ok = stack_used + 64u <= stack_size;

  const char* failure = nullptr;
  if (!calibrated) failure = "calibration (is QEMU running with the matching -icount shift?)";
  else if (!stack_ok) failure = "stack (high-water mark within 64 bytes of the reservation)";
  else if (!r.pass) failure = r.failure != nullptr ? r.failure : "unnamed check";

  if (failure == nullptr) {
    ConsoleLine().text("selftest: pass").emit();
    return 0;
  }
  ConsoleLine().text("selftest: fail ").text(failure).emit();
  return 1;
}

// The STM32F405 flight image for the Omnibus F4 (README.md, "Flight image"): the firmware core
// fed by the board's MPU-6000 and driving four ESCs with DShot600 (or PWM: motor_output.hpp),
// talking to the ground over a UART radio link. Start-up: clocks, the microsecond clock (TIM5),
// console and link UARTs, battery ADC, LED, motor outputs (held at motor stop), then the IMU; a missing or wrong IMU
// is reported on the console and by the LED, and the motors stay stopped. The 1 kHz loop is
// the IMU's data-ready interrupt (with no IMU, the beat: see main); a 1 ms SysTick beat does the
// housekeeping.
#include <array>
#include <cstdint>
#include <limits>

#include "clock.hpp"
#include "cortex_m/runtime.hpp"
#include "cycle_counter.hpp"
#include "flight_io.hpp"
#include "fw/config.hpp"
#include "fw/drivers/omnibus_f4.hpp"
#include "imu_spi.hpp"
#include "link_identity.hpp"
#include "microsecond_clock.hpp"
#include "motor_output.hpp"
#include "pa/serial_frame.hpp"
#include "pins.hpp"
#include "registers.hpp"
#include "vehicle_node.hpp"

#ifndef PA_STM32F405_NODE
#define PA_STM32F405_NODE 1
#endif
static_assert(pa::VehicleId(PA_STM32F405_NODE).valid(), "PA_STM32F405_NODE must be a vehicle node, 1..14");

namespace stm32f405::flight {
namespace {

using namespace stm32f4;
namespace board = fw::drivers::omnibus_f4;
namespace mpu = fw::drivers::mpu6000;
namespace serial_frame = pa::serial_frame;

Uart g_link;
Uart g_console;
volatile std::uint32_t g_ms = 0;

// Without an IMU sample for this long (IMU gone or never there) the motors are stopped: the
// core cannot fly without its samples.
constexpr std::uint32_t kImuSilenceMs = 20;
constexpr std::uint32_t kBatteryPeriodMs = 10;
constexpr std::uint32_t kStatusPeriodMs = 1000;
constexpr std::uint8_t kPriorityLink = 1, kPriorityConsole = 3;

// The board's own health, for the console and a debugger.
struct FlightStatus {
  ClockReport clock{};
  mpu::InitResult imu{};
  bool link_keyed = false;    // a key in the slot and a nonce from the RNG (link_identity.hpp)
  bool motors_ready = false;  // the motor output has a timing for this clock
  bool motors_enabled = false;
  std::uint16_t battery_mv = 0;
  std::uint32_t ticks = 0;
  std::uint32_t tick_cycles_max = 0;
  std::uint32_t link_frames_in = 0;
  std::uint32_t link_frames_out = 0;
  std::uint32_t stack_used_bytes = 0;
  fw::ImuSample last_sample{};  // body frame, for checking the mounting by hand
};

}  // namespace
}  // namespace stm32f405::flight

// External linkage so the writes stay and a debugger finds it by name (as g_board_status in the
// HIL image).
extern "C" {
stm32f405::flight::FlightStatus g_flight_status;
}

namespace stm32f405::flight {

Uart& link() { return g_link; }
Uart& console() { return g_console; }
void on_millisecond() { g_ms = g_ms + 1u; }
std::uint32_t milliseconds() { return g_ms; }

namespace {

FlightStatus& status() { return g_flight_status; }

// The flight image's side of the seam: motor commands to the ESCs, frames to the radio link.
struct FlightIo {
  void write_motors(const fw::TickOutput& out) {
    MotorOutput::write(out.motor_command, out.motors_enabled);
    status().motors_enabled = out.motors_enabled;
  }
  void send(const pa::proto::Frame& frame) {
    std::array<std::uint8_t, serial_frame::kMaxBytes> bytes{};
    const std::size_t n = serial_frame::encode(frame, bytes);
    if (n != 0 && g_link.send(bytes.data(), n)) ++status().link_frames_out;
  }
};

// A status line built without printf (newlib's pulls in malloc through its stdio buffers).
// Not inlined: the status report calls these dozens of times and would grow by kilobytes.
class Line {
 public:
  __attribute__((noinline)) Line& text(const char* s) {
    while (*s != '\0') put(*s++);
    return *this;
  }
  __attribute__((noinline)) Line& u32(std::uint32_t v) {
    char digits[10];
    int n = 0;
    do {
      digits[n++] = static_cast<char>('0' + v % 10u);
      v /= 10u;
    } while (v != 0u);
    while (n > 0) put(digits[--n]);
    return *this;
  }
  __attribute__((noinline)) Line& i32(std::int32_t v) {
    if (v < 0) put('-');
    return u32(v < 0 ? 0u - static_cast<std::uint32_t>(v) : static_cast<std::uint32_t>(v));
  }
  // Three values scaled to whole units (centimetres, milliradians), for the console.
  Line& vec(const fw::Vec3f& v, float scale) {
    for (std::size_t i = 0; i < 3; ++i) {
      const float x = v[i] * scale;
      const float clamped = x > 1e9f ? 1e9f : x < -1e9f ? -1e9f : x;  // NaN stays NaN, then 0
      i32(clamped == clamped ? static_cast<std::int32_t>(clamped) : 0).text(i < 2 ? "," : "");
    }
    return *this;
  }
  __attribute__((noinline)) Line& hex8(std::uint8_t v) {
    const char* hex = "0123456789abcdef";
    return text("0x").put(hex[v >> 4]).put(hex[v & 0xFu]);
  }
  void emit() {
    buffer_[length_++] = '\r';  // room kept by put()
    buffer_[length_++] = '\n';
    g_console.send(buffer_.data(), length_);
  }

 private:
  Line& put(char c) {
    if (length_ + 2u < buffer_.size()) buffer_[length_++] = static_cast<std::uint8_t>(c);
    return *this;
  }
  std::array<std::uint8_t, 320> buffer_{};
  std::size_t length_ = 0;
};

const char* clock_name(ClockSource s) {
  return s == ClockSource::hse_pll ? "hse_pll" : s == ClockSource::hsi_pll ? "hsi_pll" : "hsi";
}

void report(const char* what) {
  const FlightStatus& s = status();
  const MotorOutputStats& m = MotorOutput::stats();
  const ImuStats imu = Imu::stats();
  Line line;
  line.text("flight: ").text(board::kName).text(" ").text(what).text(" t_ms=").u32(g_ms);
  line.text(" clock=").text(clock_name(s.clock.source)).text(" imu=").text(mpu::to_string(s.imu.status));
  line.text(" who_am_i=").hex8(s.imu.who_am_i);
  if (s.imu.status == mpu::Status::config_rejected || s.imu.status == mpu::Status::bus_error)
    line.text(" imu_register=").hex8(s.imu.failed_register);
  line.text(" samples=").u32(imu.samples);
  line.text(" bad=").u32(imu.bad_bursts + imu.bus_timeouts).text(" ticks=").u32(s.ticks);
  line.text(" acc_cmps2=")
      .vec(s.last_sample.accel_mps2, 100.0f)
      .text(" gyro_mradps=")
      .vec(s.last_sample.gyro_radps, 1000.0f);
  line.text(" tick_cycles_max=").u32(s.tick_cycles_max);
  line.text(" motors=").text(s.motors_enabled ? "on" : "off").text(" ").text(MotorOutput::name()).text("=");
  for (std::size_t i = 0; i < 4; ++i) line.u32(m.last_values[i]).text(i < 3 ? "," : "");
  line.text(" ").text(MotorOutput::name()).text("_frames=").u32(m.frames).text(" vbat_mv=").u32(s.battery_mv);
  line.text(" link_in=").u32(s.link_frames_in).text(" link_out=").u32(s.link_frames_out);
  line.text(" link_key=").text(s.link_keyed ? "yes" : "none");
  line.text(" stack=").u32(s.stack_used_bytes);
  line.emit();
}

void battery_init() {
  rcc().APB2ENR |= rcc_bits::apb2_adc1;
  (void)rcc().APB2ENR;
  configure_pin(board::kBatteryPin, gpio_mode_analog);
  adc_common_ccr() = (adc_common_ccr() & ~(3u << 16)) | (1u << 16);  // ADCCLK = APB2 / 4 (21 MHz)
  Adc& a = adc1();
  const std::uint32_t ch = board::kBatteryAdcChannel;  // 10..18 are in SMPR1
  a.SMPR1 = (a.SMPR1 & ~(7u << (3u * (ch - 10u)))) |
            (7u << (3u * (ch - 10u)));  // 480 cycles: a high-impedance divider
  a.SQR1 = 0;                           // one conversion
  a.SQR3 = ch;
  a.CR2 = adc_bits::cr2_adon;
}

// Takes the last conversion if done and starts the next: never waits.
void battery_poll(fw::Vehicle& vehicle) {
  Adc& a = adc1();
  if ((a.SR & adc_bits::sr_eoc) != 0u) {
    status().battery_mv = board::battery_mv(static_cast<std::uint16_t>(a.DR));
    vehicle.note_battery_mv(status().battery_mv);
  }
  a.CR2 |= adc_bits::cr2_swstart;
}

// Slow blink: healthy, motors stopped. Steady: motors running. Fast blink: a fault (no IMU,
// wrong IMU, no motor output timing) that keeps the motors stopped.
void led_update(std::uint32_t ms, bool fault) {
  bool lit = status().motors_enabled;
  if (fault) lit = (ms / 100u) % 2u == 0u;
  else if (!lit) lit = (ms / 500u) % 2u == 0u;
  write_pin(board::kLed, board::kLedActiveLow ? !lit : lit);
}

void start_millisecond_beat(std::uint32_t sysclk_hz) {
  systick().CSR = 0;
  systick().RVR = sysclk_hz / 1000u - 1u;
  systick().CVR = 0;
  systick().CSR = systick_enable | systick_tickint | systick_cpu_clock;
}

fw::VehicleConfig make_config(FlightStatus& s) {
  fw::VehicleConfig config{};
  config.link.vehicle = pa::VehicleId(PA_STM32F405_NODE);
  s.link_keyed = load_link_identity(config.link, s.clock.sysclk_hz) && pa::auth::provisioned(config.link.key);
  return config;
}

}  // namespace
}  // namespace stm32f405::flight

int main() {
  using namespace stm32f405;
  using namespace stm32f405::flight;
  namespace board = fw::drivers::omnibus_f4;

  CycleCounter::start();  // start-up timeouts count its cycles
  FlightStatus& s = status();
  s.clock = clock_init();
  FlightMicrosecondClock::start(s.clock.apb1_timer_hz);
  configure_pin(board::kLed, stm32f4::gpio_mode_output);
  g_console.init(stm32f4::kUsart3Base, stm32f4::irq::usart3, board::kConsoleTx, board::kConsoleRx,
                 s.clock.apb1_hz, board::kConsoleBaud, kPriorityConsole);
  g_link.init(stm32f4::kUsart1Base, stm32f4::irq::usart1, board::kLinkTx, board::kLinkRx, s.clock.apb2_hz,
              board::kLinkBaud, kPriorityLink);
  battery_init();
  // Motor stop before anything else can fail: ESCs see a valid signal that keeps them stopped.
  s.motors_ready = MotorOutput::init(s.clock.apb1_timer_hz);
  MotorOutput::stop();
  s.imu = Imu::init(s.clock.apb2_hz);
  const bool imu_fault = s.imu.status != fw::drivers::mpu6000::Status::ok;
  const bool fault = imu_fault || !s.motors_ready;
  report(fault ? "boot FAULT: motors held stopped" : "boot ok");

  // The composition root: the one vehicle, built once the clocks are known.
  static VehicleNode<FlightIo> node(make_config(s), s.clock.sysclk_hz / 1000000u, FlightIo{});
  pa::serial_frame::Decoder decoder;
  start_millisecond_beat(s.clock.sysclk_hz);

  std::uint32_t last_ms = milliseconds();
  std::uint32_t last_tick_ms = last_ms;
  std::uint32_t last_status_ms = last_ms;
  // What the core is given in place of a sample when there is no IMU: NaN, which it does not use
  // (imu_ok false), so the supervisor sees the IMU lost and refuses ARM.
  constexpr float kNoReading = std::numeric_limits<float>::quiet_NaN();
  fw::ImuSample no_imu{};
  no_imu.gyro_radps = {kNoReading, kNoReading, kNoReading};
  no_imu.accel_mps2 = {kNoReading, kNoReading, kNoReading};
  for (;;) {
    // Frames from the ground, a bounded number per pass.
    std::uint8_t byte;
    pa::proto::Frame frame;
    for (int i = 0; i < 64 && g_link.receive(byte); ++i) {
      if (decoder.push(byte, frame)) {
        ++s.link_frames_in;
        node.on_frame(frame, FlightMicrosecondClock::now_us());
      }
    }

    fw::ImuSample sample;
    if (Imu::take_sample(sample)) {
      node.on_imu_sample(sample);
      s.last_sample = sample;
      last_tick_ms = milliseconds();
      s.ticks = node.stats().ticks;
      s.tick_cycles_max = node.stats().tick_cycles_max;
    }

    const std::uint32_t ms = milliseconds();
    if (ms != last_ms) {
      last_ms = ms;
      // With no IMU the beat ticks the core instead, so the ground link stays up: heartbeat,
      // session and telemetry go out, and COMMAND (ARM refused) and KILL are handled. Not a
      // sample: last_tick_ms and last_sample keep to the real ones.
      if (imu_fault) {
        no_imu.t_us = FlightMicrosecondClock::now_us();
        node.on_imu_sample(no_imu);
        s.ticks = node.stats().ticks;
        s.tick_cycles_max = node.stats().tick_cycles_max;
      }
      // After the tick, so that a fault's motor stop has the last word.
      if (fault || ms - last_tick_ms > kImuSilenceMs) {
        MotorOutput::stop();  // refreshed every millisecond
        s.motors_enabled = false;
      }
      if (ms % kBatteryPeriodMs == 0u) battery_poll(node.vehicle());
      led_update(ms, fault);
      if (ms - last_status_ms >= kStatusPeriodMs) {
        last_status_ms = ms;
        s.stack_used_bytes = cortex_m::stack_used_bytes();
        report(fault ? "FAULT: motors held stopped" : "status");
      }
    }
    g_link.kick();
    g_console.kick();

    // Sleep until the next interrupt; masked across the check so one arriving in between
    // still wakes the core (WFI wakes on a pending interrupt even when masked). With no IMU the
    // next tick is the beat's, and SysTick wakes it.
    const std::uint32_t saved = stm32f4::irq_save();
    if (!Imu::sample_pending() && !g_link.rx_pending() && milliseconds() == last_ms) asm volatile("wfi");
    stm32f4::irq_restore(saved);
  }
}

#include "imu_spi.hpp"

#include <array>
#include <cstddef>

#include "fw/drivers/omnibus_f4.hpp"
#include "microsecond_clock.hpp"
#include "pins.hpp"
#include "registers.hpp"

namespace stm32f405 {
namespace {

using namespace stm32f4;
namespace board = fw::drivers::omnibus_f4;
namespace mpu = fw::drivers::mpu6000;

constexpr unsigned kPriorityDataReady = 0;  // most urgent: the sample time is stamped here
constexpr unsigned kPrioritySpi = 0;        // the same: the two never preempt each other
// Each pass of a wait reads a peripheral register and compares; a byte at the slow clock
// (656 kHz) is 12 us, well under this many passes at any CPU clock the board runs.
constexpr std::uint32_t kWaitPasses = 20000;

// Written by the interrupts: the burst in progress ...
volatile bool g_burst_busy = false;
std::uint32_t g_burst_index = 0;
std::uint32_t g_burst_stamp_us = 0;
std::array<std::uint8_t, mpu::kBurstBytes> g_burst{};
// ... and the last complete one, for the main loop (taken with interrupts masked).
volatile bool g_pending = false;
std::uint32_t g_stamp_us = 0;
std::array<std::uint8_t, mpu::kBurstBytes> g_sample_burst{};
ImuStats g_stats;  // data_ready, missed and bus_timeouts by the interrupts, the rest by the main loop

// SPI1 baud-rate divider (BR = 0..7 divides by 2^(BR+1)): the smallest within `max_hz`.
std::uint32_t divider_bits(std::uint32_t apb2_hz, std::uint32_t max_hz) {
  for (std::uint32_t br = 0; br < 7u; ++br)
    if ((apb2_hz >> (br + 1u)) <= max_hz) return br;
  return 7u;
}

void set_clock(std::uint32_t br) {
  Spi& s = spi1();
  s.CR1 &= ~spi_bits::cr1_spe;
  s.CR1 = (s.CR1 & ~(7u << spi_bits::cr1_br_shift)) | (br << spi_bits::cr1_br_shift);
  s.CR1 |= spi_bits::cr1_spe;
}

bool wait_flag(std::uint32_t flag) {
  for (std::uint32_t pass = 0; pass < kWaitPasses; ++pass)
    if ((spi1().SR & flag) != 0u) return true;
  return false;
}

bool transfer(std::uint8_t out, std::uint8_t& in) {
  if (!wait_flag(spi_bits::sr_txe)) return false;
  spi1().DR = out;
  if (!wait_flag(spi_bits::sr_rxne)) return false;
  in = static_cast<std::uint8_t>(spi1().DR);
  return true;
}

void select(bool on) { write_pin(board::kImuCs, !on); }  // chip select is active low

// The register bus of mpu6000::init over SPI1.
struct SpiBus {
  bool read(std::uint8_t reg, std::uint8_t* data, std::size_t n) {
    select(true);
    std::uint8_t ignored = 0;
    bool ok = transfer(static_cast<std::uint8_t>(reg | mpu::kReadBit), ignored);
    for (std::size_t i = 0; ok && i < n; ++i) ok = transfer(0x00, data[i]);
    select(false);
    return ok;
  }
  bool write(std::uint8_t reg, std::uint8_t value) {
    select(true);
    std::uint8_t ignored = 0;
    const bool ok = transfer(reg, ignored) && transfer(value, ignored);
    select(false);
    return ok;
  }
  void delay_ms(std::uint32_t ms) {
    // On the microsecond clock (running by now), bounded by a pass count as well.
    const std::uint32_t start = FlightMicrosecondClock::now_us();
    for (std::uint32_t pass = 0; pass < ms * 20000u; ++pass)
      if (FlightMicrosecondClock::now_us() - start >= ms * 1000u) return;
  }
};

void configure_data_ready() {
  rcc().APB2ENR |= rcc_bits::apb2_syscfg;
  (void)rcc().APB2ENR;
  configure_pin(board::kImuDataReady, 0u, Pull::down);     // input
  const std::uint32_t line = board::kImuDataReady.number;  // 4: EXTICR2 holds lines 4-7
  const std::uint32_t port = static_cast<std::uint32_t>(board::kImuDataReady.port - 'A');
  Reg& cr = syscfg().EXTICR[line / 4u];
  cr = (cr & ~(0xFu << (4u * (line % 4u)))) | (port << (4u * (line % 4u)));
  exti().RTSR |= 1u << line;
  exti().FTSR &= ~(1u << line);
  exti().PR = 1u << line;
  exti().IMR |= 1u << line;
  nvic_enable(irq::spi1, kPrioritySpi);
  nvic_enable(irq::exti4, kPriorityDataReady);
}

}  // namespace

mpu::InitResult Imu::init(std::uint32_t apb2_hz) {
  rcc().APB2ENR |= rcc_bits::apb2_spi1;
  (void)rcc().APB2ENR;
  configure_pin(board::kImuCs, gpio_mode_output);
  select(false);
  configure_pin(board::kSpiSck, gpio_mode_af);
  configure_pin(board::kSpiMiso, gpio_mode_af, Pull::up);  // an absent chip reads 0xFF, not noise
  configure_pin(board::kSpiMosi, gpio_mode_af);

  // Master, mode 3 (clock idles high, data taken on the rising edge), 8 bits, software chip select.
  spi1().CR1 =
      spi_bits::cr1_mstr | spi_bits::cr1_cpol | spi_bits::cr1_cpha | spi_bits::cr1_ssm | spi_bits::cr1_ssi;
  spi1().CR2 = 0;
  set_clock(divider_bits(apb2_hz, mpu::kSpiConfigHzMax));

  SpiBus bus;
  const mpu::InitResult r = mpu::init(bus, board::kImuRange);
  if (r.status != mpu::Status::ok) return r;
  set_clock(divider_bits(apb2_hz, mpu::kSpiSensorHzMax / 2u));  // 10.5 MHz at APB2 = 84 MHz
  configure_data_ready();
  return r;
}

// The burst runs on interrupts: data ready selects the chip and sends the address byte; each
// SPI RXNE interrupt stores a byte and sends the next dummy; the last one deselects the chip
// and hands the burst to the main loop. About 0.8 us per byte at 10.5 MHz, so a burst takes
// some 12 us of the 1000 us period and the main loop never waits for it.
void Imu::on_data_ready_interrupt() {
  exti().PR = 1u << board::kImuDataReady.number;
  ++g_stats.data_ready;
  if (g_burst_busy) {
    // A burst still running a whole period later is stuck (the SPI stopped): restart it.
    ++g_stats.bus_timeouts;
    select(false);
  }
  if (g_pending) ++g_stats.missed;  // the main loop has not taken the last sample: replaced
  g_pending = false;
  g_burst_stamp_us = FlightMicrosecondClock::now_us();
  g_burst_index = 0;
  g_burst_busy = true;
  (void)spi1().DR;  // no stale byte may count as the first
  select(true);
  spi1().CR2 = spi_bits::cr2_rxneie;
  spi1().DR = mpu::reg::accel_xout_h | mpu::kReadBit;
}

void Imu::on_spi_interrupt() {
  const auto byte = static_cast<std::uint8_t>(spi1().DR);  // clears RXNE
  if (!g_burst_busy) {
    spi1().CR2 = 0;
    return;
  }
  if (g_burst_index > 0u) g_burst[g_burst_index - 1u] = byte;  // byte 0 answered the address
  ++g_burst_index;
  if (g_burst_index <= mpu::kBurstBytes) {
    spi1().DR = 0x00;
    return;
  }
  select(false);
  spi1().CR2 = 0;
  g_burst_busy = false;
  g_sample_burst = g_burst;
  g_stamp_us = g_burst_stamp_us;
  g_pending = true;
}

bool Imu::sample_pending() { return g_pending; }

bool Imu::take_sample(fw::ImuSample& out) {
  if (!g_pending) return false;
  std::array<std::uint8_t, mpu::kBurstBytes> burst;
  const std::uint32_t saved = irq_save();
  burst = g_sample_burst;
  const std::uint32_t stamp = g_stamp_us;
  g_pending = false;
  irq_restore(saved);

  mpu::Raw raw;
  if (!mpu::parse(burst, raw)) {
    ++g_stats.bad_bursts;
    return false;
  }
  ++g_stats.samples;
  out = mpu::to_sample(raw, board::kImuRange, board::kImuMounting, stamp);
  return true;
}

ImuStats Imu::stats() {
  const std::uint32_t saved = irq_save();
  const ImuStats s = g_stats;
  irq_restore(saved);
  return s;
}

}  // namespace stm32f405

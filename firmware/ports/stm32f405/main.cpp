// The STM32F405 image: the firmware core on a flight controller, in hardware-in-the-loop mode
// over CAN1 (see README.md). Start-up: clocks (HSE -> 168 MHz, or the reported fallback), the
// microsecond clock, CAN1 at 1 Mbit/s; then the main loop hands every received frame to the
// HIL node and sleeps until the next interrupt.
#include <cstdint>

#include "bxcan.hpp"
#include "clock.hpp"
#include "cortex_m/runtime.hpp"
#include "cycle_counter.hpp"
#include "fw/config.hpp"
#include "hil_can_node.hpp"
#include "link_identity.hpp"
#include "microsecond_clock.hpp"
#include "pa/sequence.hpp"
#include "registers.hpp"

#ifndef PA_STM32F405_NODE
#define PA_STM32F405_NODE 1
#endif
static_assert(pa::VehicleId(PA_STM32F405_NODE).valid(), "PA_STM32F405_NODE must be a vehicle node, 1..14");

namespace {

using namespace stm32f405;

// The board's own health, for a debugger (this board has no console): the clock actually
// running, how CAN came up, the busiest tick and the longest silence of the HIL stream.
struct BoardStatus {
  ClockReport clock{};
  bool link_keyed = false;  // a key in the slot and a nonce from the RNG (link_identity.hpp)
  CanInitResult can_init = CanInitResult::no_init_mode;
  CanStats can{};
  HilCanStats hil{};
  std::uint32_t hil_sample_gap_max_us = 0;  // longest wait between ticks, on TIM2's clock
  std::uint32_t stack_used_bytes = 0;       // high-water mark of the 4 KiB main stack
};

fw::VehicleConfig make_config(BoardStatus& status) {
  fw::VehicleConfig config{};
  config.link.vehicle = pa::VehicleId(PA_STM32F405_NODE);
  status.link_keyed =
      load_link_identity(config.link, status.clock.sysclk_hz) && pa::auth::provisioned(config.link.key);
  return config;
}

}  // namespace

// External linkage so the writes stay and a debugger finds it by name.
extern "C" {
BoardStatus g_board_status;
}

int main() {
  CycleCounter::start();  // start-up timeouts count its cycles
  g_board_status.clock = clock_init();
  MicrosecondClock::start(g_board_status.clock.apb1_timer_hz);
  g_board_status.can_init = Can1::init(g_board_status.clock.apb1_hz, g_board_status.clock.sysclk_hz);

  // The composition root: the one vehicle, built once the clocks are known.
  static HilCanNode node(make_config(g_board_status), g_board_status.clock.sysclk_hz / 1000000u);

  std::uint32_t last_tick_us = MicrosecondClock::now_us();
  std::uint32_t ticks_seen = 0;
  for (;;) {
    pa::proto::Frame frame;
    while (Can1::receive(frame)) node.on_frame(frame);

    if (node.stats().ticks != ticks_seen) {
      const std::uint32_t now_us = MicrosecondClock::now_us();
      const auto gap_us = static_cast<std::uint32_t>(pa::elapsed_us(now_us, last_tick_us));
      if (ticks_seen != 0 && gap_us > g_board_status.hil_sample_gap_max_us)
        g_board_status.hil_sample_gap_max_us = gap_us;
      last_tick_us = now_us;
      ticks_seen = node.stats().ticks;
      if ((ticks_seen & 1023u) == 0u) {  // ~1 Hz
        g_board_status.stack_used_bytes = cortex_m::stack_used_bytes();
      }
    }
    g_board_status.can = Can1::stats();
    g_board_status.hil = node.stats();

    // Sleep until the next interrupt. Interrupts are masked across the check so a frame
    // arriving between it and WFI still wakes the core (WFI wakes on a pending interrupt
    // even when masked; the handler runs once they are unmasked).
    const std::uint32_t saved = stm32f4::irq_save();
    if (!Can1::rx_pending()) asm volatile("wfi");
    stm32f4::irq_restore(saved);
  }
}

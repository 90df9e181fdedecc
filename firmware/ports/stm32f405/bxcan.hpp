// CAN1 (bxCAN) on PB8 (CAN1_RX) / PB9 (CAN1_TX), alternate function 9, at 1 Mbit/s.
//
// Receive: one filter bank passes every standard-identifier data frame into FIFO0; its
// interrupt drains the FIFO into a lock-free ring the main loop reads. Transmit: frames are
// queued in a second ring and moved into free mailboxes by the transmit interrupt (the main
// loop pends it after queuing), in request order (TXFP), so frames leave in the order they
// were sent. Bus-off is left automatically after 128 x 11 recessive bits (ABOM). Every drop
// is counted, nothing blocks, nothing allocates.
#pragma once

#include <cstdint>

#include "pa/protocol.hpp"

namespace stm32f405 {

struct CanStats {
  std::uint32_t rx_frames = 0;          // delivered to the receive ring
  std::uint32_t rx_fifo_overruns = 0;   // hardware FIFO overran before the interrupt ran
  std::uint32_t rx_ring_overflows = 0;  // the main loop fell behind; frame dropped
  std::uint32_t rx_rejected = 0;        // extended-identifier or remote frames
  std::uint32_t tx_frames = 0;          // transmitted and acknowledged
  std::uint32_t tx_errors = 0;          // attempts that ended in an error
  std::uint32_t tx_arbitration_lost = 0;
  std::uint32_t tx_ring_overflows = 0;  // queue full; frame dropped
  std::uint32_t tx_invalid = 0;         // bad identifier or length; frame dropped
  std::uint32_t bus_off_events = 0;
  // Live state from CAN_ESR.
  std::uint8_t tx_error_counter = 0;
  std::uint8_t rx_error_counter = 0;
  std::uint8_t last_error_code = 0;  // 0 none, 1 stuff, 2 form, 3 ack, 4 recessive, 5 dominant, 6 crc
  bool error_warning = false;
  bool error_passive = false;
  bool bus_off = false;
};

enum class CanInitResult : std::uint8_t {
  ok = 0,
  bad_bit_timing,    // the APB1 clock allows no exact 1 Mbit/s timing
  no_init_mode,      // the controller never acknowledged initialisation mode
  not_synchronised,  // configured, but no 11 recessive bits seen yet (it joins by itself later)
};

class Can1 {
 public:
  static constexpr std::uint32_t kBitrate = 1000000;

  // `apb1_hz` is bxCAN's kernel clock; `sysclk_hz` paces the start-up timeouts.
  static CanInitResult init(std::uint32_t apb1_hz, std::uint32_t sysclk_hz);

  // Queues a frame; false (and counted) when the queue is full or the frame is malformed.
  static bool send(const pa::proto::Frame& frame);
  // Takes the oldest received frame; false when none is waiting.
  static bool receive(pa::proto::Frame& frame);
  static bool rx_pending();

  // A consistent snapshot of the counters and the live error state.
  static CanStats stats();

  // Interrupt entry points (startup.cpp's vector table).
  static void on_tx_interrupt();
  static void on_rx0_interrupt();
  static void on_status_change_error_interrupt();
};

}  // namespace stm32f405

#include "bxcan.hpp"

#include "can_bit_timing.hpp"
#include "cycle_counter.hpp"
#include "registers.hpp"
#include "spsc_ring.hpp"

namespace stm32f405 {
namespace {

using namespace stm32f4;
using pa::proto::Frame;

// 64 received frames is 64 ms of the busiest HIL stream (two IMU frames per 1 kHz tick
// plus ground traffic) at 1 Mbit/s; 32 queued for transmission covers a tick's burst.
SpscRing<Frame, 64> g_rx;  // producer: RX0 interrupt; consumer: main loop
SpscRing<Frame, 32> g_tx;  // producer: main loop; consumer: TX interrupt
CanStats g_stats;          // counters written only by the interrupts
bool g_was_bus_off = false;

constexpr std::uint32_t kMailboxes = 3;
constexpr unsigned kPriorityRx = 1, kPriorityTx = 2, kPrioritySce = 3;  // lower is more urgent

std::uint32_t pack(const Frame& f, int first) {
  return static_cast<std::uint32_t>(f.data[first]) | (static_cast<std::uint32_t>(f.data[first + 1]) << 8) |
         (static_cast<std::uint32_t>(f.data[first + 2]) << 16) |
         (static_cast<std::uint32_t>(f.data[first + 3]) << 24);
}

void unpack(std::uint32_t word, Frame& f, int first) {
  for (int i = 0; i < 4; ++i) f.data[first + i] = static_cast<std::uint8_t>(word >> (8 * i));
}

void configure_pins() {
  rcc().AHB1ENR |= rcc_bits::ahb1_gpiob;
  (void)rcc().AHB1ENR;
  Gpio& b = gpiob();
  constexpr std::uint32_t kRx = 8, kTx = 9, kAf9 = 9;
  b.MODER = (b.MODER & ~((3u << (2 * kRx)) | (3u << (2 * kTx)))) | (2u << (2 * kRx)) | (2u << (2 * kTx));
  b.OTYPER &= ~((1u << kRx) | (1u << kTx));                                            // push-pull
  b.OSPEEDR |= (2u << (2 * kRx)) | (2u << (2 * kTx));                                  // fast
  b.PUPDR = (b.PUPDR & ~((3u << (2 * kRx)) | (3u << (2 * kTx)))) | (1u << (2 * kRx));  // RX pulled recessive
  b.AFRH = (b.AFRH & ~0xFFu) | (kAf9 << (4 * (kRx - 8))) | (kAf9 << (4 * (kTx - 8)));
}

void configure_filters() {
  Can& c = can1();
  c.FMR |= can_bits::fmr_finit;
  c.FA1R &= ~1u;                                          // bank 0 off while it is changed
  c.FS1R |= 1u;                                           // one 32-bit filter
  c.FM1R &= ~1u;                                          // identifier-mask mode
  c.FFA1R &= ~1u;                                         // to FIFO0
  c.filter[0].FR1 = 0;                                    // IDE = 0, RTR = 0 ...
  c.filter[0].FR2 = can_bits::ir_ide | can_bits::ir_rtr;  // ... must match; the identifier is free
  c.FA1R |= 1u;
  c.FMR &= ~can_bits::fmr_finit;
}

// Moves queued frames into free mailboxes. Runs only in the TX interrupt (the only consumer).
void fill_mailboxes() {
  Can& c = can1();
  for (std::uint32_t i = 0; i < kMailboxes; ++i) {
    const std::uint32_t tsr = c.TSR;
    if ((tsr & (7u * can_bits::tsr_tme0)) == 0u) return;  // none free
    Frame f;
    if (!g_tx.pop(f)) return;
    CanTxMailbox& mb = c.tx[(tsr >> 24) & 3u];  // CODE: the next free mailbox
    mb.TDTR = f.len;
    mb.TDLR = pack(f, 0);
    mb.TDHR = pack(f, 4);
    mb.TIR = (static_cast<std::uint32_t>(f.id) << can_bits::ir_stid_shift) | can_bits::ir_txrq;
  }
}

}  // namespace

CanInitResult Can1::init(std::uint32_t apb1_hz, std::uint32_t sysclk_hz) {
  const CanBitTiming timing = can_bit_timing(apb1_hz, kBitrate);
  if (!timing.valid) return CanInitResult::bad_bit_timing;

  rcc().APB1ENR |= rcc_bits::apb1_can1;
  rcc().APB1RSTR |= rcc_bits::apb1_can1;
  rcc().APB1RSTR &= ~rcc_bits::apb1_can1;
  (void)rcc().APB1ENR;
  configure_pins();

  Can& c = can1();
  const std::uint32_t timeout = sysclk_hz / 100u;  // 10 ms
  c.MCR = (c.MCR & ~can_bits::mcr_sleep) | can_bits::mcr_inrq;
  if (!wait_for(c.MSR, can_bits::msr_inak | can_bits::msr_slak, can_bits::msr_inak, timeout))
    return CanInitResult::no_init_mode;

  // Automatic bus-off recovery, automatic wake-up, retransmission on, transmit in request
  // order, a full receive FIFO keeps the newest frame.
  c.MCR = (c.MCR & ~(can_bits::mcr_nart | can_bits::mcr_rflm)) | can_bits::mcr_abom | can_bits::mcr_awum |
          can_bits::mcr_txfp | can_bits::mcr_inrq;
  c.BTR = timing.btr();
  configure_filters();

  c.IER = can_bits::ier_fmpie0 | can_bits::ier_fovie0 | can_bits::ier_tmeie | can_bits::ier_errie |
          can_bits::ier_bofie | can_bits::ier_epvie | can_bits::ier_ewgie;
  nvic_enable(irq::can1_rx0, kPriorityRx);
  nvic_enable(irq::can1_tx, kPriorityTx);
  nvic_enable(irq::can1_sce, kPrioritySce);

  c.MCR &= ~can_bits::mcr_inrq;
  if (!wait_for(c.MSR, can_bits::msr_inak, 0u, timeout)) return CanInitResult::not_synchronised;
  return CanInitResult::ok;
}

bool Can1::send(const Frame& frame) {
  if (frame.id > 0x7FFu || frame.len > pa::proto::kMaxPayload) {
    const std::uint32_t saved = irq_save();
    ++g_stats.tx_invalid;
    irq_restore(saved);
    return false;
  }
  const bool queued = g_tx.push(frame);
  if (!queued) {
    const std::uint32_t saved = irq_save();
    ++g_stats.tx_ring_overflows;
    irq_restore(saved);
  }
  nvic_set_pending(irq::can1_tx);  // the TX interrupt moves it into a mailbox
  return queued;
}

bool Can1::receive(Frame& frame) { return g_rx.pop(frame); }

bool Can1::rx_pending() { return !g_rx.empty(); }

CanStats Can1::stats() {
  const std::uint32_t saved = irq_save();
  CanStats s = g_stats;
  irq_restore(saved);
  const std::uint32_t esr = can1().ESR;
  s.tx_error_counter = static_cast<std::uint8_t>(esr >> can_bits::esr_tec_shift);
  s.rx_error_counter = static_cast<std::uint8_t>(esr >> can_bits::esr_rec_shift);
  s.last_error_code = static_cast<std::uint8_t>((esr & can_bits::esr_lec_mask) >> can_bits::esr_lec_shift);
  s.error_warning = (esr & can_bits::esr_ewgf) != 0u;
  s.error_passive = (esr & can_bits::esr_epvf) != 0u;
  s.bus_off = (esr & can_bits::esr_boff) != 0u;
  return s;
}

void Can1::on_tx_interrupt() {
  Can& c = can1();
  const std::uint32_t tsr = c.TSR;
  for (std::uint32_t m = 0; m < kMailboxes; ++m) {
    const std::uint32_t shift = m * can_bits::tsr_mailbox_stride;
    if ((tsr & (can_bits::tsr_rqcp0 << shift)) == 0u) continue;
    if ((tsr & (can_bits::tsr_txok0 << shift)) != 0u) ++g_stats.tx_frames;
    if ((tsr & (can_bits::tsr_alst0 << shift)) != 0u) ++g_stats.tx_arbitration_lost;
    if ((tsr & (can_bits::tsr_terr0 << shift)) != 0u) ++g_stats.tx_errors;
    c.TSR = can_bits::tsr_rqcp0 << shift;  // clears RQCP, TXOK, ALST and TERR of this mailbox
  }
  fill_mailboxes();
}

void Can1::on_rx0_interrupt() {
  Can& c = can1();
  const std::uint32_t rf = c.RF0R;
  if ((rf & can_bits::rfr_fovr) != 0u) {
    ++g_stats.rx_fifo_overruns;
    c.RF0R = can_bits::rfr_fovr;
  }
  if ((rf & can_bits::rfr_full) != 0u) c.RF0R = can_bits::rfr_full;
  // At most the FIFO's three frames per entry, so the handler is bounded; it re-enters
  // while frames remain.
  for (int i = 0; i < 3 && (c.RF0R & can_bits::rfr_fmp_mask) != 0u; ++i) {
    const CanRxFifo& mb = c.rx[0];
    const std::uint32_t rir = mb.RIR;
    const std::uint32_t rdtr = mb.RDTR;
    const std::uint32_t low = mb.RDLR;
    const std::uint32_t high = mb.RDHR;
    c.RF0R = can_bits::rfr_rfom;  // release the slot
    if ((rir & (can_bits::ir_ide | can_bits::ir_rtr)) != 0u) {
      ++g_stats.rx_rejected;
      continue;
    }
    Frame f;
    f.id = static_cast<std::uint16_t>(rir >> can_bits::ir_stid_shift);
    const std::uint32_t dlc = rdtr & 0xFu;  // a DLC of 9..15 still means 8 bytes
    f.len = static_cast<std::uint8_t>(dlc > pa::proto::kMaxPayload ? pa::proto::kMaxPayload : dlc);
    unpack(low, f, 0);
    unpack(high, f, 4);
    if (g_rx.push(f)) ++g_stats.rx_frames;
    else ++g_stats.rx_ring_overflows;
  }
}

// The interrupt fires when an error-state flag is set, never when one clears. Leaving bus-off
// resets the error counters, so the next bus-off is preceded by fresh warning and passive
// interrupts (TEC >= 96, >= 128) that see BOFF clear, and each bus-off is counted once.
void Can1::on_status_change_error_interrupt() {
  Can& c = can1();
  const bool bus_off = (c.ESR & can_bits::esr_boff) != 0u;
  if (bus_off && !g_was_bus_off) ++g_stats.bus_off_events;
  g_was_bus_off = bus_off;
  c.MSR = can_bits::msr_erri;  // acknowledge
}

}  // namespace stm32f405

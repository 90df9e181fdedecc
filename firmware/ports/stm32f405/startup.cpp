// What the STM32F405 image adds to the shared Cortex-M runtime (cortex_m/runtime.hpp): VTOR
// set at reset, a fault handler that halts silently, and the vector table with the STM32F405's
// 82 interrupt lines (RM0090 table 61); the CAN1 ones go to the bxCAN driver, the rest to
// Default_Handler.
#include <cstdint>

#include "bxcan.hpp"
#include "cortex_m/runtime.hpp"
#include "registers.hpp"

extern "C" {
void CAN1_TX_IRQHandler();
void CAN1_RX0_IRQHandler();
void CAN1_SCE_IRQHandler();

// The exception number of the fault that stopped the firmware, for a debugger to read.
volatile std::uint32_t g_fault_exception = 0;
}

// The boot pins alias flash at 0; say explicitly where the table is.
extern "C" void pa_board_reset_init() { stm32f4::scb().VTOR = 0x08000000u; }

// main() never returns; if it did, the firmware stops as on a fault (exception number 0).
extern "C" void pa_board_exit(int) { Default_Handler(); }

// A fault stops the firmware here with interrupts off (no CAN traffic goes out, so the HIL
// plant sees the vehicle fall silent); a debugger finds the cause in g_fault_exception.
extern "C" void Default_Handler() {
  std::uint32_t ipsr;
  asm volatile("mrs %0, ipsr" : "=r"(ipsr));
  asm volatile("cpsid i" ::: "memory");
  g_fault_exception = ipsr & 0x1FFu;
  for (;;) asm volatile("wfi");
}

extern "C" void CAN1_TX_IRQHandler() { stm32f405::Can1::on_tx_interrupt(); }
extern "C" void CAN1_RX0_IRQHandler() { stm32f405::Can1::on_rx0_interrupt(); }
extern "C" void CAN1_SCE_IRQHandler() { stm32f405::Can1::on_status_change_error_interrupt(); }

namespace {

constexpr cortex_m::VectorTable<stm32f4::irq::count> make_vector_table() {
  auto t = cortex_m::default_vector_table<stm32f4::irq::count>();
  t.irq(stm32f4::irq::can1_tx) = CAN1_TX_IRQHandler;
  t.irq(stm32f4::irq::can1_rx0) = CAN1_RX0_IRQHandler;
  t.irq(stm32f4::irq::can1_sce) = CAN1_SCE_IRQHandler;
  return t;
}

}  // namespace

extern "C"
    __attribute__((section(".isr_vector"), used)) constinit const cortex_m::VectorTable<stm32f4::irq::count>
        g_vector_table = make_vector_table();

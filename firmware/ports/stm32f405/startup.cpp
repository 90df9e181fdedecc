// The HIL image's vector table: the STM32F405's 82 interrupt lines (RM0090 table 61); the
// CAN1 ones go to the bxCAN driver, the rest to Default_Handler (board_runtime.cpp).
#include <cstdint>

#include "bxcan.hpp"
#include "cortex_m/runtime.hpp"
#include "registers.hpp"

extern "C" {
void CAN1_TX_IRQHandler();
void CAN1_RX0_IRQHandler();
void CAN1_SCE_IRQHandler();
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

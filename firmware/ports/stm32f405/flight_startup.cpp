// The flight image's vector table: SysTick (the 1 ms housekeeping beat), EXTI4 (the IMU's
// data-ready line), SPI1 (its burst read) and the two USARTs; everything else goes to Default_Handler
// (board_runtime.cpp).
#include <cstdint>

#include "cortex_m/runtime.hpp"
#include "flight_io.hpp"
#include "imu_spi.hpp"
#include "registers.hpp"

extern "C" {
void SysTick_Handler();
void EXTI4_IRQHandler();
void SPI1_IRQHandler();
void USART1_IRQHandler();
void USART3_IRQHandler();
}

extern "C" void SysTick_Handler() { stm32f405::flight::on_millisecond(); }
extern "C" void EXTI4_IRQHandler() { stm32f405::Imu::on_data_ready_interrupt(); }
extern "C" void SPI1_IRQHandler() { stm32f405::Imu::on_spi_interrupt(); }
extern "C" void USART1_IRQHandler() { stm32f405::flight::link().on_interrupt(); }
extern "C" void USART3_IRQHandler() { stm32f405::flight::console().on_interrupt(); }

namespace {

constexpr cortex_m::VectorTable<stm32f4::irq::count> make_vector_table() {
  auto t = cortex_m::default_vector_table<stm32f4::irq::count>();
  t.exception(cortex_m::exception::sys_tick) = SysTick_Handler;
  t.irq(stm32f4::irq::exti4) = EXTI4_IRQHandler;
  t.irq(stm32f4::irq::spi1) = SPI1_IRQHandler;
  t.irq(stm32f4::irq::usart1) = USART1_IRQHandler;
  t.irq(stm32f4::irq::usart3) = USART3_IRQHandler;
  return t;
}

}  // namespace

extern "C"
    __attribute__((section(".isr_vector"), used)) constinit const cortex_m::VectorTable<stm32f4::irq::count>
        g_vector_table = make_vector_table();

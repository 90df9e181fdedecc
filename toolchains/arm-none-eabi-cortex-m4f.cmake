# Cortex-M4F (single-precision FPU) with Debian's Arm GNU toolchain (gcc-arm-none-eabi,
# newlib). Used by the cortex-m4 (mps2-an386) and stm32f405 presets, which build Release
# (-O3): the 1 kHz tick's longest path is the figure that matters (at -Os the protocol's
# encoders and small helpers stay out of line and the tick takes some 13 % more instructions),
# and the images stay far inside their 64 KiB flash budget.
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR arm)

set(CMAKE_C_COMPILER arm-none-eabi-gcc)
set(CMAKE_CXX_COMPILER arm-none-eabi-g++)
set(CMAKE_ASM_COMPILER arm-none-eabi-gcc)
set(CMAKE_OBJCOPY arm-none-eabi-objcopy CACHE FILEPATH "")
set(CMAKE_SIZE arm-none-eabi-size CACHE FILEPATH "")
set(CMAKE_NM arm-none-eabi-nm CACHE FILEPATH "")

# Try-compiles cannot link a bare-metal executable without a linker script.
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)

set(PA_MCU_FLAGS "-mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard")
# No heap, no exceptions, no RTTI, no static-init guards or atexit registration. Debug information
# (-g) stays in the ELF: the code is the same without it (the flashed binaries compare equal), and
# gdb and scripts/tick-profile.sh name the inlined steps of a tick with it.
set(CMAKE_C_FLAGS_INIT "${PA_MCU_FLAGS} -g -ffunction-sections -fdata-sections")
set(CMAKE_CXX_FLAGS_INIT
    "${PA_MCU_FLAGS} -g -ffunction-sections -fdata-sections -fno-exceptions -fno-rtti -fno-threadsafe-statics -fno-use-cxa-atexit")
set(CMAKE_ASM_FLAGS_INIT "${PA_MCU_FLAGS}")
set(CMAKE_EXE_LINKER_FLAGS_INIT "${PA_MCU_FLAGS} -nostartfiles -Wl,--gc-sections --specs=nano.specs")

set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)

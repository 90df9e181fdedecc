# Boots an image that never exits on a QEMU board for a fixed time and checks, from QEMU's
# translation log, that it got where it should without taking any exception. For the STM32F405
# image on `netduinoplus2` (QEMU's STM32F405 model, which has no RCC, DWT or bxCAN model) this
# exercises the start-up code, the vector table, the clock and CAN fall-backs when their
# hardware never answers, the construction of the vehicle, and the main loop's sleep.
#
#   cmake -DQEMU=qemu-system-arm -DMACHINE=netduinoplus2 -DELF=<image> -DLOG=<file>
#         -DSECONDS=<run time> -DREACH=<function whose code must be reached, regex>
#         -DREACH_INSTRUCTION=<instruction that must appear in REACH's code, regex>
#         [-DEXECUTED=<regex>;<regex>...] -P RunQemuBoot.cmake
cmake_minimum_required(VERSION 3.25)

include(${CMAKE_CURRENT_LIST_DIR}/RunQemuCommon.cmake)
pa_qemu_require(QEMU MACHINE ELF LOG SECONDS REACH REACH_INSTRUCTION)

file(REMOVE "${LOG}")
pa_run_qemu(${MACHINE} ${SECONDS} status output -d in_asm,int -D "${LOG}")

# The image never exits, so QEMU is expected to be stopped by the timeout; any other end is
# QEMU failing (a bad image, an unknown machine).
if(NOT status MATCHES "timeout")
  message(FATAL_ERROR "qemu: ended by itself (status '${status}') instead of running until stopped:\n${output}")
endif()
if(NOT EXISTS "${LOG}")
  message(FATAL_ERROR "qemu: wrote no log to ${LOG}")
endif()
file(READ "${LOG}" log)

set(problems "")
if(log MATCHES "Taking exception|taking pending[^\n]*exception")
  list(APPEND problems "the image took an exception (a fault): see ${LOG}")
endif()
foreach(function IN LISTS EXECUTED)
  if(NOT log MATCHES "\nIN: ${function}")
    list(APPEND problems "never ran ${function}")
  endif()
endforeach()
# Translation blocks are logged as "IN: <function>" followed by their instructions.
if(NOT log MATCHES "\nIN: ${REACH}\n(0x[0-9a-f]+: [^\n]*\n)*0x[0-9a-f]+: [^\n]*[ \t]${REACH_INSTRUCTION}")
  list(APPEND problems "never reached '${REACH_INSTRUCTION}' in ${REACH}")
endif()

if(problems)
  string(REPLACE ";" "\n  " report "${problems}")
  message(FATAL_ERROR "qemu: FAIL\n  ${report}")
endif()
message("qemu: the image booted, ran what it should and reached '${REACH_INSTRUCTION}' in ${REACH}, with no fault")

# Runs the mps2-an386 image in QEMU and passes only when it printed `selftest: pass` and
# exited with status 0 (semihosting SYS_EXIT_EXTENDED carries the image's exit code).
#
#   cmake -DQEMU=qemu-system-arm -DELF=<image> -DICOUNT_SHIFT=<n> [-DTIMEOUT_S=<s>]
#         [-DTICK_INSTRUCTIONS_BUDGET=<n>] -P RunQemuSelftest.cmake
#
# -icount shift=N makes QEMU's virtual clock advance exactly 2^N ns per instruction; the
# image's instruction counter assumes the same N (it is compiled in) and calibrates itself.
# With a TICK_INSTRUCTIONS_BUDGET the test also fails when the image's `tick_instructions_max`
# (the worst tick, in instructions net of the measurement's own cost) is over it or missing.
cmake_minimum_required(VERSION 3.25)

include(${CMAKE_CURRENT_LIST_DIR}/RunQemuCommon.cmake)
pa_qemu_require(QEMU ELF ICOUNT_SHIFT)
if(NOT DEFINED TIMEOUT_S)
  set(TIMEOUT_S 240)
endif()
set(budget "${TICK_INSTRUCTIONS_BUDGET}")
if(NOT budget STREQUAL "" AND NOT budget MATCHES "^[0-9]+$")
  message(FATAL_ERROR "RunQemuSelftest.cmake: -DTICK_INSTRUCTIONS_BUDGET='${budget}' is not a whole number of instructions")
endif()

pa_run_qemu(mps2-an386 ${TIMEOUT_S} status output
            -semihosting-config enable=on,target=native -icount shift=${ICOUNT_SHIFT})
message("${output}")

if(NOT status STREQUAL "0")
  message(FATAL_ERROR "qemu: the image exited with status '${status}' (0 expected)")
endif()
if(output MATCHES "selftest: fail")
  message(FATAL_ERROR "qemu: the image reported a failure")
endif()
if(NOT output MATCHES "(^|\n)selftest: pass\r?\n")
  message(FATAL_ERROR "qemu: the image did not print 'selftest: pass'")
endif()

# The worst tick's instructions (net of the probe, as the image prints it) against the budget.
if(NOT budget STREQUAL "")
  pa_qemu_printed_number(output tick_instructions_max tick_max)
  # Which tick it was (from 0), for whoever must find the work that made it the worst.
  set(at_tick "")
  if(output MATCHES "(^|\n)tick_instructions_max_at_tick: ([0-9]+)")
    set(at_tick " (tick ${CMAKE_MATCH_2})")
  endif()
  if(tick_max GREATER budget)
    message(FATAL_ERROR "qemu: the worst tick${at_tick} took ${tick_max} instructions, over the budget of ${budget}")
  endif()
  message("qemu: the worst tick${at_tick} took ${tick_max} instructions, within the budget of ${budget}")
endif()
message("qemu: selftest passed")

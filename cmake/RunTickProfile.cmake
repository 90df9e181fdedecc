# Checks scripts/tick-profile.sh against the self-test's own instruction counter: flies the
# self-test image, reads its worst tick (tick_instructions_max, net of the probe, and
# tick_instructions_max_at_tick), profiles that tick with the script and passes when the two
# counts agree within 1 % (they differ by what the probe's subtraction leaves of its calls) and
# the profile names the tick's steps.
#
#   cmake -DQEMU=qemu-system-arm -DELF=<image> -DICOUNT_SHIFT=<n> -DSCRIPT=<tick-profile.sh>
#         -P RunTickProfile.cmake
cmake_minimum_required(VERSION 3.25)

include(${CMAKE_CURRENT_LIST_DIR}/RunQemuCommon.cmake)
pa_qemu_require(QEMU ELF ICOUNT_SHIFT SCRIPT)

pa_run_qemu(mps2-an386 240 status output
            -semihosting-config enable=on,target=native -icount shift=${ICOUNT_SHIFT})
if(NOT status STREQUAL "0")
  message(FATAL_ERROR "tick profile: the self-test image exited with status '${status}':\n${output}")
endif()
pa_qemu_printed_number(output tick_instructions_max counted)
pa_qemu_printed_number(output tick_instructions_max_at_tick tick)

execute_process(COMMAND bash ${SCRIPT} ${ELF} ${tick} ${ICOUNT_SHIFT} TIMEOUT 240
                RESULT_VARIABLE status OUTPUT_VARIABLE profile ERROR_VARIABLE profile)
message("${profile}")
if(NOT status STREQUAL "0")
  message(FATAL_ERROR "tick profile: ${SCRIPT} exited with status '${status}'")
endif()
if(NOT profile MATCHES "tick-profile: tick ${tick} of [^:]+: ([0-9]+) instructions")
  message(FATAL_ERROR "tick profile: no total for tick ${tick} in the profile")
endif()
set(stepped "${CMAKE_MATCH_1}")
# Every tick runs the rate loop and the mixer: a profile that cannot name them read no debug
# information.
foreach(step "fw::RateController::update" "fw::Mixer::mix")
  string(FIND "${profile}" "  ${step}\n" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "tick profile: the profile does not name ${step}")
  endif()
endforeach()

math(EXPR difference "${stepped} - ${counted}")
if(difference LESS 0)
  math(EXPR difference "-${difference}")
endif()
math(EXPR allowed "${counted} / 100")
if(difference GREATER allowed)
  message(FATAL_ERROR "tick profile: tick ${tick} stepped ${stepped} instructions, the counter said ${counted} (more than 1 % apart)")
endif()
message("tick profile: tick ${tick} stepped ${stepped} instructions, the counter said ${counted}")

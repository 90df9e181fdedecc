# Boots the STM32F405 flight image on QEMU's netduinoplus2 for a fixed time with its console
# (USART3, the machine's third serial port) written to a file, and checks what a person would
# see on that console with no IMU fitted: the IMU reported missing (no_response, or a wrong
# identity), the motors held at motor stop with output going out, and the status line coming
# back every second (a fault would stop the firmware with interrupts off).
#
#   cmake -DQEMU=qemu-system-arm -DMACHINE=netduinoplus2 -DELF=<image> -DCONSOLE=<file>
#         -DSECONDS=<run time> -DMOTORS=<dshot|pwm_us> -DSTOP=<its motor-stop value>
#         -P RunQemuFlight.cmake
cmake_minimum_required(VERSION 3.25)

include(${CMAKE_CURRENT_LIST_DIR}/RunQemuCommon.cmake)
pa_qemu_require(QEMU MACHINE ELF CONSOLE SECONDS MOTORS STOP)

file(REMOVE "${CONSOLE}")
# USART1 (the radio link) and USART2 go nowhere; USART3 is the console.
set(command "${QEMU}" -M ${MACHINE} -nographic -monitor none -serial null -serial null
            -serial "file:${CONSOLE}" -kernel "${ELF}")
string(REPLACE ";" " " shown "${command}")
message("qemu: ${shown} (for ${SECONDS} s)")
execute_process(COMMAND ${command} TIMEOUT ${SECONDS} RESULT_VARIABLE status OUTPUT_VARIABLE output
                ERROR_VARIABLE output)
if(NOT status MATCHES "timeout")
  message(FATAL_ERROR "qemu: ended by itself (status '${status}') instead of running until stopped:\n${output}")
endif()
if(NOT EXISTS "${CONSOLE}")
  message(FATAL_ERROR "qemu: wrote no console file ${CONSOLE}")
endif()
file(READ "${CONSOLE}" console)
message("console:\n${console}")
# QEMU is stopped wherever the image is: a last line cut short (" dshot=0,0") is not judged.
string(FIND "${console}" "\n" last_newline REVERSE)
if(last_newline GREATER_EQUAL 0)
  string(SUBSTRING "${console}" 0 ${last_newline} console)
endif()

set(problems "")
string(REGEX MATCHALL "\nflight: [a-z0-9]+ FAULT: motors held stopped t_ms=[0-9]+" periodic "${console}")
list(LENGTH periodic periodic_count)
if(periodic_count LESS 3)
  list(APPEND problems "${periodic_count} periodic status lines in ${SECONDS} s (3 or more expected): the firmware stopped or its beat does not run")
endif()
if(NOT console MATCHES "flight: [a-z0-9]+ boot FAULT: motors held stopped[^\n]* imu=(no_response|wrong_identity)")
  list(APPEND problems "no boot line reporting the missing IMU")
endif()
set(stopped "${STOP},${STOP},${STOP},${STOP}")
if(NOT console MATCHES "\nflight: [a-z0-9]+ FAULT: motors held stopped[^\n]* motors=off ${MOTORS}=${stopped} ${MOTORS}_frames=[1-9]")
  list(APPEND problems "no periodic status line with the motors off, at motor stop (${MOTORS}=${stopped}), output going out")
endif()
string(REGEX MATCHALL " ${MOTORS}=[0-9,]+" outputs "${console}")
foreach(output IN LISTS outputs)
  if(NOT output STREQUAL " ${MOTORS}=${stopped}")
    list(APPEND problems "a motor was commanded:${output}")
  endif()
endforeach()
if(console MATCHES "motors=on")
  list(APPEND problems "the motors were enabled")
endif()
if(problems)
  string(REPLACE ";" "\n  " report "${problems}")
  message(FATAL_ERROR "qemu: FAIL\n  ${report}")
endif()
message("qemu: the flight image found no IMU, reported it and kept the motors stopped")

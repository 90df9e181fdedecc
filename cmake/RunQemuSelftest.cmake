# Runs the mps2-an386 image in QEMU and passes only when it printed `selftest: pass` and
# exited with status 0 (semihosting SYS_EXIT_EXTENDED carries the image's exit code).
#
#   cmake -DQEMU=qemu-system-arm -DELF=<image> -DICOUNT_SHIFT=<n> [-DTIMEOUT_S=<s>] -P RunQemuSelftest.cmake
#
# -icount shift=N makes QEMU's virtual clock advance exactly 2^N ns per instruction; the
# image's instruction counter assumes the same N (it is compiled in) and calibrates itself.
cmake_minimum_required(VERSION 3.25)

if(NOT QEMU OR NOT ELF OR "${ICOUNT_SHIFT}" STREQUAL "")
  message(FATAL_ERROR "usage: cmake -DQEMU=<qemu-system-arm> -DELF=<image> -DICOUNT_SHIFT=<n> -P RunQemuSelftest.cmake")
endif()
if(NOT DEFINED TIMEOUT_S)
  set(TIMEOUT_S 240)
endif()

set(command "${QEMU}" -M mps2-an386 -nographic -monitor none -serial none
            -semihosting-config enable=on,target=native -icount shift=${ICOUNT_SHIFT} -kernel "${ELF}")
string(REPLACE ";" " " shown "${command}")
message("qemu: ${shown}")
execute_process(COMMAND ${command} TIMEOUT ${TIMEOUT_S}
                RESULT_VARIABLE status OUTPUT_VARIABLE output ERROR_VARIABLE output)
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
message("qemu: selftest passed")

# Boots the mps2-an386 processor-in-the-loop image (fw_mps2_an386_pil) in a working directory
# whose pil_vehicle.cfg is missing, then one with the wrong magic, then one whose size field is
# not sizeof(fw::VehicleConfig), and passes only when each run ends with exit status 2 and the
# image's `pil: fail config` line: the image reads its configuration from QEMU's working
# directory over semihosting and refuses to fly on a bad one. (Flying it needs a host peer on
# its serial port; hil/sil runs that.)
#
#   cmake -DQEMU=qemu-system-arm -DELF=<image> -DICOUNT_SHIFT=<n> -DWORK_DIR=<scratch folder>
#         -P RunQemuPilConfig.cmake
cmake_minimum_required(VERSION 3.25)

include(${CMAKE_CURRENT_LIST_DIR}/RunQemuCommon.cmake)
pa_qemu_require(QEMU ELF ICOUNT_SHIFT WORK_DIR)

function(expect_refusal case)
  set(command "${QEMU}" -M mps2-an386 -cpu cortex-m4 -nographic -monitor none -serial none
              -icount shift=${ICOUNT_SHIFT} -semihosting-config enable=on,target=native -kernel "${ELF}")
  string(REPLACE ";" " " shown "${command}")
  message("qemu (${case}, in ${WORK_DIR}): ${shown}")
  execute_process(COMMAND ${command} WORKING_DIRECTORY "${WORK_DIR}" TIMEOUT 30
                  RESULT_VARIABLE status OUTPUT_VARIABLE output ERROR_VARIABLE output)
  message("${output}")
  if(NOT status STREQUAL "2")
    message(FATAL_ERROR "qemu (${case}): the image exited with status '${status}' (2 expected)")
  endif()
  if(NOT output MATCHES "(^|\n)pil: fail config pil_vehicle.cfg ")
    message(FATAL_ERROR "qemu (${case}): the image did not print 'pil: fail config pil_vehicle.cfg ...'")
  endif()
endfunction()

file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")
expect_refusal("no pil_vehicle.cfg")

file(WRITE "${WORK_DIR}/pil_vehicle.cfg" "XAVC\n\n\n\nnot a configuration")
expect_refusal("wrong magic")

file(WRITE "${WORK_DIR}/pil_vehicle.cfg" "PAVC\n\n\n\nnot a configuration")
expect_refusal("wrong size field")
message("qemu: the PIL image refused each bad configuration")

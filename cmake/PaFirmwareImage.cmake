# Turns an executable target into an MCU image: links it with its linker script, writes the
# .bin (and .hex), prints its size and runs the no-heap check after every link (so an image
# that allocates fails to build), and adds the ctests <prefix>_no_heap and <prefix>_size, and
# once per build the tests that prove the no-heap check itself catches a heap user.
#
#   pa_firmware_image(<target> TEST_PREFIX <prefix> LINKER_SCRIPT <file.ld>
#                     RAM_BUDGET_BYTES <n> FLASH_BUDGET_BYTES <n> [HEX])
#
# pa_qemu_test() adds a ctest that runs an image in qemu-system-arm through one of the
# cmake/RunQemu*.cmake scripts.
#
#   pa_qemu_test(<name> SCRIPT <RunQemu....cmake> TIMEOUT <s> ARGS -D<var>=<value>...)
include_guard(GLOBAL)

set(PA_CMAKE_SCRIPTS_DIR ${CMAKE_CURRENT_LIST_DIR})

function(pa_firmware_image target)
  cmake_parse_arguments(ARG "HEX" "TEST_PREFIX;LINKER_SCRIPT;RAM_BUDGET_BYTES;FLASH_BUDGET_BYTES" "" ${ARGN})
  foreach(required TEST_PREFIX LINKER_SCRIPT RAM_BUDGET_BYTES FLASH_BUDGET_BYTES)
    if(NOT ARG_${required})
      message(FATAL_ERROR "pa_firmware_image(${target}): ${required} is required")
    endif()
  endforeach()

  set(elf $<TARGET_FILE:${target}>)
  set(dir $<TARGET_FILE_DIR:${target}>)
  set_target_properties(${target} PROPERTIES SUFFIX .elf LINK_DEPENDS ${ARG_LINKER_SCRIPT})
  target_link_options(${target} PRIVATE -T${ARG_LINKER_SCRIPT} -Wl,-Map=${dir}/${target}.map)

  set(hex_command "")
  if(ARG_HEX)
    set(hex_command COMMAND ${CMAKE_OBJCOPY} -O ihex ${elf} ${dir}/${target}.hex)
  endif()
  add_custom_command(TARGET ${target} POST_BUILD
    COMMAND ${CMAKE_OBJCOPY} -O binary ${elf} ${dir}/${target}.bin
    ${hex_command}
    COMMAND ${CMAKE_SIZE} ${elf}
    COMMAND ${CMAKE_COMMAND} -DSIZE=${CMAKE_SIZE} -DNM=${CMAKE_NM} -DFILE=${elf}
            -DRAM_BUDGET_BYTES=${ARG_RAM_BUDGET_BYTES} -DFLASH_BUDGET_BYTES=${ARG_FLASH_BUDGET_BYTES} -DENFORCE=OFF
            -P ${PA_CMAKE_SCRIPTS_DIR}/SizeCheck.cmake
    COMMAND ${CMAKE_COMMAND} -DNM=${CMAKE_NM} -DFILE=${elf} -P ${PA_CMAKE_SCRIPTS_DIR}/NoHeapCheck.cmake
    COMMENT "${target}: .bin, size and no-heap check"
    VERBATIM)

  add_test(NAME ${ARG_TEST_PREFIX}_no_heap
           COMMAND ${CMAKE_COMMAND} -DNM=${CMAKE_NM} -DFILE=${elf} -P ${PA_CMAKE_SCRIPTS_DIR}/NoHeapCheck.cmake)
  add_test(NAME ${ARG_TEST_PREFIX}_size
           COMMAND ${CMAKE_COMMAND} -DSIZE=${CMAKE_SIZE} -DNM=${CMAKE_NM} -DFILE=${elf}
                   -DRAM_BUDGET_BYTES=${ARG_RAM_BUDGET_BYTES} -DFLASH_BUDGET_BYTES=${ARG_FLASH_BUDGET_BYTES}
                   -P ${PA_CMAKE_SCRIPTS_DIR}/SizeCheck.cmake)
  set_tests_properties(${ARG_TEST_PREFIX}_no_heap ${ARG_TEST_PREFIX}_size PROPERTIES LABELS "mcu")
  pa_no_heap_check_selftest()
endfunction()

# The script gets -DQEMU=<qemu-system-arm> before ARGS. PARSE_ARGV keeps a semicolon inside one
# argument ("-DLIST=a;b") in that argument.
function(pa_qemu_test name)
  cmake_parse_arguments(PARSE_ARGV 1 ARG "" "SCRIPT;TIMEOUT" "ARGS")
  foreach(required SCRIPT TIMEOUT)
    if(NOT ARG_${required})
      message(FATAL_ERROR "pa_qemu_test(${name}): ${required} is required")
    endif()
  endforeach()
  find_program(PA_QEMU_SYSTEM_ARM qemu-system-arm)
  set(qemu ${PA_QEMU_SYSTEM_ARM})
  if(NOT qemu)
    set(qemu qemu-system-arm)  # the test then fails saying so
  endif()
  add_test(NAME ${name}
           COMMAND ${CMAKE_COMMAND} -DQEMU=${qemu} ${ARG_ARGS} -P ${PA_CMAKE_SCRIPTS_DIR}/${ARG_SCRIPT})
  set_tests_properties(${name} PROPERTIES TIMEOUT ${ARG_TIMEOUT} LABELS "mcu")
endfunction()

# A small library (never linked into an image) whose code allocates, throws and uses RTTI;
# the no-heap check must reject it, and must name each kind of offence.
function(pa_no_heap_check_selftest)
  if(TARGET no_heap_check_probe)
    return()
  endif()
  add_library(no_heap_check_probe STATIC ${PA_CMAKE_SCRIPTS_DIR}/no_heap_check/probe.cpp)
  # This one object opts back into what the images forbid, so the check has something to find.
  target_compile_options(no_heap_check_probe PRIVATE -fexceptions -frtti)
  set(lib $<TARGET_FILE:no_heap_check_probe>)

  add_test(NAME no_heap_check_rejects_malloc
           COMMAND ${CMAKE_COMMAND} -DNM=${CMAKE_NM} -DFILE=${lib} -P ${PA_CMAKE_SCRIPTS_DIR}/NoHeapCheck.cmake)
  set_tests_properties(no_heap_check_rejects_malloc PROPERTIES WILL_FAIL TRUE LABELS "mcu")

  add_test(NAME no_heap_check_names_each_offence
           COMMAND ${CMAKE_COMMAND} -DNM=${CMAKE_NM} -DFILE=${lib}
                   -P ${PA_CMAKE_SCRIPTS_DIR}/no_heap_check/ExpectRejection.cmake)
  set_tests_properties(no_heap_check_names_each_offence PROPERTIES LABELS "mcu")
endfunction()

# Prints an MCU image's flash and RAM use and fails when either exceeds its budget.
#
#   cmake -DSIZE=arm-none-eabi-size -DNM=arm-none-eabi-nm -DFILE=<elf>
#         -DRAM_BUDGET_BYTES=<n> -DFLASH_BUDGET_BYTES=<n> [-DENFORCE=OFF] -P SizeCheck.cmake
#
# Flash is text + data (the initial values of .data are stored in flash). RAM is everything
# from __data_start to __stack_top: .data, .bss, the NOLOAD .stack section the linker
# scripts reserve (which `size` counts as bss) and the alignment padding between them. The
# figure is checked to be honest: data + bss must fit inside that span with no more than
# alignment padding left over, so no RAM section lies outside it and the stack is inside it.
# With ENFORCE=OFF the budgets are reported but not enforced (the build step).
cmake_minimum_required(VERSION 3.25)

foreach(var SIZE NM FILE RAM_BUDGET_BYTES FLASH_BUDGET_BYTES)
  if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
    message(FATAL_ERROR "SizeCheck.cmake: -D${var}=... is required")
  endif()
endforeach()
if(NOT DEFINED ENFORCE)
  set(ENFORCE ON)
endif()

execute_process(COMMAND "${SIZE}" -B -d "${FILE}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "size: ${SIZE} ${FILE} failed: ${err}")
endif()
if(NOT out MATCHES "\n *([0-9]+)[ \t]+([0-9]+)[ \t]+([0-9]+)[ \t]+")
  message(FATAL_ERROR "size: cannot read the output of ${SIZE}:\n${out}")
endif()
set(text ${CMAKE_MATCH_1})
set(data ${CMAKE_MATCH_2})
set(bss ${CMAKE_MATCH_3})
math(EXPR flash "${text} + ${data}")
math(EXPR sections "${data} + ${bss}")

execute_process(COMMAND "${NM}" "${FILE}" RESULT_VARIABLE rc OUTPUT_VARIABLE symbols ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "size: ${NM} ${FILE} failed: ${err}")
endif()
foreach(sym __data_start __stack_bottom __stack_top)
  if(NOT symbols MATCHES "(^|\n)([0-9a-fA-F]+) [A-Za-z] ${sym}\n")
    message(FATAL_ERROR "size: ${FILE} has no symbol ${sym} (the linker script must define it)")
  endif()
  math(EXPR ${sym} "0x${CMAKE_MATCH_2}")
endforeach()
math(EXPR stack "${__stack_top} - ${__stack_bottom}")
math(EXPR ram "${__stack_top} - ${__data_start}")
math(EXPR padding "${ram} - ${sections}")

get_filename_component(shown "${FILE}" NAME)
message("size: ${shown}: flash ${flash} bytes (text ${text} + data ${data}), budget ${FLASH_BUDGET_BYTES}")
message("size: ${shown}: RAM ${ram} bytes (data ${data} + bss ${bss} + alignment ${padding}; the stack is ${stack} of it), budget ${RAM_BUDGET_BYTES}")

set(problems "")
if(padding LESS 0 OR padding GREATER 64)
  list(APPEND problems "data + bss is ${sections} bytes but __data_start..__stack_top spans ${ram}: some RAM lies outside the span the figure counts")
endif()
if(ENFORCE)
  if(flash GREATER FLASH_BUDGET_BYTES)
    list(APPEND problems "flash ${flash} bytes exceeds the budget of ${FLASH_BUDGET_BYTES}")
  endif()
  if(ram GREATER RAM_BUDGET_BYTES)
    list(APPEND problems "RAM ${ram} bytes exceeds the budget of ${RAM_BUDGET_BYTES}")
  endif()
endif()
if(problems)
  string(REPLACE ";" "\n  " report "${problems}")
  message(FATAL_ERROR "size: ${shown}: FAIL\n  ${report}")
endif()
if(ENFORCE)
  message("size: ${shown}: ok, within budget")
endif()

# What the cmake/RunQemu*.cmake scripts share; included by them, not run on its own.
include_guard(GLOBAL)

# Fails, naming the script, unless every variable named was given a non-empty value with -D.
function(pa_qemu_require)
  get_filename_component(script "${CMAKE_SCRIPT_MODE_FILE}" NAME)
  foreach(required IN LISTS ARGN)
    if(NOT DEFINED ${required} OR "${${required}}" STREQUAL "")
      message(FATAL_ERROR "${script}: -D${required}=... is required")
    endif()
  endforeach()
endfunction()

# Boots ${ELF} on QEMU's board <machine> with no display, monitor or serial port and the
# further QEMU arguments given, for at most <timeout_s> seconds, after printing the command.
# Sets <status_var> to QEMU's exit status (or execute_process's message when the time ran out)
# and <output_var> to what it wrote on stdout and stderr.
function(pa_run_qemu machine timeout_s status_var output_var)
  set(command "${QEMU}" -M ${machine} -nographic -monitor none -serial none -kernel "${ELF}" ${ARGN})
  string(REPLACE ";" " " shown "${command}")
  message("qemu: ${shown} (for at most ${timeout_s} s)")
  execute_process(COMMAND ${command} TIMEOUT ${timeout_s}
                  RESULT_VARIABLE status OUTPUT_VARIABLE output ERROR_VARIABLE output)
  set(${status_var} "${status}" PARENT_SCOPE)
  set(${output_var} "${output}" PARENT_SCOPE)
endfunction()

# Sets <var> to the whole number the image printed in <output_var> on a line `<name>: N`; fails,
# naming the script, when there is no such line or its value is not a whole number.
function(pa_qemu_printed_number output_var name var)
  get_filename_component(script "${CMAKE_SCRIPT_MODE_FILE}" NAME)
  if(NOT "${${output_var}}" MATCHES "(^|\n)${name}: ([^\r\n]*)")
    message(FATAL_ERROR "${script}: the image printed no '${name}: N' line")
  endif()
  set(value "${CMAKE_MATCH_2}")
  if(NOT value MATCHES "^[0-9]+$")
    message(FATAL_ERROR "${script}: '${name}: ${value}' is not a whole number")
  endif()
  set(${var} "${value}" PARENT_SCOPE)
endfunction()

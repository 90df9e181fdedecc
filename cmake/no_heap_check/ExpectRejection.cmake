# Runs NoHeapCheck.cmake on the probe library (no_heap_check/probe.cpp) and passes only if
# the check failed and named every offence the probe commits.
#
#   cmake -DNM=<nm> -DFILE=<libno_heap_check_probe.a> -P ExpectRejection.cmake
cmake_minimum_required(VERSION 3.25)

execute_process(COMMAND ${CMAKE_COMMAND} -DNM=${NM} -DFILE=${FILE} -P ${CMAKE_CURRENT_LIST_DIR}/../NoHeapCheck.cmake
                RESULT_VARIABLE status OUTPUT_VARIABLE output ERROR_VARIABLE output)
message("${output}")
if(status EQUAL 0)
  message(FATAL_ERROR "expect-rejection: the no-heap check accepted code that allocates")
endif()
set(missing "")
foreach(expected
    "referenced malloc "
    "referenced free "
    "referenced _Znwj "
    "referenced _ZdlPv"
    "referenced __cxa_allocate_exception "
    "referenced __cxa_throw "
    "referenced __cxa_begin_catch "
    "_ZTI"
    "__gxx_personality_v0 ")
  string(FIND "${output}" "${expected}" at)
  if(at EQUAL -1)
    list(APPEND missing "'${expected}'")
  endif()
endforeach()
if(missing)
  message(FATAL_ERROR "expect-rejection: the check did not name: ${missing}")
endif()
message("expect-rejection: the check rejected the probe and named every offence")

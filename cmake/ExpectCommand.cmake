# cmake -DCOMMAND="prog;arg;..." -DEXPECT_EXIT=<code|nonzero> -DEXPECT_OUTPUT=<regex> -P ExpectCommand.cmake
# Runs a command and passes only if its exit code and its output (stdout + stderr) both match.
execute_process(COMMAND ${COMMAND} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 120)
message("${out}${err}")
if(EXPECT_EXIT STREQUAL "nonzero")
  if(code EQUAL 0)
    message(FATAL_ERROR "expected a non-zero exit code, got 0")
  endif()
elseif(NOT code STREQUAL EXPECT_EXIT)
  message(FATAL_ERROR "expected exit code ${EXPECT_EXIT}, got '${code}'")
endif()
if(DEFINED EXPECT_OUTPUT AND NOT "${out}${err}" MATCHES "${EXPECT_OUTPUT}")
  message(FATAL_ERROR "output does not match '${EXPECT_OUTPUT}'")
endif()

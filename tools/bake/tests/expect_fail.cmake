# cmake -DCOMMAND="prog;arg;..." -DREGEX=... -P expect_fail.cmake
# Passes when the command exits non-zero and its stderr matches REGEX.
execute_process(COMMAND ${COMMAND} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("exit ${rc}\nstdout: ${out}\nstderr: ${err}")
if(rc EQUAL 0)
  message(FATAL_ERROR "expected a non-zero exit status")
endif()
if(NOT err MATCHES "${REGEX}")
  message(FATAL_ERROR "stderr does not match: ${REGEX}")
endif()

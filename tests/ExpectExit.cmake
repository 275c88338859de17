# Runs a command and checks its exit code and that its output contains a
# message: cmake -DCMD="prog;arg;..." -DCODE=2 -DMATCH="text" -P ExpectExit.cmake
execute_process(COMMAND ${CMD} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT "${rc}" STREQUAL "${CODE}")
  message(FATAL_ERROR "expected exit code ${CODE}, got ${rc}\nstdout:\n${out}\nstderr:\n${err}")
endif()
string(FIND "${out}${err}" "${MATCH}" at)
if(at EQUAL -1)
  message(FATAL_ERROR "output lacks \"${MATCH}\"\nstdout:\n${out}\nstderr:\n${err}")
endif()
if(DEFINED NOFILE AND EXISTS "${NOFILE}")
  message(FATAL_ERROR "a failed run left ${NOFILE} behind")
endif()

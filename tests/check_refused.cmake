# Runs a driver with bad input and checks that it is refused as a hostile user would want:
# a non-zero exit, one message on stderr matching EXPECT (naming the flag and the value), and no
# output directory OUT left behind. -DEXE=... -DOUT=... "-DARGS=a|b|c" "-DEXPECT=regex"
string(REPLACE "|" ";" args "${ARGS}")
file(REMOVE_RECURSE "${OUT}")
execute_process(COMMAND "${EXE}" ${args} --out "${OUT}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err
                TIMEOUT 120)
if(rc EQUAL 0)
  message(FATAL_ERROR "exit code 0 for bad input; stdout:\n${out}\nstderr:\n${err}")
endif()
if(NOT err MATCHES "${EXPECT}")
  message(FATAL_ERROR "stderr does not match '${EXPECT}':\n${err}")
endif()
if(EXISTS "${OUT}")
  message(FATAL_ERROR "bad input left the output directory ${OUT} behind")
endif()
message(STATUS "refused (exit ${rc}): ${err}")

# Installs the build tree into WORK_DIR/prefix, then configures, builds and runs
# tests/consumer against it (the prism program, the arch, and where the package has CHOLMOD the
# supernodal factor), in WORK_DIR. Fails loudly at the first step that fails.
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
function(run_step)
  execute_process(COMMAND ${ARGN} WORKING_DIRECTORY ${WORK_DIR} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "step failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  message(STATUS "${out}")
endfunction()
run_step(${CMAKE_COMMAND} --install ${BINARY_DIR} --prefix ${WORK_DIR}/prefix)
run_step(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/consumer -B ${WORK_DIR}/build -G ${GENERATOR}
         -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix -DCMAKE_BUILD_TYPE=Release)
run_step(${CMAKE_COMMAND} --build ${WORK_DIR}/build)
run_step(${WORK_DIR}/build/consumer)
run_step(${WORK_DIR}/build/arch)
if(EXISTS ${WORK_DIR}/build/factor)
  run_step(${WORK_DIR}/build/factor)
elseif(EXPECT_CHOLMOD)
  message(FATAL_ERROR "the package was built with TESSERA_CHOLMOD, but find_package(tessera COMPONENTS cholmod) "
                      "did not find tessera::cholmod")
endif()
if(NOT EXISTS ${WORK_DIR}/arch.csv)
  message(FATAL_ERROR "the arch wrote no arch.csv")
endif()

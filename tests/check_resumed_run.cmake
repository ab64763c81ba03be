# A driver's run stopped by a checkpoint and resumed against the same run made in one go: the
# files SAME must be byte-identical, and a resume with other flags must be refused before
# anything is written. CMake script mode:
#   -DEXE=<driver> -DOUT=<dir> -DARGS=<a|b> -DFIRST=<a|b> -DRESUME=<a|b> -DSAME=<f1|f2>
# ARGS are every run's flags; FIRST the first leg's own (a smaller --max-deflection: its end state
# is the checkpoint); RESUME the resumed leg's own (another --threads: the same bits). OTHER is a
# flag pair that makes another run (e.g. --seed|7), refused on resume.
cmake_minimum_required(VERSION 3.22)
foreach(v ARGS FIRST RESUME SAME OTHER)
  string(REPLACE "|" ";" ${v} "${${v}}")
endforeach()
file(REMOVE_RECURSE "${OUT}")
set(ckpt "${OUT}/first/state.ckpt")
function(run_leg name)
  execute_process(COMMAND "${EXE}" ${ARGS} ${ARGN} --out "${OUT}/${name}"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr)
  message("${name}: ${stdout}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${name}: ${EXE} ${ARGS} ${ARGN} exited with ${rc}\n${stderr}")
  endif()
endfunction()
run_leg(straight)
run_leg(first ${FIRST} --checkpoint "${ckpt}")
if(NOT EXISTS "${ckpt}")
  message(FATAL_ERROR "the first leg wrote no checkpoint ${ckpt}")
endif()
run_leg(resumed ${RESUME} --resume "${ckpt}")
set(failed "")
foreach(f IN LISTS SAME)
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files "${OUT}/straight/${f}" "${OUT}/resumed/${f}"
                  RESULT_VARIABLE differ)
  if(NOT differ EQUAL 0)
    list(APPEND failed "${f} differs between the run made in one go and the resumed one")
  endif()
endforeach()
# The first leg stopped early and the resumed one took up the rest of the same steps.
foreach(run straight first resumed)
  file(READ "${OUT}/${run}/summary.json" summary)
  string(JSON steps_${run} GET "${summary}" steps)
  string(JSON resumed_at_${run} GET "${summary}" resumed_at_step)
endforeach()
if(NOT steps_resumed EQUAL steps_straight OR NOT steps_first LESS steps_straight)
  list(APPEND failed "steps: ${steps_straight} in one go, ${steps_first} in the first leg, ${steps_resumed} resumed")
endif()
if(NOT resumed_at_resumed EQUAL steps_first OR NOT resumed_at_straight EQUAL -1)
  list(APPEND failed "resumed_at_step is ${resumed_at_resumed} (expected the first leg's ${steps_first} steps)")
endif()
# Another run's flags: refused, naming both, and nothing written.
execute_process(COMMAND "${EXE}" ${ARGS} ${OTHER} --resume "${ckpt}" --out "${OUT}/other"
                RESULT_VARIABLE rc ERROR_VARIABLE stderr OUTPUT_QUIET)
if(rc EQUAL 0 OR NOT stderr MATCHES "was saved by a run with other flags" OR EXISTS "${OUT}/other")
  list(APPEND failed "a resume with other flags (${OTHER}) was not refused cleanly (exit ${rc}): ${stderr}")
endif()
if(failed)
  string(REPLACE ";" "\n  " failed "${failed}")
  message(FATAL_ERROR "resumed run checks failed:\n  ${failed}")
endif()

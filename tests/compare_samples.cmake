# Runs the sample generator into WORK and compares each file with the committed SAMPLES.
file(REMOVE_RECURSE ${WORK})
execute_process(COMMAND ${GENERATOR} ${WORK} RESULT_VARIABLE rc OUTPUT_QUIET)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "make_sample_leaves failed (${rc})")
endif()
file(GLOB generated RELATIVE ${WORK} ${WORK}/*.json)
list(LENGTH generated count)
if(NOT count EQUAL 3)
  message(FATAL_ERROR "expected 3 sample leaves, generator wrote ${count}")
endif()
foreach(f IN LISTS generated)
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${WORK}/${f} ${SAMPLES}/${f}
                  RESULT_VARIABLE diff)
  if(NOT diff EQUAL 0)
    message(FATAL_ERROR "data/samples/${f} differs from what tools/make_sample_leaves writes; "
                        "regenerate with: build/dev/tools/make_sample_leaves data/samples")
  endif()
endforeach()

# The `grip` command line on bad input: each case must exit non-zero with exactly one line on
# stderr starting "grip: " (and naming what is wrong), and never crash. Then a good run: exit 0,
# the recording and metrics written, the same hash twice.
#   cmake -DGRIP=<path to grip> -DWORK=<scratch dir> -P cli_test.cmake
if(NOT GRIP OR NOT WORK)
  message(FATAL_ERROR "usage: cmake -DGRIP=... -DWORK=... -P cli_test.cmake")
endif()
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
file(WRITE ${WORK}/bad.json "{\"grip_scene\": 1, \"duration\": 1, \"bodies\": [{\"shape\": {\"type\": \"box\", \"halfExtents\": [1, -1, 1]}}]}")
file(WRITE ${WORK}/broken.json "{\"grip_scene\": 1,")
file(WRITE ${WORK}/afile "x")

set(failures 0)
function(expect_error expected)
  execute_process(COMMAND ${GRIP} ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  string(STRIP "${err}" err)
  string(REGEX MATCHALL "\n" newlines "${err}")
  list(LENGTH newlines extra)
  if(rc EQUAL 0 OR NOT rc MATCHES "^[0-9]+$" OR rc GREATER 3 OR NOT extra EQUAL 0
     OR NOT err MATCHES "^grip: " OR NOT err MATCHES "${expected}")
    message(SEND_ERROR "grip ${ARGN}: exit ${rc}, stderr:\n${err}\n(expected one line matching '${expected}')")
  endif()
endfunction()

expect_error("no such scene file or built-in scene" run ${WORK}/missing.json)
expect_error("no such scene file or built-in scene" run no_such_scene)
expect_error("bodies\\[0\\]\\.shape\\.halfExtents\\[1\\]: must be positive" run ${WORK}/bad.json)
expect_error("invalid JSON" run ${WORK}/broken.json)
expect_error("is a directory" run ${WORK})
expect_error("--set world.substeps: expected KEY=VALUE" run grasp_lift --set world.substeps)
expect_error("world.substeps: must be an integer" run grasp_lift --set world.substeps=abc)
expect_error("world.nosuch: unknown field" run grasp_lift --set world.nosuch=1)
expect_error("bodies has 2 elements, no index 7" run grasp_lift --set bodies[7].mass=1)
expect_error("cannot create the output directory" run grasp_lift --out ${WORK}/afile/sub)
expect_error("method" run grasp_lift --method magic)
expect_error("no such built-in scene" scenes --print nope)
expect_error("" nosuchcommand)
expect_error("trials: must be positive \\(got 0\\)" eval placement --trials 0)
expect_error("trials: must be positive" eval placement --trials -2)
expect_error("noise: must be between" eval placement --noise 1)

# A good run, twice: exit 0, files written, the same hash.
foreach(i 1 2)
  execute_process(COMMAND ${GRIP} run push_box --out ${WORK}/out${i} --quiet
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out${i} ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT EXISTS ${WORK}/out${i}/recording.jsonl OR NOT EXISTS ${WORK}/out${i}/metrics.json)
    message(SEND_ERROR "grip run push_box: exit ${rc}: ${err}")
  endif()
endforeach()
if(NOT out1 STREQUAL out2 OR NOT out1 MATCHES "^state hash [0-9a-f]+\n$")
  message(SEND_ERROR "two runs printed '${out1}' and '${out2}'")
endif()
file(REMOVE_RECURSE ${WORK})

# Included by ctest (TEST_INCLUDE_FILES of each test folder, after the discovered Catch2 tests): gives every
# test named in the cost table $SCULPT_CTEST_COSTS its measured seconds as its COST, so `ctest -j` starts the
# longest tests first on a build folder that has run nothing yet (.ci/ctest sets it; .ci/costs/ holds a table
# per CI stage).
# note: ctest's own Testing/Temporary/CTestCostData.txt cannot do this for our tests: ctest splits its lines at
# the first space, so a test whose name has a space never finds its entry (CMake 3.25).
if(DEFINED ENV{SCULPT_CTEST_COSTS} AND EXISTS "$ENV{SCULPT_CTEST_COSTS}")
  file(STRINGS "$ENV{SCULPT_CTEST_COSTS}" sculpt_cost_lines)
  foreach(sculpt_cost_line IN LISTS sculpt_cost_lines)
    if(sculpt_cost_line STREQUAL "---")
      break()
    endif()
    # "NAME RUNS SECONDS", NAME with spaces.
    if(sculpt_cost_line MATCHES "^(.+) [0-9]+ ([0-9.eE+-]+)$")
      set_tests_properties("${CMAKE_MATCH_1}" PROPERTIES COST "${CMAKE_MATCH_2}")
    endif()
  endforeach()
endif()

# One ctest test per GoogleTest suite of a program, not one per test as gtest_discover_tests adds.
# Every process of a torch test program spends 0.8 s before its first test, loading Debian's
# libtorch_cpu (286 libraries) and registering its operators: one process per test cost about 140 s
# of the suite's 2000-2300 s of work (docs/profiling.md, "The test suite's time"). A failing
# suite's output names the failing test; `ctest -R Suite` still picks a suite, and the program's
# --gtest_filter one test.
#
# fscil_add_test_suites(TARGET [PROPERTIES name value ...]): after each build of TARGET, its suites
# are listed (--gtest_list_tests) into a file that ctest includes; PROPERTIES go to every suite.
# Called with -P and PROGRAM, OUTPUT defined, this file is that listing step.

if(CMAKE_SCRIPT_MODE_FILE)
  execute_process(COMMAND ${PROGRAM} --gtest_list_tests OUTPUT_VARIABLE listing RESULT_VARIABLE status
                  TIMEOUT 60)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "${PROGRAM} --gtest_list_tests failed (${status}):\n${listing}")
  endif()
  string(REPLACE "\n" ";" lines "${listing}")
  set(text "")
  foreach(line IN LISTS lines)
    # A suite's line is its name and a dot at column 0 (a typed suite adds "  # TypeParam = ...").
    if(line MATCHES "^([A-Za-z0-9_/]+)\\.")
      set(suite ${CMAKE_MATCH_1})
      string(APPEND text "add_test(\"${suite}.*\" \"${PROGRAM}\" \"--gtest_filter=${suite}.*\")\n"
                         "set_tests_properties(\"${suite}.*\" PROPERTIES \${fscil_suite_properties})\n")
    endif()
  endforeach()
  file(WRITE ${OUTPUT}.new "${text}")
  file(RENAME ${OUTPUT}.new ${OUTPUT})
  return()
endif()

set(fscil_gtest_suites_script ${CMAKE_CURRENT_LIST_FILE})

function(fscil_add_test_suites target)
  cmake_parse_arguments(arg "" "" "PROPERTIES" ${ARGN})
  set(listing ${CMAKE_CURRENT_BINARY_DIR}/${target}_suites.cmake)
  set(include_file ${CMAKE_CURRENT_BINARY_DIR}/${target}_suites_include.cmake)
  add_custom_command(TARGET ${target} POST_BUILD
                     COMMAND ${CMAKE_COMMAND} -DPROGRAM=$<TARGET_FILE:${target}> -DOUTPUT=${listing}
                             -P ${fscil_gtest_suites_script}
                     BYPRODUCTS ${listing} VERBATIM)
  set(properties "")
  foreach(word IN LISTS arg_PROPERTIES)
    string(APPEND properties " [==[${word}]==]")
  endforeach()
  file(WRITE ${include_file}
       "set(fscil_suite_properties${properties})\n"
       "if(EXISTS [==[${listing}]==])\n"
       "  include([==[${listing}]==])\n"
       "else()\n"
       "  add_test(${target}_NOT_BUILT ${target}_NOT_BUILT)\n"
       "endif()\n")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES ${include_file})
endfunction()

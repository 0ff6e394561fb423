# nct_gtests(<executable> <label> <ranks> <source>...): every GoogleTest
# case of the sources (TEST, TEST_F, TEST_P, read from the source text) as
# a ctest of its own, on each rank count of <ranks> ("" for a plain
# executable without MPI):
#   Suite.Name        on 1 rank (or without MPI), labels <label>, suite, np1
#   Suite.Name_np2    on 2 ranks, labels <label>, suite, np2
# where suite is the suite's name in snake_case (ZeroPressure ->
# zero_pressure). A case with ranks writes its run folders under
# test-runs/np<ranks>/ and is a fixture of that name for the tests that
# read them (ranks_agree_*). Cases named in NCT_ONE_RANK run on 1 rank only.
function(nct_gtests executable label ranks)
  foreach(source ${ARGN})
    set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS
                 ${CMAKE_CURRENT_SOURCE_DIR}/${source})
    file(STRINGS ${CMAKE_CURRENT_SOURCE_DIR}/${source} lines
         REGEX "^TEST(_F|_P)?\\([A-Za-z0-9_]+, *[A-Za-z0-9_]+\\)")
    foreach(line ${lines})
      string(REGEX REPLACE "^TEST(_F|_P)?\\(([A-Za-z0-9_]+), *([A-Za-z0-9_]+)\\).*" "\\2"
             suite "${line}")
      string(REGEX REPLACE "^TEST(_F|_P)?\\(([A-Za-z0-9_]+), *([A-Za-z0-9_]+)\\).*" "\\3"
             case "${line}")
      set(name ${suite}.${case})
      set(filter ${name})
      if(line MATCHES "^TEST_P")
        set(filter "*/${name}/*") # Instantiation/Suite.Name/parameter
      endif()
      string(REGEX REPLACE "([a-z0-9])([A-Z])" "\\1_\\2" suite_label "${suite}")
      string(TOLOWER "${suite_label}" suite_label)
      if(NOT ranks)
        add_test(NAME ${name} COMMAND ${executable} --gtest_filter=${filter})
        set_tests_properties(${name} PROPERTIES LABELS "${label};${suite_label}")
        continue()
      endif()
      foreach(n ${ranks})
        if(n GREATER 1 AND name IN_LIST NCT_ONE_RANK)
          continue()
        endif()
        set(test ${name})
        set(launcher "")
        if(n GREATER 1)
          set(test ${name}_np${n})
          set(launcher ${MPIEXEC_BIN} -n ${n} --allow-run-as-root --oversubscribe)
        endif()
        add_test(NAME ${test}
                 COMMAND ${launcher} $<TARGET_FILE:${executable}> --gtest_filter=${filter})
        set_tests_properties(${test} PROPERTIES
                             LABELS "${label};${suite_label};np${n}" PROCESSORS ${n}
                             ENVIRONMENT "NCT_TEST_OUT=${RUNS}/np${n}"
                             FIXTURES_SETUP ${test})
      endforeach()
    endforeach()
  endforeach()
endfunction()

# Fails unless every test CTest knows in a build carries exactly one of the labels unit (in
# process) and e2e (runs the octrace binary), so `ctest -L unit` and `ctest -L e2e` split the
# suite in two (tests/CMakeLists.txt). Registered as the test test_labels.
# Usage: cmake -DCTEST=ctest -DDIR=build -P tests/check_labels.cmake
# (several -L options must all match, CMake 3.21 on; test names may hold list-breaking brackets,
# so tests are counted from ctest's total and listed as its text)

# How many tests `ctest -N` lists with the given filter options, and their lines.
function(count_tests out_n out_lines)
  execute_process(COMMAND ${CTEST} --test-dir ${DIR} -N ${ARGN}
                  OUTPUT_VARIABLE text RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0 OR NOT text MATCHES "Total Tests: ([0-9]+)")
    message(FATAL_ERROR "check_labels: ctest -N ${ARGN} failed (${rc}):\n${text}")
  endif()
  set(${out_n} ${CMAKE_MATCH_1} PARENT_SCOPE)
  string(REGEX REPLACE "Total Tests:[^\n]*" "" text "${text}")
  string(REGEX REPLACE "^[^\n]*\n" "" text "${text}")  # "Test project <dir>"
  set(${out_lines} "${text}" PARENT_SCOPE)
endfunction()

count_tests(n_all lines)
count_tests(n_unit lines -L "^unit$")
count_tests(n_e2e lines -L "^e2e$")
count_tests(n_neither neither -LE "^(unit|e2e)$")
count_tests(n_both both -L "^unit$" -L "^e2e$")
math(EXPR sum "${n_unit} + ${n_e2e}")
if(NOT n_neither EQUAL 0 OR NOT n_both EQUAL 0 OR NOT sum EQUAL n_all OR n_unit EQUAL 0
   OR n_e2e EQUAL 0)
  message(FATAL_ERROR
    "check_labels: ${n_all} tests, ${n_unit} labelled unit, ${n_e2e} e2e; each must carry "
    "exactly one of the two (tests/CMakeLists.txt).\nNeither (${n_neither}):${neither}\n"
    "Both (${n_both}):${both}")
endif()
message(STATUS "check_labels: ${n_all} tests: ${n_unit} unit, ${n_e2e} e2e")

# SPDX-License-Identifier: GPL-3.0-or-later
# ctest_safe_names.cmake -- a test name with ';' is split by catch_discover_tests into a name that
# matches no test case, and CTest then "passes" a test that never ran (eight did, one of them with
# a stale expectation). Fails when any TEST_CASE name contains ';'.
file(GLOB sources "${SOURCE_DIR}/tests/*.cpp")
set(bad "")
foreach(source IN LISTS sources)
  file(STRINGS "${source}" lines REGEX "TEST_CASE\\(\"[^\"]*;")
  foreach(line IN LISTS lines)
    string(APPEND bad "\n  ${source}: ${line}")
  endforeach()
endforeach()
if(bad)
  message(FATAL_ERROR "test names with ';' never run under CTest:${bad}")
endif()

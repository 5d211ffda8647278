# SPDX-License-Identifier: GPL-3.0-or-later
# Installs the build tree into a scratch prefix, then configures, builds and runs a downstream
# project that uses find_package(impactcert): impactcert::float_law, and impactcert::impactcert
# (the library) unless CONSUMER_LIBRARY is OFF.
set(prefix "${BUILD_DIR}/package-test/prefix")
set(consumer "${BUILD_DIR}/package-test/consumer")
file(REMOVE_RECURSE "${BUILD_DIR}/package-test")
foreach(step
    "${CMAKE_COMMAND};--install;${BUILD_DIR};--prefix;${prefix}"
    "${CMAKE_COMMAND};-S;${SOURCE_DIR}/tests/package_consumer;-B;${consumer};-DCMAKE_PREFIX_PATH=${prefix};-DCONSUMER_LIBRARY=${CONSUMER_LIBRARY}"
    "${CMAKE_COMMAND};--build;${consumer}"
    "${consumer}/consumer")
  execute_process(COMMAND ${step} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "step failed (${rc}): ${step}\n${out}\n${err}")
  endif()
endforeach()
if(CONSUMER_LIBRARY)
  execute_process(COMMAND "${consumer}/library_consumer" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT out MATCHES "sequential-3-balls, [0-9]+ pieces, proved; fuzz: violations")
    message(FATAL_ERROR "library_consumer (${rc}): ${out}${err}")
  endif()
  message(STATUS "${out}")
endif()
message(STATUS "find_package(impactcert) works from an installed prefix")

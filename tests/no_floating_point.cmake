# SPDX-License-Identifier: GPL-3.0-or-later
# Fails when a source file of the exact core mentions a floating-point type or conversion, or when
# a file it should check is missing (a moved file must be named here again, not skipped).
# Display-only timing lives in prover/verdict_output.cpp and uses integer microseconds.
set(exact_sources
  exact/rational.hpp exact/rational.cpp exact/matrix.hpp exact/matrix.cpp model/law.hpp
  model/law.cpp base/json.hpp base/json.cpp model/law_json.hpp model/law_json.cpp
  model/paper_law.hpp model/paper_law.cpp exact/copositivity.hpp exact/copositivity.cpp
  exact/pair_kernel.hpp exact/pair_kernel.cpp exact/int_kernel.hpp exact/int_kernel.cpp
  model/cradle.hpp model/cradle.cpp prover/fan.hpp prover/fan.cpp prover/obligations.hpp
  prover/verdict_output.hpp prover/verdict_output.cpp prover/certificate.hpp prover/certificate.cpp
  prover/smt.hpp prover/smt.cpp derive/derive.hpp derive/derive.cpp derive/derive_classical.cpp
  derive/derive_regions.hpp derive/derive_regions.cpp derive/derive_planar.hpp
  derive/derive_planar.cpp derive/derive_order.cpp derive/derive_friction.cpp
  exact/exact_conditions.hpp exact/exact_conditions.cpp model/system.hpp model/system.cpp
  model/scene.hpp model/scene.cpp model/scene3d.cpp base/json_read.hpp sweep/sweep.hpp sweep/sweep.cpp
  sweep/sweep_point.hpp sweep/sweep_point.cpp sweep/threshold.hpp sweep/threshold.cpp
  base/limits.hpp)
set(files "")
foreach(name IN LISTS exact_sources)
  if(NOT EXISTS "${SOURCE_DIR}/src/${name}")
    message(FATAL_ERROR "no_floating_point.cmake: src/${name} is missing (moved? name it here again)")
  endif()
  list(APPEND files "${SOURCE_DIR}/src/${name}")
endforeach()
# The prover's obligations, one file each, are all on the exact path.
file(GLOB obligation_sources "${SOURCE_DIR}/src/prover/obligations/*.hpp" "${SOURCE_DIR}/src/prover/obligations/*.cpp")
if(NOT obligation_sources)
  message(FATAL_ERROR "no sources under ${SOURCE_DIR}/src/prover/obligations/")
endif()
list(SORT obligation_sources)
list(APPEND files ${obligation_sources})
set(bad "")
foreach(file IN LISTS files)
  file(RELATIVE_PATH name "${SOURCE_DIR}/src" "${file}")
  file(STRINGS "${file}" lines REGEX "(^|[^a-z_])(double|float|long double|strtod|atof|stod|mpq_set_d|mpq_get_d)([^a-z_]|$)")
  foreach(line IN LISTS lines)
    if(NOT line MATCHES "^ *//")
      list(APPEND bad "${name}: ${line}")
    endif()
  endforeach()
endforeach()
if(bad)
  message(FATAL_ERROR "floating point on the exact path:\n${bad}")
endif()
message(STATUS "exact core sources are free of floating point")

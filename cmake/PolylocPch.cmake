# Precompiled headers: build time only, the code is the same with or without them. Only where
# parsing is a large share of a file's compile: the tests (gtest, Eigen, json: a test file 7.7 s
# instead of 10.1 s) and the Python module (pybind11). The kernels' and the CLI's files spend
# their time generating code at -O3 (cmd_eval_nav.cpp 18.7 s with, 19.4 s without; refine.cpp
# 19.3 vs 18.3 s), where a PCH per target costs more than it saves. -DPOLYLOC_PCH=OFF builds
# without (e.g. to check that every file includes what it uses).
option(POLYLOC_PCH "Precompile the heavy third-party headers of each large target" ON)

# polyloc_pch(TARGET HEADER...): HEADER as <name>, C++ sources only (a target may hold C files).
function(polyloc_pch target)
  if(NOT POLYLOC_PCH)
    return()
  endif()
  set(_headers)
  foreach(_h ${ARGN})
    list(APPEND _headers "$<$<COMPILE_LANGUAGE:CXX>:${_h}>")
  endforeach()
  target_precompile_headers(${target} PRIVATE ${_headers})
endfunction()

# Unity builds: the files of a target compiled in batches, one translation unit per batch, so
# that the headers every file includes (CLI11, whose header-only code is parsed in 4 s and
# generated again in each file; gtest; pybind11) are parsed and their inline code generated once
# per batch. Measured on 2 cores: two test files 14.2 s apart, 10.6 s as one batch. The code is
# the same; a file's helpers live in a named namespace of their own, not an anonymous one, so
# that batched files do not clash. -DPOLYLOC_UNITY=OFF compiles file by file (faster when
# editing one file; CI and `make test` build everything once).
option(POLYLOC_UNITY "Compile the CLI, the tests and the Python module in batches (unity build)" ON)

# polyloc_unity(TARGET BATCH): BATCH files per translation unit.
function(polyloc_unity target batch)
  if(POLYLOC_UNITY)
    set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE ${batch})
  endif()
endfunction()

# Precompiled headers: build time only, the code is the same with or without them.
# Half of a typical translation unit's compile time here is parsing the same third-party headers
# (CLI11, gtest, pybind11, Eigen, nlohmann/json: 2-4 s each on one core); each target parses them
# once. -DPOLYLOC_PCH=OFF builds without (e.g. to check that every file includes what it uses).
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

# Debian's per-module OpenCV packages (libopencv-core-dev, -imgproc-dev, -imgcodecs-dev) ship no
# CMake config; only the 190-package libopencv-dev meta package does. Find the three modules we use.
find_path(OpenCVParts_INCLUDE_DIR opencv2/core.hpp PATH_SUFFIXES opencv4)
set(_ocv_libs)
foreach(_m core imgproc imgcodecs)
  find_library(OpenCVParts_${_m}_LIBRARY NAMES opencv_${_m})
  list(APPEND _ocv_libs OpenCVParts_${_m}_LIBRARY)
endforeach()
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(OpenCVParts REQUIRED_VARS OpenCVParts_INCLUDE_DIR ${_ocv_libs})
if(OpenCVParts_FOUND AND NOT TARGET OpenCVParts::OpenCV)
  add_library(OpenCVParts::OpenCV INTERFACE IMPORTED)
  set_target_properties(OpenCVParts::OpenCV PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${OpenCVParts_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${OpenCVParts_core_LIBRARY};${OpenCVParts_imgproc_LIBRARY};${OpenCVParts_imgcodecs_LIBRARY}")
endif()

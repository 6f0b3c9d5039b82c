// A depth sensor_msgs/Image as metres: 32FC1 (metres; NaN, 0 or negative: none) or 16UC1
// (millimetres, REP-118; 0: none), little-endian, rows `step` bytes apart.
#pragma once

#include <polyloc/io/messages.hpp>

#include <string>
#include <vector>

namespace polyloc {

// Fills `metres` (width x height, row-major, NaN where none) and returns "" , or returns what is
// wrong with the image ("16SC1 encoding: depth is 32FC1 (m) or 16UC1 (mm)", "step 10 < 4 x
// width 6", ...) and leaves `metres` unspecified.
std::string depthImageToMetres(const msg::Image& image, std::vector<float>& metres);

}  // namespace polyloc

// A picture written whole or not at all (io/atomic_file.hpp): the old PNG stays until the new one
// is complete. Throws std::runtime_error naming the file when it cannot be written.
#pragma once

#include <opencv2/core.hpp>

#include <string>

namespace polyloc::viz {

void writePng(const cv::Mat& image, const std::string& png_path);

}  // namespace polyloc::viz

#include "viz/png_file.hpp"

#include <polyloc/io/atomic_file.hpp>

#include <opencv2/imgcodecs.hpp>

#include <stdexcept>

namespace polyloc::viz {

void writePng(const cv::Mat& image, const std::string& png_path) {
  AtomicFile f(png_path);
  bool ok = false;
  try {
    ok = cv::imwrite(f.tmp(), image);
  } catch (const cv::Exception& e) {
    throw std::runtime_error("cannot write picture '" + png_path + "': " + e.what());
  }
  if (!ok) throw std::runtime_error("cannot write picture '" + png_path + "'");
  f.commit();
}

}  // namespace polyloc::viz

#include <polyloc/map/grid_morphology.hpp>

#include <opencv2/imgproc.hpp>

#include <stdexcept>
#include <string>

namespace polyloc {
namespace {

// The occupied cells as a binary image, the operation on it, and back: cells it adds become
// occupied, the others keep their value.
template <class Op>
OccupancyGrid onOccupied(const OccupancyGrid& g, Op op) {
  if (g.cells.size() != g.width * g.height) throw std::invalid_argument("grid morphology: inconsistent grid");
  OccupancyGrid out = g;
  if (g.cells.empty()) return out;
  cv::Mat occ(int(g.height), int(g.width), CV_8U);
  for (size_t i = 0; i < g.cells.size(); ++i) occ.data[i] = g.cells[i] == OccupancyGrid::kOccupied ? 255 : 0;
  cv::Mat res;
  op(occ, res);
  for (size_t i = 0; i < g.cells.size(); ++i)
    if (res.data[i]) out.cells[i] = OccupancyGrid::kOccupied;
  return out;
}

}  // namespace

OccupancyGrid closeOccupied(const OccupancyGrid& grid, int kernel) {
  if (kernel < 1 || kernel % 2 == 0)
    throw std::invalid_argument("grid closing: kernel must be odd and >= 1, got " + std::to_string(kernel));
  const cv::Mat k = cv::getStructuringElement(cv::MORPH_RECT, {kernel, kernel});
  // Outside the grid counts as empty, so the border does not grow walls.
  return onOccupied(grid, [&](const cv::Mat& in, cv::Mat& out) {
    cv::morphologyEx(in, out, cv::MORPH_CLOSE, k, {-1, -1}, 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  });
}

OccupancyGrid dilateOccupied(const OccupancyGrid& grid, int cells) {
  if (cells < 0) throw std::invalid_argument("grid dilation: cells must be >= 0, got " + std::to_string(cells));
  if (cells == 0) return grid;
  const cv::Mat k = cv::getStructuringElement(cv::MORPH_RECT, {2 * cells + 1, 2 * cells + 1});
  return onOccupied(grid, [&](const cv::Mat& in, cv::Mat& out) {
    cv::dilate(in, out, k, {-1, -1}, 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  });
}

}  // namespace polyloc

#include <polynav/nav_grid.hpp>

#include <opencv2/imgproc.hpp>

#include <climits>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

namespace polynav {

namespace {

[[noreturn]] void bad(const std::string& what) { throw std::invalid_argument("NavGrid: " + what); }

}  // namespace

std::optional<size_t> NavGrid::cellAt(const Eigen::Vector2d& p) const {
  const double fx = (p.x() - origin_x) / resolution, fy = (p.y() - origin_y) / resolution;
  // The negated comparisons also reject NaN.
  if (!(fx >= 0 && fx < double(width) && fy >= 0 && fy < double(height))) return std::nullopt;
  const size_t ix = std::min(size_t(fx), width - 1), iy = std::min(size_t(fy), height - 1);
  return index(ix, iy);
}

Eigen::Vector2d NavGrid::centre(size_t ix, size_t iy) const {
  return {origin_x + (double(ix) + 0.5) * resolution, origin_y + (double(iy) + 0.5) * resolution};
}

void NavGrid::validate() const {
  std::ostringstream s;
  if (!(resolution > 0) || !std::isfinite(resolution)) s << "resolution must be > 0 and finite, got " << resolution;
  else if (!std::isfinite(origin_x)) s << "origin_x must be finite, got " << origin_x;
  else if (!std::isfinite(origin_y)) s << "origin_y must be finite, got " << origin_y;
  else if (height != 0 && width > std::numeric_limits<size_t>::max() / height)
    s << "width * height overflows: width " << width << ", height " << height;
  else if (occupied.size() != size())
    s << "occupied has " << occupied.size() << " cells, width * height is " << size();
  else if (!door.empty() && door.size() != size())
    s << "door has " << door.size() << " cells, width * height is " << size() << " (or leave it empty)";
  if (!s.str().empty()) bad(s.str());
}

namespace {

// Distances in cells (exact for integer offsets: the transform's precise mask).
std::vector<float> distanceInCells(const NavGrid& g) {
  g.validate();
  if (g.width > size_t(INT_MAX) || g.height > size_t(INT_MAX))
    bad("width and height must fit an int for the distance transform, got " + std::to_string(g.width) + " x " +
        std::to_string(g.height));
  bool any = false;
  for (uint8_t o : g.occupied) any = any || o;
  if (!any) return std::vector<float>(g.size(), std::numeric_limits<float>::infinity());
  // Rows of the image are the grid's rows: the distances do not care which way up.
  cv::Mat free_mask(int(g.height), int(g.width), CV_8U);
  for (size_t iy = 0; iy < g.height; ++iy) {
    uint8_t* row = free_mask.ptr<uint8_t>(int(iy));
    for (size_t ix = 0; ix < g.width; ++ix) row[ix] = g.occupied[g.index(ix, iy)] ? 0 : 255;
  }
  cv::Mat dist;
  cv::distanceTransform(free_mask, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
  std::vector<float> out(g.size());
  for (size_t iy = 0; iy < g.height; ++iy) {
    const float* row = dist.ptr<float>(int(iy));
    for (size_t ix = 0; ix < g.width; ++ix) out[g.index(ix, iy)] = row[ix];
  }
  return out;
}

}  // namespace

std::vector<float> obstacleDistance(const NavGrid& g) {
  std::vector<float> d = distanceInCells(g);
  for (float& v : d) v *= float(g.resolution);
  return d;
}

NavGrid inflate(const NavGrid& g, double radius) {
  if (!std::isfinite(radius) || radius < 0) {
    std::ostringstream s;
    s << "inflate radius must be finite and >= 0, got " << radius;
    bad(s.str());
  }
  const std::vector<float> dist = distanceInCells(g);
  NavGrid out = g;
  const double r_cells = radius / g.resolution;
  for (size_t i = 0; i < g.size(); ++i)
    if (double(dist[i]) < r_cells) out.occupied[i] = 1;
  return out;
}

}  // namespace polynav

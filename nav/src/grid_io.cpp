#include <polynav/grid_io.hpp>

#include <opencv2/imgcodecs.hpp>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <set>
#include <string>

namespace polynav {

namespace {

[[noreturn]] void fail(const std::string& file, const std::string& what) { throw GridIoError(file + ": " + what); }

cv::Mat readGray(const std::string& file, const std::string& from) {
  if (!std::filesystem::is_regular_file(file)) fail(from, "image '" + file + "' does not exist");
  cv::Mat m = cv::imread(file, cv::IMREAD_GRAYSCALE);
  if (m.empty()) fail(from, "image '" + file + "' could not be decoded");
  return m;
}

}  // namespace

LoadedGrid loadNavGrid(const std::string& yaml_path) {
  if (!std::filesystem::is_regular_file(yaml_path)) fail(yaml_path, "no such file");
  YAML::Node y;
  try {
    y = YAML::LoadFile(yaml_path);
  } catch (const YAML::Exception& e) {
    fail(yaml_path, e.what());
  }
  if (!y.IsMap()) fail(yaml_path, "expected a mapping (image, resolution, origin, ...)");
  // yaml-cpp keeps one of two equal keys silently: a repeated key is an error, as in polyloc's configs.
  std::set<std::string> keys;
  for (auto it = y.begin(); it != y.end(); ++it)
    if (it->first.IsScalar() && !keys.insert(it->first.Scalar()).second)
      fail(yaml_path, "line " + std::to_string(it->first.Mark().line + 1) + ": key '" + it->first.Scalar() + "' given twice");
  auto need = [&](const char* key) {
    if (!y[key]) fail(yaml_path, std::string("missing key '") + key + "'");
    return y[key];
  };
  LoadedGrid out;
  NavGrid& g = out.grid;
  double negate = 0, free_thresh = 0.196;
  std::vector<double> origin;
  std::string image;
  try {
    image = need("image").as<std::string>();
    g.resolution = need("resolution").as<double>();
    origin = need("origin").as<std::vector<double>>();
    if (y["negate"]) negate = y["negate"].as<double>();
    if (y["free_thresh"]) free_thresh = y["free_thresh"].as<double>();
  } catch (const YAML::Exception& e) {
    fail(yaml_path, std::string("a key has the wrong type: ") + e.what());
  }
  if (!(g.resolution > 0) || !std::isfinite(g.resolution)) fail(yaml_path, "resolution must be > 0");
  if (origin.size() != 3) fail(yaml_path, "origin must be [x, y, yaw]");
  if (origin[2] != 0) fail(yaml_path, "origin yaw " + std::to_string(origin[2]) + ": rotated grids are not supported");
  g.origin_x = origin[0], g.origin_y = origin[1];
  const std::filesystem::path dir = std::filesystem::path(yaml_path).parent_path();
  const cv::Mat img = readGray((dir / image).string(), yaml_path);
  g.width = size_t(img.cols), g.height = size_t(img.rows);
  g.occupied.assign(g.size(), 0);
  // Image row 0 is the top (largest y); cell row 0 the bottom. Occupied or unknown: not free.
  for (size_t iy = 0; iy < g.height; ++iy)
    for (size_t ix = 0; ix < g.width; ++ix) {
      const double v = img.at<uint8_t>(int(g.height - 1 - iy), int(ix));
      const double p = negate != 0 ? v / 255.0 : (255.0 - v) / 255.0;
      g.occupied[g.index(ix, iy)] = p >= free_thresh ? 1 : 0;  // occupied and unknown alike: never driven into
    }
  const std::filesystem::path danger = dir / (std::filesystem::path(yaml_path).stem().string() + ".danger.pgm");
  if (std::filesystem::is_regular_file(danger)) {
    const cv::Mat d = readGray(danger.string(), yaml_path);
    if (size_t(d.cols) != g.width || size_t(d.rows) != g.height)
      fail(danger.string(), "danger mask is " + std::to_string(d.cols) + "x" + std::to_string(d.rows) + ", the grid " +
                                std::to_string(g.width) + "x" + std::to_string(g.height));
    out.danger.assign(g.size(), 0);
    for (size_t iy = 0; iy < g.height; ++iy)
      for (size_t ix = 0; ix < g.width; ++ix) out.danger[g.index(ix, iy)] = d.at<uint8_t>(int(g.height - 1 - iy), int(ix)) < 128;
  }
  g.validate();
  return out;
}

}  // namespace polynav

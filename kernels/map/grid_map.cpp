#include <polyloc/map/grid_map.hpp>

#include <polyloc/config/yaml.hpp>
#include <polyloc/io/atomic_file.hpp>

#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace polyloc {

namespace fs = std::filesystem;

OccupancyGrid loadGridMap(const std::string& yaml_path) {
  if (!fs::is_regular_file(yaml_path)) throw GridMapError(yaml_path + ": no such file");
  OccupancyGrid g;
  std::string image;
  double occ = 0, free = 0;
  bool negate = false;
  try {
    ConfigMap m = ConfigMap::load(yaml_path);
    image = m.getPath("image", "");
    if (image.empty()) m.value("image");  // throws: the key is required
    const ConfigValue res = m.value("resolution");
    g.resolution = res.asDouble();
    if (!(g.resolution > 0)) res.fail("must be > 0");
    const std::vector<double> o = m.value("origin").asDoubles(3);
    g.origin_x = o[0], g.origin_y = o[1], g.origin_yaw = o[2];
    occ = m.value("occupied_thresh").asDouble();
    free = m.value("free_thresh").asDouble();
    if (occ < 0 || occ > 1) m.value("occupied_thresh").fail("must be in [0, 1]");
    if (free < 0 || free > 1) m.value("free_thresh").fail("must be in [0, 1]");
    if (free >= occ) m.value("free_thresh").fail("must be below occupied_thresh");
    const ConfigValue neg = m.value("negate");
    const int64_t n = neg.asInt();
    if (n != 0 && n != 1) neg.fail("must be 0 or 1");
    negate = n == 1;
    // map_server's other modes (scale, raw) keep grey levels; our grids are trinary.
    m.getChoice("mode", "trinary", {"trinary"});
    m.finish();
  } catch (const ConfigError& e) {
    throw GridMapError(e.what());
  }
  if (!fs::is_regular_file(image))
    throw GridMapError(yaml_path + ": image: no such file '" + image + "'");
  const cv::Mat img = cv::imread(image, cv::IMREAD_GRAYSCALE);
  if (img.empty() || img.depth() != CV_8U)
    throw GridMapError(image + ": cannot decode the image (named by " + yaml_path + ": image)");
  g.resize(size_t(img.cols), size_t(img.rows), OccupancyGrid::kUnknown);
  for (int r = 0; r < img.rows; ++r)
    for (int c = 0; c < img.cols; ++c) {
      const double v = img.at<uint8_t>(r, c);
      const double p = negate ? v / 255.0 : (255.0 - v) / 255.0;
      g.at(size_t(c), size_t(img.rows - 1 - r)) = p > occ    ? OccupancyGrid::kOccupied
                                                  : p < free ? OccupancyGrid::kFree
                                                             : OccupancyGrid::kUnknown;
    }
  return g;
}

void saveGridMap(const OccupancyGrid& g, const std::string& yaml_path, const GridSaveOptions& o) {
  if (g.cells.size() != g.width * g.height) throw GridMapError(yaml_path + ": grid has a wrong cell count");
  const fs::path yp(yaml_path);
  const fs::path pgm = fs::path(yaml_path).replace_extension(".pgm");
  AtomicFile pgm_file(pgm.string()), yaml_file(yaml_path);  // both replaced only when both are whole
  {
    std::ofstream f(pgm_file.tmp(), std::ios::binary);
    f << "P5\n" << g.width << ' ' << g.height << "\n255\n";
    std::vector<char> row(g.width);
    for (size_t r = 0; r < g.height; ++r) {
      const size_t y = g.height - 1 - r;  // image row 0 is the top
      for (size_t x = 0; x < g.width; ++x) {
        const int8_t v = g.at(x, y);
        row[x] = char(v == OccupancyGrid::kOccupied ? 0 : v == OccupancyGrid::kFree ? 254 : 205);
      }
      f.write(row.data(), std::streamsize(row.size()));
    }
    if (!f) throw GridMapError(pgm.string() + ": cannot write");
  }
  std::ofstream y(yaml_file.tmp());
  y.precision(17);
  y << "image: " << pgm.filename().string() << "\nresolution: " << g.resolution << "\norigin: ["
    << g.origin_x << ", " << g.origin_y << ", " << g.origin_yaw << "]\nnegate: 0\noccupied_thresh: "
    << o.occupied_thresh << "\nfree_thresh: " << o.free_thresh << "\n";
  y.close();
  if (!y) throw GridMapError(yaml_path + ": cannot write");
  pgm_file.commit();
  yaml_file.commit();
}

}  // namespace polyloc

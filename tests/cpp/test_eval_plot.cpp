// The localisation plot: a PNG with paths, clouds and legend, also when the estimate wanders off
// the map (the canvas grows) or a path is empty; a bad path is an error naming the file.
#include "viz/localize_plot.hpp"

#include "fixtures.hpp"
#include "temp_dir.hpp"

#include <gtest/gtest.h>

#include <filesystem>

namespace polyloc::t_eval_plot {  // the file's own: the suite is compiled in batches (unity build)
namespace {

TEST(EvalPlot, DrawsPathsCloudsAndLegend) {
  test::TempDir dir;
  const Mesh room = test::boxRoom(2.f, 1.5f, 3.f, 0.2f);
  viz::LocalizePlotData d;
  for (int i = 0; i <= 20; ++i) {
    d.truth_path.emplace_back(-1.5f + 0.15f * i, 0.f);
    d.estimate_path.emplace_back(-1.5f + 0.15f * i, 0.02f);
  }
  d.estimate_path.emplace_back(9.f, 7.f);  // a lost filter, off the map
  for (int c = 0; c < 4; ++c) {
    viz::LocalizePlotData::Cloud cloud{c * 2.0, uint64_t(c * 10 + 1), Pose::planar(-1.5 + c, 0, 0), {}};
    for (int k = 0; k < 50; ++k) cloud.particles.emplace_back(-1.5f + c + 0.01f * k, 0.005f * k);
    d.clouds.push_back(cloud);
  }
  d.title = "test";
  d.legend = "ATE 0.010 m\nconverged after 0.0 s";
  const std::string png = dir.file("loc.png");
  viz::drawLocalization(room, d, png);
  EXPECT_GT(std::filesystem::file_size(png), 1000u);

  viz::drawLocalization(room, viz::LocalizePlotData{}, dir.file("empty.png"));  // nothing to draw
  EXPECT_TRUE(std::filesystem::exists(dir.file("empty.png")));
  try {
    viz::drawLocalization(room, d, "/nonexistent-dir/loc.png");
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-dir/loc.png"), std::string::npos);
  }
}

}  // namespace
}  // namespace polyloc

// A grid of error-over-time strips (PNG), one panel per case of a matrix (polyloc eval carmen's
// robustness matrix: rows map style x decimation, columns odometry). Each panel plots a run's
// planar position error per frame on a log scale (1 mm .. 5 m), the points coloured by the
// status the localiser published (green tracking, orange uncertain, red lost, grey initialising),
// the floor of the map at the same frames as a grey line, and the 0.5 m line a `tracking` frame
// must never cross (dashed red). A panel's title carries its figures.
#pragma once

#include <polyloc/mcl/localizer.hpp>

#include <string>
#include <vector>

namespace polyloc::viz {

struct ErrorStrip {
  std::string title;              // e.g. "ATE 4.1 cm = 1.2x floor"
  std::vector<double> t_s;        // per frame, seconds from the run's start
  std::vector<double> error_m;    // per frame, planar error
  std::vector<MclStatus> status;  // per frame
  std::vector<double> floor_t_s, floor_m;  // the floor's errors (may be empty)
  bool empty = false;             // nothing ran (e.g. no odometry): the panel says so
};

struct ErrorStripGrid {
  std::string title;
  std::vector<std::string> row_labels, column_labels;
  std::vector<ErrorStrip> strips;  // row-major, rows x columns
  double limit_m = 0.5;            // the dashed line
};

// Throws std::invalid_argument when strips.size() != rows x columns, std::runtime_error naming
// the file when it cannot be written.
void drawErrorStrips(const ErrorStripGrid& grid, const std::string& png_path);

}  // namespace polyloc::viz

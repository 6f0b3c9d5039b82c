// polyloc map navgrid: the polygon map's free space for a robot of a given height, as a ROS
// map_server grid (YAML + PGM) that a 2D planner reads (kernels/map/height_band.hpp): a cell is
// occupied when anything stands in it between the floor + clearance and the floor + the robot's
// height. Also OUT.danger.yaml + .pgm (map_server's format too: 0 where a danger label lies, 254
// elsewhere; a keepout mask) when the map has danger cells, and a preview OUT.png.
#include "cli/commands.hpp"
#include "cli/output_check.hpp"
#include "cli/parse_number.hpp"

#include <polyloc/configfile/polyloc_config.hpp>
#include <polyloc/map/grid_map.hpp>
#include <polyloc/map/height_band.hpp>
#include <polyloc/map/load.hpp>

#include "viz/topview.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace polyloc::cli {
namespace cmd_map_navgrid_impl {  // named, not anonymous: the CLI is compiled in batches (unity build)

namespace fs = std::filesystem;

struct MapNavgridArgs {
  std::string config, map, out;
  double resolution = HeightBandOptions{}.resolution;
  double clearance = HeightBandOptions{}.clearance, height = HeightBandOptions{}.height;
  bool has_clearance = false, has_height = false, no_preview = false, json = false;
};

// Free white, occupied black, unknown grey (TopView::drawGrid), danger cells red on top.
void drawPreview(const HeightBand& band, const std::string& title, const std::string& png) {
  const OccupancyGrid& g = band.grid;
  const float r = float(g.resolution);
  const Eigen::Vector2f lo(float(g.origin_x), float(g.origin_y));
  const Eigen::AlignedBox2f box(lo, lo + Eigen::Vector2f(r * float(g.width), r * float(g.height)));
  const float extent = std::max(box.sizes().x(), box.sizes().y());
  const float px_per_m = std::clamp(2400.f / std::max(extent, 1e-3f), 1.f, 4.f / r);
  viz::TopView view(box, px_per_m, 60);
  view.drawGrid(g);
  // Runs of danger cells along x as lines one cell thick (their round caps end at the cells' edges).
  const int thick = std::max(1, int(std::lround(r * px_per_m)));
  for (size_t y = 0; y < g.height; ++y)
    for (size_t x = 0; x < g.width;) {
      if (!band.danger[y * g.width + x]) {
        ++x;
        continue;
      }
      size_t x1 = x;
      while (x1 + 1 < g.width && band.danger[y * g.width + x1 + 1]) ++x1;
      const float yc = lo.y() + r * (float(y) + 0.5f);
      view.drawLine({lo.x() + r * (float(x) + 0.5f), yc}, {lo.x() + r * (float(x1) + 0.5f), yc}, viz::kRed, thick);
      x = x1 + 1;
    }
  view.drawLegend(title);
  view.drawScaleBar();
  view.save(png);
}

void run(const MapNavgridArgs& a) {
  const auto t0 = std::chrono::steady_clock::now();
  std::optional<PolylocConfig> cfg;
  if (!a.config.empty()) cfg = loadConfig(a.config, {.map_optional = !a.map.empty()});
  const std::string map_file = a.map.empty() ? cfg->map.file : a.map;
  const std::string base = (fs::path(a.out).parent_path() / fs::path(a.out).stem()).string();
  const std::string pgm = base + ".pgm", danger_yaml = base + ".danger.yaml", danger_pgm = base + ".danger.pgm",
                    png = a.no_preview ? std::string() : base + ".png";
  const std::vector<PathArg> inputs{{"--config", a.config}, {a.map.empty() ? "map (of --config)" : "--map", map_file}};
  checkOutputs(inputs, {{"--out", a.out}});  // first: `--out MAP` is refused as what it is
  const std::string ext = fs::path(a.out).extension().string();
  if (ext != ".yaml" && ext != ".yml")
    throw std::runtime_error(fmt::format("--out {}: expected a map_server YAML (.yaml or .yml); the image goes beside it", a.out));
  checkOutputs(inputs, {{"--out", a.out}, {"--out's image", pgm}, {"--out's danger mask", danger_yaml},
                        {"--out's danger image", danger_pgm}, {"--out's preview", png}});

  HeightBandOptions o;
  o.resolution = a.resolution;
  o.clearance = a.has_clearance ? a.clearance : cfg ? cfg->vrs.floor_clearance : o.clearance;
  o.height = a.has_height ? a.height : cfg->robot.height;  // without --config --robot-height is required
  if (cfg) o.danger_labels = cfg->vrs.danger_labels;
  const Mesh mesh = loadMesh(map_file, cfg ? cfg->map.load : LoadOptions{});
  HeightBandStats st;
  const HeightBand band = heightBandGrid(mesh, o, &st);
  const double compute_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  saveHeightBand(band, a.out);
  nlohmann::json files = {a.out, pgm};
  if (st.cells_danger > 0) files.push_back(danger_yaml), files.push_back(danger_pgm);
  if (!png.empty()) {
    drawPreview(band,
                fmt::format("polyloc map navgrid {}: {} x {} cells at {} m, band {}..{} m above the floor\n"
                            "free white, occupied black, unknown grey, danger red",
                            map_file, band.grid.width, band.grid.height, o.resolution, o.clearance, o.height),
                png);
    files.push_back(png);
  }
  const double total_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  if (a.json) {
    const nlohmann::json j = {{"map", map_file}, {"config", a.config}, {"out", a.out}, {"files", files},
                              {"cells_x", band.grid.width}, {"cells_y", band.grid.height}, {"resolution_m", o.resolution},
                              {"origin", {band.grid.origin_x, band.grid.origin_y, 0.0}},
                              {"size_m", {double(band.grid.width) * o.resolution, double(band.grid.height) * o.resolution}},
                              {"clearance_m", o.clearance}, {"height_m", o.height}, {"floor_labels", o.floor_labels},
                              {"danger_labels", o.danger_labels}, {"cells_occupied", st.cells_occupied},
                              {"cells_free", st.cells_free}, {"cells_unknown", st.cells_unknown},
                              {"cells_danger", st.cells_danger}, {"cells_no_floor", st.cells_no_floor},
                              {"cells_in_solid", st.cells_in_solid}, {"cells_drop", st.cells_drop}, {"open_columns", st.open_columns},
                              {"triangles", st.triangles}, {"floor_triangles", st.floor_triangles},
                              {"danger_triangles", st.danger_triangles}, {"compute_s", compute_s}, {"seconds", total_s}};
    // Paths come from the command line: replace bytes that are not UTF-8 rather than throw.
    fmt::print("{}\n", j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
  } else {
    fmt::print("{}: {} x {} cells at {} m, band {}..{} m above the floor: {} occupied, {} free, {} unknown, {} danger -> {}{}{} "
               "({:.2f} s)\n",
               map_file, band.grid.width, band.grid.height, o.resolution, o.clearance, o.height, st.cells_occupied,
               st.cells_free, st.cells_unknown, st.cells_danger, a.out, st.cells_danger ? ", " + danger_yaml : "",
               png.empty() ? "" : ", " + png, total_s);
  }
  if (st.open_columns > 0)
    fmt::print(stderr, "polyloc map navgrid: warning: {} cells lie under or over open surfaces (the mesh is not closed there); "
               "solids thicker than a cell may show free cells inside (polyloc map info lists open edges)\n",
               st.open_columns);
}

}  // namespace cmd_map_navgrid_impl

void registerMapNavgrid(CLI::App& map) {
  using namespace cmd_map_navgrid_impl;
  auto a = std::make_shared<MapNavgridArgs>();
  CLI::App* c = map.add_subcommand(
      "navgrid", "The map's free space for the robot as a ROS map_server grid (YAML + PGM) for a 2D planner: a "
                 "cell is occupied when anything lies in it between the floor + clearance and the floor + the "
                 "robot's height (table tops, seats, overhangs); no floor (a stairwell) is occupied; danger "
                 "labels go to OUT.danger.yaml/.pgm");
  c->add_option("--config", a->config, "polyloc config: map, robot.height, vrs.floor_clearance, vrs.danger_labels")
      ->check(CLI::ExistingFile);
  c->add_option("--map", a->map, "Map file (OBJ, PLY, STL, glTF, DAE); default: the config's")->check(CLI::ExistingFile);
  c->add_option("--out", a->out, "Output map_server YAML; the image is OUT.pgm beside it")->required();
  // Ranges are the kernel's to check (heightBandGrid): one rule, one message naming the option.
  c->add_option("--resolution", a->resolution, "Cell size (m), in (0, 1]")->capture_default_str();
  c->add_option("--floor-clearance", a->clearance, "Lower is floor (m above the local floor); default vrs.floor_clearance, else 0.06");
  c->add_option("--robot-height", a->height, "Robot height (m above the local floor); default robot.height");
  c->add_flag("--no-preview", a->no_preview, "Do not write the preview OUT.png");
  c->add_flag("--json", a->json, "Print one JSON object on stdout");
  c->callback([a, c] {
    a->has_clearance = c->count("--floor-clearance") > 0;
    a->has_height = c->count("--robot-height") > 0;
    if (a->config.empty() && a->map.empty()) throw CLI::ValidationError("map navgrid", "give --config (and/or --map)");
    if (a->config.empty() && !a->has_height)
      throw CLI::ValidationError("map navgrid", "without --config give the robot's --robot-height (m)");
    run(*a);
  });
}

}  // namespace polyloc::cli

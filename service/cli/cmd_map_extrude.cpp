// polyloc map extrude: a 2D occupancy grid to a 3D polygon map, walls extruded from the occupied
// cells on a floor slab (kernels/map/extrude.hpp), validated before it is saved. The grid is a ROS
// map_server grid (YAML + PGM/PNG) or is built from a CARMEN log with known laser poses
// (kernels/io/recording_grid.hpp).
#include "cli/parse_number.hpp"
#include "cli/output_check.hpp"
#include "cli/commands.hpp"

#include <polyloc/io/recording.hpp>
#include <polyloc/map/extrude.hpp>
#include <polyloc/map/grid_map.hpp>
#include <polyloc/map/load.hpp>
#include <polyloc/io/recording_grid.hpp>
#include <polyloc/map/validate.hpp>

#include "viz/topview.hpp"

#include <fmt/core.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <filesystem>
#include <memory>
#include <stdexcept>

namespace polyloc::cli {
namespace cmd_map_extrude_impl {  // named, not anonymous: the CLI is compiled in batches (unity build)

struct MapExtrudeArgs {
  std::string grid, carmen, out, laser = "all", save_grid, plot, scans = "all";
  ScanMapperConfig mapper;
  ExtrudeOptions options;
  bool no_merge = false, json = false;
};

// The grid of a CARMEN log's scans at their logged laser poses; what was used goes into j.
OccupancyGrid gridFromCarmen(const MapExtrudeArgs& a, nlohmann::json& j, std::vector<std::array<float, 2>>& path) {
  std::vector<std::string> topics;
  for (const char* l : {"front", "rear", "robot"})
    if (a.laser == "all" || a.laser == l) topics.push_back(fmt::format("/{}_laser", l));
  auto reader = openRecording(a.carmen);
  RecordingGridStats st;
  const ScanSelection select = a.scans == "even" ? ScanSelection{2, 0} : a.scans == "odd" ? ScanSelection{2, 1} : ScanSelection{};
  OccupancyGrid grid = gridFromRecording(*reader, topics, a.mapper, &st, select);
  const ReadStats& rs = reader->stats();
  for (size_t i = 0; i < std::min<size_t>(rs.warnings.size(), 5); ++i)
    fmt::print(stderr, "polyloc map extrude: warning: {}\n", rs.warnings[i]);
  if (rs.rejected > 5) fmt::print(stderr, "polyloc map extrude: {} bad lines in all\n", rs.rejected);
  if (st.scans_used == 0)
    throw std::runtime_error(fmt::format("{}: no usable laser scan with a pose on {} ({} skipped, {} bad lines)",
                                         a.carmen, fmt::join(topics, ", "), st.scansSkipped(), rs.rejected));
  j.update({{"carmen", a.carmen}, {"scans_used", st.scans_used}, {"scans_skipped", st.scansSkipped()},
            {"skipped_reasons", st.skipped}, {"rejected_lines", rs.rejected}});
  if (!a.save_grid.empty()) {
    if (auto dir = std::filesystem::path(a.save_grid).parent_path(); !dir.empty()) std::filesystem::create_directories(dir);
    saveGridMap(grid, a.save_grid, {a.mapper.occupied_thresh, a.mapper.free_thresh});
    j["saved_grid"] = a.save_grid;
  }
  path = std::move(st.laser_path);
  return grid;
}

// The grid's cells, the extruded walls sliced at half their height (red), and for a CARMEN log
// the lasers' path (blue): what came in, what went out, and from where it was seen.
void drawExtrusion(const OccupancyGrid& grid, const Mesh& mesh, const std::vector<std::array<float, 2>>& path,
                   const std::string& title, const std::string& png) {
  const Eigen::AlignedBox3f b3 = mesh.bounds();
  const Eigen::AlignedBox2f b(b3.min().head<2>(), b3.max().head<2>());
  const float extent = std::max(b.sizes().x(), b.sizes().y());
  viz::TopView view(b, std::clamp(4000.f / std::max(extent, 1.f), 1.f, 40.f));
  view.drawGrid(grid);
  view.drawMeshSlice(mesh, 0.5f * float(b3.max().z()), &viz::kRed, 1);
  for (size_t i = 1; i < path.size(); ++i)
    view.drawLine({path[i - 1][0], path[i - 1][1]}, {path[i][0], path[i][1]}, viz::kBlue, 2);
  view.drawLegend(title);
  view.drawScaleBar();
  view.save(png);
}

void run(const MapExtrudeArgs& a) {
  checkOutputs({{"--grid", a.grid}, {"--carmen", a.carmen}}, {{"--out", a.out}, {"--save-grid", a.save_grid}, {"--plot", a.plot}});
  checkMeshPath(a.out);
  nlohmann::json j;
  std::vector<std::array<float, 2>> path;  // --carmen: laser positions of the scans used
  const OccupancyGrid grid = a.grid.empty() ? gridFromCarmen(a, j, path) : loadGridMap(a.grid);
  const std::string& source = a.grid.empty() ? a.carmen : a.grid;
  ExtrudeOptions o = a.options;
  o.merge = !a.no_merge;
  ExtrudeStats st;
  Mesh mesh = extrudeGrid(grid, o, &st);
  const ValidationReport r = validateMesh(mesh);
  if (!r.closed() || !r.consistentWinding())  // by construction never; a guard for changes
    throw std::runtime_error("extruded map is not closed and consistently wound:\n" + r.summary());
  if (auto dir = std::filesystem::path(a.out).parent_path(); !dir.empty()) std::filesystem::create_directories(dir);
  saveMesh(mesh, a.out);
  if (!a.plot.empty()) {
    drawExtrusion(grid, mesh, path,
                  fmt::format("polyloc map extrude {}\n{} x {} cells at {} m: black occupied, grey unknown; red: "
                              "extruded walls at half height{}", source, grid.width, grid.height, grid.resolution,
                              path.empty() ? "" : "; blue: laser path"), a.plot);
    j["plot"] = a.plot;
  }
  if (!a.grid.empty()) j["grid"] = a.grid;
  j.update({{"out", a.out},
            {"cells_x", grid.width},   {"cells_y", grid.height},
            {"resolution_m", grid.resolution}, {"occupied_cells", st.occupied_cells},
            {"boxes", st.boxes},       {"triangles", mesh.numTriangles()},
            {"wall_height_m", o.height}, {"closed", r.closed()},
            {"consistent_winding", r.consistentWinding()}});
  // Paths come from the command line: replace bytes that are not UTF-8 rather than throw.
  if (a.json) fmt::print("{}\n", j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
  else
    fmt::print("{}: {} x {} cells at {} m, {} occupied -> {} boxes, {} triangles, closed -> {}\n", source,
               grid.width, grid.height, grid.resolution, st.occupied_cells, st.boxes, mesh.numTriangles(), a.out);
}

}  // namespace cmd_map_extrude_impl

void registerMapExtrude(CLI::App& map) {
  using namespace cmd_map_extrude_impl;
  auto a = std::make_shared<MapExtrudeArgs>();
  CLI::App* c = map.add_subcommand(
      "extrude", "Turn a 2D occupancy grid (a ROS map_server YAML + PGM/PNG, or one built from a CARMEN log "
                 "with known laser poses) into a 3D polygon map: walls from occupied cells, runs merged "
                 "into boxes, on a floor slab");
  auto* grid = c->add_option("--grid", a->grid, "map_server YAML (image, resolution, origin, thresholds, negate)")->check(CLI::ExistingFile);
  auto* carmen = c->add_option("--carmen", a->carmen, "CARMEN log (plain or gzip) whose FLASER/RLASER/ROBOTLASER1 laser poses are known (corrected)")->check(CLI::ExistingFile);
  grid->excludes(carmen);
  c->add_option("--resolution", a->mapper.resolution, "--carmen: grid cell size (m)")->capture_default_str()->check(positiveFinite());
  c->add_option("--laser", a->laser, "--carmen: which lasers to map")->capture_default_str()->check(CLI::IsMember({"front", "rear", "robot", "all"}));
  c->add_option("--scans", a->scans, "--carmen: which scans (in file order, per laser): all, or even / odd (the real-log protocol maps the even ones)")
      ->capture_default_str()->check(CLI::IsMember({"all", "even", "odd"}));
  c->add_option("--max-range", a->mapper.max_range, "--carmen: beams at or beyond this (m) only clear free space")->capture_default_str()->check(positiveFinite());
  c->add_option("--save-grid", a->save_grid, "--carmen: also save the built grid as map_server YAML + PGM");
  c->add_option("--out", a->out, "Output map (.obj, .ply, .stl, .gltf, .glb, .dae)")->required();
  c->add_option("--wall-height", a->options.height, "Wall height (m)")->capture_default_str()->check(positiveFinite());
  c->add_option("--floor-thickness", a->options.floor_thickness, "Floor slab under the grid (m; 0 = none)")->capture_default_str()->check(nonNegativeFinite());
  c->add_flag("--unknown-occupied", a->options.unknown_is_occupied, "Unknown cells become walls too");
  // Merging is the default; the flag spells it out, --no-merge makes one box per cell.
  c->add_flag("--resolution-merge", [](int64_t) {}, "Merge runs of cells into boxes (default)");
  c->add_flag("--no-merge", a->no_merge, "One box per occupied cell");
  c->add_option("--plot", a->plot, "PNG: the grid, the extruded walls and (--carmen) the laser path");
  c->add_flag("--json", a->json, "Print one JSON object on stdout");
  c->callback([a, c] {
    if (a->grid.empty() == a->carmen.empty()) throw CLI::ValidationError("map extrude", "give exactly one of --grid and --carmen");
    for (const char* o : {"--resolution", "--laser", "--scans", "--max-range", "--save-grid"})
      if (!a->grid.empty() && c->count(o)) throw CLI::ValidationError(o, "only with --carmen (a --grid brings its own cells)");
    run(*a);
  });
}

}  // namespace polyloc::cli

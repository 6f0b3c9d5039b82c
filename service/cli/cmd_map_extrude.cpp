// polyloc map extrude: a ROS map_server grid (YAML + PGM/PNG) to a 3D polygon map, walls extruded
// from the occupied cells on a floor slab (kernels/map/extrude.hpp), validated before it is saved.
// (Grids built from CARMEN logs with known poses are not supported yet.)
#include "cli/commands.hpp"

#include <polyloc/map/extrude.hpp>
#include <polyloc/map/grid_map.hpp>
#include <polyloc/map/load.hpp>
#include <polyloc/map/validate.hpp>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <memory>

namespace polyloc::cli {
namespace {

struct MapExtrudeArgs {
  std::string grid, out;
  ExtrudeOptions options;
  bool no_merge = false, json = false;
};

void run(const MapExtrudeArgs& a) {
  const OccupancyGrid grid = loadGridMap(a.grid);
  ExtrudeOptions o = a.options;
  o.merge = !a.no_merge;
  ExtrudeStats st;
  Mesh mesh = extrudeGrid(grid, o, &st);
  const ValidationReport r = validateMesh(mesh);
  if (!r.closed() || !r.consistentWinding())  // by construction never; a guard for changes
    throw std::runtime_error("extruded map is not closed and consistently wound:\n" + r.summary());
  if (auto dir = std::filesystem::path(a.out).parent_path(); !dir.empty()) std::filesystem::create_directories(dir);
  saveMesh(mesh, a.out);
  nlohmann::json j{{"grid", a.grid},          {"out", a.out},
                   {"cells_x", grid.width},   {"cells_y", grid.height},
                   {"resolution_m", grid.resolution}, {"occupied_cells", st.occupied_cells},
                   {"boxes", st.boxes},       {"triangles", mesh.numTriangles()},
                   {"wall_height_m", o.height}, {"closed", r.closed()},
                   {"consistent_winding", r.consistentWinding()}};
  if (a.json) fmt::print("{}\n", j.dump());
  else
    fmt::print("{}: {} x {} cells at {} m, {} occupied -> {} boxes, {} triangles, closed -> {}\n", a.grid,
               grid.width, grid.height, grid.resolution, st.occupied_cells, st.boxes, mesh.numTriangles(), a.out);
}

}  // namespace

void registerMapExtrude(CLI::App& map) {
  auto a = std::make_shared<MapExtrudeArgs>();
  CLI::App* c = map.add_subcommand(
      "extrude", "Turn a ROS map_server grid (YAML + PGM/PNG) into a 3D polygon map: walls from "
                 "occupied cells, runs merged into boxes, on a floor slab");
  c->add_option("--grid", a->grid, "map_server YAML (image, resolution, origin, thresholds, negate)")->required()->check(CLI::ExistingFile);
  c->add_option("--out", a->out, "Output map (.obj, .ply, .stl, .gltf, .glb, .dae)")->required();
  c->add_option("--height", a->options.height, "Wall height (m)")->capture_default_str()->check(CLI::PositiveNumber);
  c->add_option("--floor-thickness", a->options.floor_thickness, "Floor slab under the grid (m; 0 = none)")->capture_default_str()->check(CLI::NonNegativeNumber);
  c->add_flag("--unknown-occupied", a->options.unknown_is_occupied, "Unknown cells become walls too");
  // Merging is the default; the flag spells it out, --no-merge makes one box per cell.
  c->add_flag("--resolution-merge", [](int64_t) {}, "Merge runs of cells into boxes (default)");
  c->add_flag("--no-merge", a->no_merge, "One box per occupied cell");
  c->add_flag("--json", a->json, "Print one JSON object on stdout");
  c->callback([a] { run(*a); });
}

}  // namespace polyloc::cli

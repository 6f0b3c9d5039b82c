// polyloc map info FILE: load a polygon map and report what validation finds.
#include "cli/parse_number.hpp"
#include "cli/commands.hpp"

#include <polyloc/map/load.hpp>
#include <polyloc/map/validate.hpp>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <memory>

namespace polyloc::cli {
namespace cmd_map_info_impl {  // named, not anonymous: the CLI is compiled in batches (unity build)

struct MapInfoArgs {
  std::string file;
  double scale = 1.0;
  std::string up_axis = "auto";
  bool json = false;
};

nlohmann::json toJson(const ValidationReport& r) {
  nlohmann::json labels = nlohmann::json::object();
  for (const auto& [name, count] : r.label_counts) labels[name] = count;
  nlohmann::json bounds = nullptr;  // no vertices
  if (!r.bounds.isEmpty()) {
    const Eigen::Vector3f lo = r.bounds.min(), hi = r.bounds.max();
    bounds = {{"min", {lo.x(), lo.y(), lo.z()}}, {"max", {hi.x(), hi.y(), hi.z()}}};
  }
  return {{"triangles", r.triangles},
          {"vertices", r.vertices},
          {"open_edges", r.open_edges},
          {"non_manifold_edges", r.non_manifold_edges},
          {"inconsistent_edges", r.inconsistent_edges},
          {"degenerate_triangles", r.degenerate_triangles},
          {"bounds", bounds},
          {"labels", labels},
          {"closed", r.closed()},
          {"consistent_winding", r.consistentWinding()}};
}

void run(const MapInfoArgs& args) {
  LoadOptions options;
  options.scale = args.scale;
  options.up_axis = parseUpAxis(args.up_axis);
  const Mesh mesh = loadMesh(args.file, options);
  const ValidationReport report = validateMesh(mesh);
  if (args.json) {
    fmt::print("{}\n", toJson(report).dump());
  } else {
    fmt::print("map: {}\n{}", args.file, report.summary());
  }
}

}  // namespace cmd_map_info_impl

void registerMapInfo(CLI::App& map) {
  using namespace cmd_map_info_impl;
  auto args = std::make_shared<MapInfoArgs>();
  CLI::App* cmd = map.add_subcommand(
      "info", "Load a map file (OBJ, PLY, STL, glTF/GLB, DAE...) and validate it");
  cmd->add_option("file", args->file, "Map file")->required();
  cmd->add_option("--scale", args->scale, "Multiply coordinates, e.g. 0.001 for a file in mm")
      ->capture_default_str()
      ->check(positiveFinite());
  cmd->add_option("--up-axis", args->up_axis, "The file's up axis: auto (glTF y, DAE as declared, others z), z, y or x")
      ->capture_default_str()
      ->check(CLI::IsMember({"z", "y", "x"}, CLI::ignore_case));
  cmd->add_flag("--json", args->json, "Print one JSON object on stdout");
  cmd->callback([args] { run(*args); });
}

}  // namespace polyloc::cli

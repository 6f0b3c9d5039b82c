// polyloc map generate lab|office --out FILE: writes a bundled map (maps/generator) to a file
// whose extension picks the format, and prints a one-line summary to stderr.
#include "cli/output_check.hpp"
#include "cli/commands.hpp"

#include <polyloc/map/load.hpp>
#include <polyloc/mapgen/generate.hpp>

#include <fmt/core.h>

#include <memory>
#include <string>

namespace polyloc::cli {

void registerMapGenerate(CLI::App& map) {
  struct Args {
    std::string name;
    std::string out;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = map.add_subcommand(
      "generate", "Write a bundled procedural map (lab: life-science lab floor with ramp and "
                  "stairwell; office: grid of offices, ~10k triangles, the benchmark map)");
  cmd->add_option("name", args->name, "Map to generate: lab or office")->required();
  cmd->add_option("--out,-o", args->out,
                  "Output file; the extension picks the format (.obj .ply .stl .gltf .glb .dae)")
      ->required();
  cmd->callback([args] {
    checkOutputs({}, {{"--out", args->out}});
    const Mesh mesh = generateMap(args->name);
    saveMesh(mesh, args->out);
    const Eigen::AlignedBox3f b = mesh.bounds();
    fmt::print(stderr, "{}: {} triangles, {} labels, bounds [{:.3f}, {:.3f}, {:.3f}] .. "
                       "[{:.3f}, {:.3f}, {:.3f}] -> {}\n",
               args->name, mesh.numTriangles(), mesh.label_names.size() - 1, b.min().x(),
               b.min().y(), b.min().z(), b.max().x(), b.max().y(), b.max().z(), args->out);
  });
}

}  // namespace polyloc::cli

// polyloc: the command-line front end to the kernels. `polyloc --help` lists the subcommands.
#include "cli/commands.hpp"
#include "cli/renamed_options.hpp"

#include <fmt/core.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <cstdio>
#include <exception>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  // Logs of the libraries (the live view's server, the protocol client) go to stderr: stdout is
  // for results (--json).
  spdlog::set_default_logger(spdlog::stderr_color_mt("polyloc"));
  spdlog::set_pattern("[%H:%M:%S.%e] [polyloc] [%l] %v");
  CLI::App app{"polyloc: 6-DoF localisation, virtual range scans and people tracking on polygon maps"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "polyloc 0.1.0");

  CLI::App& map = *app.add_subcommand("map", "Polygon maps: generate bundled maps, inspect and validate files");
  map.require_subcommand(1);
  polyloc::cli::registerMapInfo(map);
  polyloc::cli::registerMapGenerate(map);
  polyloc::cli::registerMapExtrude(map);
  polyloc::cli::registerMapFuse(map);
  polyloc::cli::registerMapNavgrid(map);
  polyloc::cli::registerBench(app);
  polyloc::cli::registerDemo(app);
  polyloc::cli::registerInfo(app);
  polyloc::cli::registerSimulate(app);
  polyloc::cli::registerLocalize(app);
  polyloc::cli::registerRelocalize(app);
  polyloc::cli::registerEval(app);
  polyloc::cli::registerPerceive(app);
  polyloc::cli::registerPlay(app);
  polyloc::cli::registerCtl(app);
  polyloc::cli::registerGpu(app);

  // Old option names still work (with a warning): cli/renamed_options.hpp.
  const std::vector<std::string> args = polyloc::cli::applyRenames(argc, argv, stderr);
  std::vector<const char*> args_c;
  for (const std::string& a : args) args_c.push_back(a.c_str());
  try {
    app.parse(int(args_c.size()), args_c.data());
  } catch (const CLI::ParseError& e) {
    // --help exits 0; a usage error (unknown option, bad value) exits 2, as Unix tools do
    // (CLI11's own codes, 106 and the like, are documented nowhere a user looks).
    return app.exit(e) == 0 ? 0 : 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "polyloc: error: {}\n", e.what());
    return 1;
  }
  return 0;
}

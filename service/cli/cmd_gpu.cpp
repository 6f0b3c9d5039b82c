// polyloc gpu info: what the headless GPU context finds (EGL platform and vendor, GL renderer and
// version, compute limits); exit 1 with the reason when there is none.
#include "cli/commands.hpp"

#ifdef POLYLOC_HAVE_GPU
#include <polyloc/gpu/context.hpp>
#endif

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <stdexcept>

namespace polyloc::cli {

void registerGpu(CLI::App& app) {
  CLI::App& gpu = *app.add_subcommand("gpu", "The GPU path: headless EGL context and compute shaders");
  gpu.require_subcommand(1);
  CLI::App* info = gpu.add_subcommand("info", "EGL vendor, GL renderer and version, compute limits");
  auto json = std::make_shared<bool>(false);
  auto platforms = std::make_shared<std::string>("surfaceless,device,default");
  info->add_flag("--json", *json, "One JSON object on stdout");
  info->add_option("--platforms", *platforms, "EGL platforms to try, in order")->capture_default_str();
  info->callback([json, platforms] {
#ifdef POLYLOC_HAVE_GPU
    const GpuContext context(GpuOptions{*platforms});  // throws GpuError naming what is missing
    const GpuInfo& i = context.info();
    const nlohmann::json j = {
        {"platform", i.platform}, {"egl_vendor", i.egl_vendor}, {"egl_version", i.egl_version},
        {"vendor", i.vendor}, {"renderer", i.renderer}, {"version", i.version}, {"glsl_version", i.glsl_version},
        {"software", i.software}, {"max_ssbo_bytes", i.max_ssbo_bytes}, {"max_ssbo_bindings", i.max_ssbo_bindings},
        {"max_work_group_invocations", i.max_work_group_invocations},
        {"max_work_group_size", {i.max_work_group_size[0], i.max_work_group_size[1], i.max_work_group_size[2]}},
        {"max_work_group_count", {i.max_work_group_count[0], i.max_work_group_count[1], i.max_work_group_count[2]}}};
    if (*json) return fmt::print("{}\n", j.dump());
    fmt::print("EGL platform {} ({} {}); {} / {}; {}{}\n", i.platform, i.egl_vendor, i.egl_version, i.vendor, i.renderer,
               i.version, i.software ? " (software renderer: a CPU)" : "");
#else
    throw std::runtime_error("this polyloc was built without the GPU path (-DPOLYLOC_GPU=OFF)");
#endif
  });
}

}  // namespace polyloc::cli

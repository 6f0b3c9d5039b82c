// Subcommands of the `polyloc` CLI; each group lives in its own cmd_*.cpp and registers itself
// on the app in main.cpp. Callbacks throw on error; main prints the message and exits 1.
#pragma once

#include <CLI/CLI.hpp>

namespace polyloc::cli {

void registerMapInfo(CLI::App& map);      // polyloc map info FILE      (cmd_map_info.cpp)
void registerMapGenerate(CLI::App& map);  // polyloc map generate ...   (cmd_map_generate.cpp)
void registerMapExtrude(CLI::App& map);   // polyloc map extrude ...    (cmd_map_extrude.cpp)
void registerMapFuse(CLI::App& map);      // polyloc map fuse ...       (cmd_map_fuse.cpp)
void registerMapNavgrid(CLI::App& map);   // polyloc map navgrid ...    (cmd_map_navgrid.cpp)
void registerBench(CLI::App& app);        // polyloc bench raycast ...  (cmd_bench.cpp)
void registerDemo(CLI::App& app);         // polyloc demo ...           (cmd_demo.cpp)
void registerInfo(CLI::App& app);         // polyloc info FILE          (cmd_info.cpp)
void registerSimulate(CLI::App& app);     // polyloc simulate ...       (cmd_simulate.cpp)
void registerLocalize(CLI::App& app);     // polyloc localize ...       (cmd_localize.cpp)
void registerRelocalize(CLI::App& app);   // polyloc relocalize ...     (cmd_relocalize.cpp)
void registerBenchMcl(CLI::App& bench);   // polyloc bench mcl ...      (cmd_bench_mcl.cpp)
void registerBenchIpc(CLI::App& bench);   // polyloc bench ipc ...      (cmd_bench_ipc.cpp)
void registerBenchBsp(CLI::App& bench);   // polyloc bench bsp ...      (cmd_bench_bsp.cpp)
void registerBenchMaps(CLI::App& bench);  // polyloc bench maps ...     (cmd_bench_maps.cpp)
void registerEval(CLI::App& app);         // polyloc eval global|kidnap|tracking|depth (cmd_eval.cpp)
void registerEvalTracking(CLI::App& eval); // polyloc eval tracking ...  (cmd_eval_tracking.cpp)
void registerPerceive(CLI::App& app);     // polyloc perceive ...       (cmd_perceive.cpp)
void registerEvalDepth(CLI::App& eval);   // polyloc eval depth ...     (cmd_eval_depth.cpp)
void registerEvalCarmen(CLI::App& eval);  // polyloc eval carmen ...    (cmd_eval_carmen.cpp)
void registerEvalRgbd(CLI::App& eval);    // polyloc eval rgbd ...      (cmd_eval_rgbd.cpp)
void registerEvalNav(CLI::App& eval);     // polyloc eval nav ...       (cmd_eval_nav.cpp)
void registerPlay(CLI::App& app);         // polyloc play ...           (cmd_play.cpp)
void registerCtl(CLI::App& app);          // polyloc ctl --port P CMD   (cmd_ctl.cpp)
void registerGpu(CLI::App& app);          // polyloc gpu info [--json]   (cmd_gpu.cpp)

}  // namespace polyloc::cli

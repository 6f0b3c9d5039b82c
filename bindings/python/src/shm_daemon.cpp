// polyloc.shm.daemon_channels: the only binding that knows polylocd's channel table (pipeline), for daemon stand-ins.
#include "shm_dicts.hpp"

#include "pipeline/channels.hpp"

#include <polyloc/configfile/polyloc_config.hpp>

#include <cstdint>

namespace polyloc::py {

void bindShmDaemon(pb::module_& parent) {
  auto m = parent.attr("_shm").cast<pb::module_>();  // made by bindShm, called before
  m.def("daemon_channels", [](const PolylocConfig& config, uint32_t slots) {
    pb::list out;
    for (const shm::ChannelSpec& s : pipeline::channelTable(config.rig, config.vrs, slots).specs) out.append(specDict(s));
    return out;
  }, pb::arg("config"), pb::arg("slots") = 16,
        "polylocd's channel table for a config (scan/<sensor>, depth/<camera>, odom, pose, vrs, tracks, health), as "
        "specs for Segment.create.");
}

}  // namespace polyloc::py

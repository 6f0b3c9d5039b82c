#include <polyloc/raycast/bsp.hpp>
#include <polyloc/raycast/distance3d.hpp>
#include <polyloc/raycast/embree.hpp>
#include <polyloc/raycast/factory.hpp>
#include <polyloc/raycast/grid2d.hpp>
#include <polyloc/raycast/octomap.hpp>

#ifdef POLYLOC_HAVE_GPU
#include <polyloc/raycast/gpu.hpp>
#endif

#include <cstdio>
#include <stdexcept>

namespace polyloc {

const std::vector<std::string>& casterNames() {
  static const std::vector<std::string> names{"embree", "bsp", "grid2d", "distance3d", "octomap",
#ifdef POLYLOC_HAVE_GPU
                                              "gpu"
#endif
  };
  return names;
}

std::unique_ptr<RayCaster> makeCaster(const std::string& name, const Mesh& mesh,
                                      const CasterOptions& o) {
  if (name == "embree") {
    EmbreeOptions e;
    e.threads = o.threads;
    return std::make_unique<EmbreeCaster>(mesh, e);
  }
  if (name == "bsp") {
    BspOptions b;
    b.threads = o.threads;
    return std::make_unique<BspCaster>(mesh, b);
  }
  if (name == "grid2d") {
    Grid2dOptions g;
    g.resolution = o.resolution;
    g.height = o.height;
    g.threads = o.threads;
    return std::make_unique<Grid2dCaster>(mesh, g);
  }
  if (name == "distance3d") {
    Distance3dOptions d;
    d.field.resolution = o.resolution;
    d.threads = o.threads;
    return std::make_unique<Distance3dCaster>(mesh, d);
  }
  if (name == "octomap") {
    OctomapOptions t;
    t.resolution = o.resolution;
    t.threads = o.threads;
    return std::make_unique<OctomapCaster>(mesh, t);
  }
  if (name == "gpu") {
#ifdef POLYLOC_HAVE_GPU
    GpuCasterOptions g;
    g.context.platforms = o.gpu_platforms;
    g.fallback = o.gpu_fallback;
    g.threads = o.threads;
    g.warn = o.warn;
    try {
      return std::make_unique<GpuCaster>(mesh, g);
    } catch (const GpuError& e) {
      if (!o.gpu_fallback) throw;
      const std::string msg = std::string(e.what()) + "; using the embree caster instead (gpu_fallback)";
      o.warn ? o.warn(msg) : void(std::fprintf(stderr, "polyloc: warning: %s\n", msg.c_str()));
      EmbreeOptions e2;
      e2.threads = o.threads;
      return std::make_unique<EmbreeCaster>(mesh, e2);
    }
#else
    throw std::invalid_argument("ray caster 'gpu': this polyloc was built without the GPU path (cmake -DPOLYLOC_GPU=ON)");
#endif
  }
  std::string known;
  for (const std::string& n : casterNames()) known += (known.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown ray caster '" + name + "' (known: " + known + ")");
}

}  // namespace polyloc

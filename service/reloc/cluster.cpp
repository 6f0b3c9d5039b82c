#include "reloc/cluster.hpp"

#include <cstdlib>
#include <stdexcept>

namespace polyloc::reloc {
namespace {

class SingleProcess final : public Cluster {
 public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  const char* kind() const override { return "single"; }
  std::vector<std::string> gather(const std::string& mine) override { return {mine}; }
};

bool startedByMpirun() {
  return std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_SIZE") || std::getenv("PMIX_RANK");
}

int launchedSize() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (const char* s = std::getenv(v)) return std::atoi(s);
  return 1;
}

}  // namespace

std::unique_ptr<Cluster> Cluster::join() {
  if (!startedByMpirun()) return std::make_unique<SingleProcess>();
#ifdef POLYLOC_HAVE_MPI
  return joinMpi();
#else
  if (launchedSize() > 1)
    throw std::runtime_error("relocalize: started by mpirun, but this polyloc was built without MPI (POLYLOC_MPI=OFF)");
  return std::make_unique<SingleProcess>();
#endif
}

}  // namespace polyloc::reloc

// The MPI side of Cluster (built with POLYLOC_MPI): MPI_Init on joining, MPI_Finalize on
// leaving; gather is MPI_Gather of the sizes and MPI_Gatherv of the bytes to rank 0.
#include "reloc/cluster.hpp"

#define OMPI_SKIP_MPICXX 1  // the C API only: the C++ bindings warn and are deprecated
#include <mpi.h>

#include <stdexcept>
#include <string>

namespace polyloc::reloc {
namespace {

class MpiCluster final : public Cluster {
 public:
  MpiCluster() {
    // Funneled: only this (the main) thread calls MPI; TBB's threads never do.
    int provided = 0;
    if (MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS)
      throw std::runtime_error("relocalize: MPI_Init failed");
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
  }
  ~MpiCluster() override { MPI_Finalize(); }
  int rank() const override { return rank_; }
  int size() const override { return size_; }
  const char* kind() const override { return "mpi"; }

  std::vector<std::string> gather(const std::string& mine) override {
    if (mine.size() > size_t(INT32_MAX)) throw std::runtime_error("relocalize: outcomes of a rank over 2 GiB");
    const int n = int(mine.size());
    std::vector<int> sizes(rank_ == 0 ? size_ : 0), offsets;
    MPI_Gather(&n, 1, MPI_INT, sizes.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
    std::string all;
    if (rank_ == 0) {
      long long total = 0;
      for (int s : sizes) offsets.push_back(int(total)), total += s;
      if (total > INT32_MAX) throw std::runtime_error("relocalize: gathered outcomes over 2 GiB");
      all.resize(size_t(total));
    }
    MPI_Gatherv(mine.data(), n, MPI_BYTE, all.data(), sizes.data(), offsets.data(), MPI_BYTE, 0, MPI_COMM_WORLD);
    std::vector<std::string> out;
    for (int r = 0; r < (rank_ == 0 ? size_ : 0); ++r) out.push_back(all.substr(size_t(offsets[r]), size_t(sizes[r])));
    return out;
  }

 private:
  int rank_ = 0, size_ = 1;
};

}  // namespace

std::unique_ptr<Cluster> joinMpi() { return std::make_unique<MpiCluster>(); }

}  // namespace polyloc::reloc

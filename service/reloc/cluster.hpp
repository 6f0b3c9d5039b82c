// The processes of one `polyloc relocalize` run: MPI ranks when mpirun started it and polyloc
// was built with POLYLOC_MPI (cluster_mpi.cpp), else this process alone. Rank 0 gathers.
#pragma once

#include <memory>
#include <string>
#include <vector>

namespace polyloc::reloc {

class Cluster {
 public:
  virtual ~Cluster() = default;  // MPI: finalises
  virtual int rank() const = 0;
  virtual int size() const = 0;
  virtual const char* kind() const = 0;  // "mpi" or "single"
  // Rank 0 gets every rank's bytes in rank order (its own first); the others get nothing.
  virtual std::vector<std::string> gather(const std::string& mine) = 0;

  // MPI when started by mpirun (OMPI_COMM_WORLD_SIZE, PMI_SIZE or PMIX_RANK in the
  // environment); a single process otherwise. Throws when mpirun started several processes
  // and this build has no MPI (each would otherwise do all the work).
  static std::unique_ptr<Cluster> join();
};

std::unique_ptr<Cluster> joinMpi();  // cluster_mpi.cpp, with POLYLOC_MPI

}  // namespace polyloc::reloc

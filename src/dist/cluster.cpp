#include "dist/cluster.h"

#include <cstdio>
#include <cstdlib>

namespace pt {

#ifdef PTVIEW_HAS_MPI
std::unique_ptr<Cluster> join_mpi_cluster();  // src/dist/mpi/mpi_cluster.cpp
#endif

namespace {
/// Open MPI's mpirun sets OMPI_COMM_WORLD_SIZE; Slurm's srun sets PMIX_RANK (PMIx) or PMI_RANK (PMI-2), as do MPICH's
/// launchers. Started any other way, ptview never calls MPI_Init: it runs exactly as a build without MPI.
[[maybe_unused]] bool started_by_mpi_launcher() {
  for (const char* var : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK"})
    if (std::getenv(var)) return true;
  return false;
}
}  // namespace

int report_error(const Cluster& cluster, const std::string& error) {
  if (!cluster.root()) return 0;
  std::fprintf(stderr, "ptview: error: %s\n", error.c_str());
  return 2;
}

std::unique_ptr<Cluster> join_cluster() {
#ifdef PTVIEW_HAS_MPI
  if (started_by_mpi_launcher()) return join_mpi_cluster();
#endif
  return std::make_unique<Cluster>();
}

}  // namespace pt

#include "studies/cli/process_ranks.hpp"

#ifdef MFDEM_MPI
#include <mpi.h>
#endif

namespace mfdem::cli {
namespace {

ProcessRanks ranks;
[[maybe_unused]] bool started = false;  // MPI_Init was called (the MPI build)

}  // namespace

void start_ranks([[maybe_unused]] int* argc, [[maybe_unused]] char*** argv) {
#ifdef MFDEM_MPI
  // Runs compute with OpenMP inside one rank; MPI is called from the main thread only.
  int provided = 0;
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &ranks.rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks.size);
  started = true;
#endif
}

ProcessRanks process_ranks() { return ranks; }

void wait_for_all_ranks() {
#ifdef MFDEM_MPI
  if (started) MPI_Barrier(MPI_COMM_WORLD);
#endif
}

void finish_ranks() {
#ifdef MFDEM_MPI
  if (started) MPI_Finalize();
  started = false;
#endif
}

bool built_with_mpi() {
#ifdef MFDEM_MPI
  return true;
#else
  return false;
#endif
}

}  // namespace mfdem::cli

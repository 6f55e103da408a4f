#pragma once
// The MPI ranks this process is one of: with the MPI build (cmake -DMFDEM_MPI=ON) started by
// `mpirun -np N mfdem ...`, a campaign's runs are dealt over the N ranks (campaigns/run_slice.hpp),
// each writing its runs into the one store, and rank 0 writes the tables once all are done. The
// default build has no MPI: one rank.
namespace mfdem::cli {

struct ProcessRanks {
  int rank = 0, size = 1;
};

// MPI_Init at the start of main (no-op without MPI); the ranks, {0, 1} until then or without MPI.
void start_ranks(int* argc, char*** argv);
ProcessRanks process_ranks();
// Every rank waits here until all have arrived (a barrier).
void wait_for_all_ranks();
// MPI_Finalize at the end of main.
void finish_ranks();
// True when mfdem was built with MPI.
bool built_with_mpi();

}  // namespace mfdem::cli

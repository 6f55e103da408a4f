// The `mfdem` executable; everything it does lives in studies/cli/ so that tests can reach it.
#include <hdf5.h>
#include <unistd.h>

#include <cstdlib>
#include <iostream>

#include "studies/cli/app.hpp"
#include "studies/cli/process_ranks.hpp"

int main(int argc, char** argv) {
  // OpenMP threads that spin while they wait starve when anything else runs on the machine (two
  // threads on two busy cores ran 4x slower than with sleeping waits). libgomp reads its
  // environment when it loads, so mfdem sets the passive policy and starts itself again, unless
  // the user chose a policy (OMP_WAIT_POLICY=active is fastest on an idle, dedicated machine).
  if (std::getenv("OMP_WAIT_POLICY") == nullptr) {
    setenv("OMP_WAIT_POLICY", "passive", 1);
    execv("/proc/self/exe", argv);  // returns only on failure: then carry on as we are
  }
  // mfdem checks every HDF5 call and says what failed in its own words; HDF5's stack dumps would
  // bury that message.
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  mfdem::cli::start_ranks(&argc, &argv);  // the MPI build under mpirun; nothing otherwise
  const int status = mfdem::cli::run_cli(argc, argv, std::cout, std::cerr);
  mfdem::cli::finish_ranks();
  return status;
}

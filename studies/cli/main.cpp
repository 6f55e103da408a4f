// The `mfdem` executable; everything it does lives in studies/cli/ so that tests can reach it.
#include <unistd.h>

#include <cstdlib>
#include <iostream>

#include "studies/cli/app.hpp"

int main(int argc, char** argv) {
  // OpenMP threads that spin while they wait starve when anything else runs on the machine (two
  // threads on two busy cores ran 4x slower than with sleeping waits). libgomp reads its
  // environment when it loads, so mfdem sets the passive policy and starts itself again, unless
  // the user chose a policy (OMP_WAIT_POLICY=active is fastest on an idle, dedicated machine).
  if (std::getenv("OMP_WAIT_POLICY") == nullptr) {
    setenv("OMP_WAIT_POLICY", "passive", 1);
    execv("/proc/self/exe", argv);  // returns only on failure: then carry on as we are
  }
  return mfdem::cli::run_cli(argc, argv, std::cout, std::cerr);
}

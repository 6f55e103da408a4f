// The `mfdem` executable; everything it does lives in studies/cli/ so that tests can reach it.
#include <iostream>

#include "studies/cli/app.hpp"

int main(int argc, char** argv) { return mfdem::cli::run_cli(argc, argv, std::cout, std::cerr); }

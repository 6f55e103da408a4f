#pragma once
// A surface or shape-library file that cannot be used. The message is meant for the user as is:
// it names the file and the problem, e.g.
//   stone.stl: the surface is open (not watertight): ...
#include <stdexcept>

namespace mfdem::fidelity {

struct ShapeError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace mfdem::fidelity

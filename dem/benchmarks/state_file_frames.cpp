// The cost of writing state frames (dem/state_file.hpp): n frames of a two-sphere scene, for
// n = 1,000 and 10,000 (or the counts given), each count timed a few times. Output is linear
// when 10,000 frames cost about ten times 1,000; the XDMF companion rewritten whole at every
// frame made it quadratic (20,001 frames took about 15 minutes). Not a test: run by hand,
//   build/dem/mfdem_state_frames_benchmark [FRAMES ...]
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <unistd.h>

#include "dem/state_file.hpp"

namespace {

using mfdem::dem::Simulation;
using mfdem::dem::Vec3;

Simulation two_spheres() {
  mfdem::dem::Material ballast;
  ballast.name = "ballast";
  mfdem::dem::MaterialTable materials;
  materials.add(ballast);
  mfdem::dem::Domain domain;
  domain.min = Vec3::Constant(-1.0);
  domain.max = Vec3::Constant(1.0);
  Simulation sim(domain, materials, mfdem::dem::SimulationSettings{});
  sim.add_sphere({Vec3(0, 0, 0), Vec3(0.1, 0, 0), Vec3::Zero(), 0.02, 0});
  sim.add_sphere({Vec3(0.3, 0, 0), Vec3(-0.1, 0, 0), Vec3::Zero(), 0.02, 0});
  sim.prepare();
  return sim;
}

// Seconds to write `frames` frames (a step between each).
double write_frames(int frames, const std::filesystem::path& path) {
  Simulation sim = two_spheres();
  const auto start = std::chrono::steady_clock::now();
  {
    mfdem::dem::StateFile file(path, sim, "benchmark");
    for (int f = 0; f < frames; ++f) {
      sim.step();
      file.write_frame(sim);
    }
  }
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> counts;
  for (int k = 1; k < argc; ++k) counts.push_back(std::atoi(argv[k]));
  if (counts.empty()) counts = {1000, 10000};
  const auto dir = std::filesystem::temp_directory_path() / fmt::format("mfdem-frames-{}", getpid());
  std::filesystem::create_directories(dir);
  fmt::print("| frames | median of 3 (s) | per frame (ms) | against the first count, per frame |\n|---:|---:|---:|---:|\n");
  double first_per_frame = 0.0;
  for (int n : counts) {
    std::vector<double> seconds;
    for (int repeat = 0; repeat < 3; ++repeat) seconds.push_back(write_frames(n, dir / "state.h5"));
    std::sort(seconds.begin(), seconds.end());
    const double per_frame = seconds[1] / n;
    if (first_per_frame == 0.0) first_per_frame = per_frame;
    fmt::print("| {} | {:.3f} | {:.3f} | {:.2f}x |\n", n, seconds[1], 1e3 * per_frame, per_frame / first_per_frame);
  }
  std::filesystem::remove_all(dir);
  return 0;
}

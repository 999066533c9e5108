// Benchmark: each mesh writer's time and bytes against the VTU writer's, on one box mesh per
// size, in the same run. Usage: froth_bench_writers [--repeat K] [CELLS ...] (default 1e5 1e6).
// Each writer runs K times (default 3) and the median time is shown; files go to a temporary
// folder that is removed afterwards.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "froth/froth.hpp"

namespace {

using Clock = std::chrono::steady_clock;

uintmax_t bytes_of(const std::filesystem::path& p) {
  if (!std::filesystem::is_directory(p)) return std::filesystem::file_size(p);
  uintmax_t n = 0;
  for (const auto& e : std::filesystem::recursive_directory_iterator(p))
    if (e.is_regular_file()) n += e.file_size();
  return n;
}

}  // namespace

int main(int argc, char** argv) {
  int repeat = 3;
  std::vector<double> sizes;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--repeat" && i + 1 < argc) repeat = std::max(1, std::atoi(argv[++i]));
    else sizes.push_back(std::atof(argv[i]));
  }
  if (sizes.empty()) sizes = {1e5, 1e6};
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / fmt::format("froth_bench_writers_{}", getpid());
  std::filesystem::create_directories(dir);
  fmt::print("| cells | format | seconds | MB | MB/s | s per byte / VTU's |\n|---|---|---|---|---|---|\n");
  for (double cells : sizes) {
    const froth::Domain box = froth::parse_box_spec("box:0,0,0,1,1,1");
    froth::MeshOptions opt;
    opt.r = froth::radius_for_cells(box, cells, 1, false);
    opt.seed = 1;
    opt.quality = true;
    froth::RunReport run;
    const froth::PolyMesh mesh = froth::generate_mesh(box, opt, &run);
    double vtu_per_byte = 0;
    for (const char* name : {"m.vtu", "m.exo", "polyMesh", "m.npz", "m.nodes"}) {
      const std::filesystem::path out = dir / name;
      std::vector<double> t;
      for (int k = 0; k < repeat; ++k) {
        const auto t0 = Clock::now();
        froth::write_mesh(mesh, run, out);
        t.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
      }
      std::sort(t.begin(), t.end());
      const double seconds = t[t.size() / 2], mb = double(bytes_of(out)) / 1e6;
      if (vtu_per_byte == 0) vtu_per_byte = seconds / mb;
      fmt::print("| {} | {} | {:.3f} | {:.1f} | {:.0f} | {:.2f} |\n", mesh.cell_count(), name, seconds, mb, mb / seconds,
                 seconds / mb / vtu_per_byte);
      std::filesystem::remove_all(out);
    }
  }
  std::filesystem::remove_all(dir);
}

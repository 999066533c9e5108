// Benchmark: froth's whole pipeline on the unit cube against voro++ computing the cells of the
// same seeds, at several sizes. Prints a table. Usage:
//   froth_bench [--threads N] [--seed S] [--repeat K] [CELLS ...]     (default 1e4 1e5 1e6)
// Each size runs K times (default 3; once when its first run takes over 5 s) and the run of
// median total time is shown: a run of 0.1 s at 10^4 cells scatters by a third from one run to
// the next on this machine.
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <string>
#include <tuple>
#include <vector>

#include <fmt/format.h>
#include <voro++.hh>

#include "froth/froth.hpp"
#include "sampling/mps.hpp"

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

size_t rss_kib(const char* key) {
  std::ifstream s("/proc/self/status");
  std::string k;
  while (s >> k) {
    if (k == key) {
      size_t v;
      s >> v;
      return v;
    }
    s.ignore(1 << 20, '\n');
  }
  return 0;
}
void reset_peak_rss() { std::ofstream("/proc/self/clear_refs") << "5"; }

// r giving about `cells` cells in the unit cube (r = 0.01 gives 747,714, and N ~ r^-3).
double radius_for(double cells) { return 0.01 * std::cbrt(747714.0 / cells); }

// voro++ cells of the given seeds in the unit cube, one thread; returns seconds and volume sum.
std::pair<double, double> voro_cells(const std::vector<froth::Vec3>& seeds) {
  auto t0 = Clock::now();
  int n = std::max(1, int(std::cbrt(seeds.size() / 5.0)));  // about 5 seeds per block
  voro::container con(0, 1, 0, 1, 0, 1, n, n, n, false, false, false, 8);
  for (size_t i = 0; i < seeds.size(); ++i) con.put(int(i), seeds[i].x, seeds[i].y, seeds[i].z);
  voro::c_loop_all loop(con);
  voro::voronoicell cell;
  double volume = 0;
  if (loop.start()) do {
      if (con.compute_cell(cell, loop)) volume += cell.volume();
    } while (loop.inc());
  return {since(t0), volume};
}

}  // namespace

int main(int argc, char** argv) {
  int threads = 2;
  uint64_t seed = 1;
  int repeat = 3;
  std::vector<double> sizes;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--threads" && i + 1 < argc) threads = std::atoi(argv[++i]);
    else if (a == "--seed" && i + 1 < argc) seed = std::strtoull(argv[++i], nullptr, 10);
    else if (a == "--repeat" && i + 1 < argc) repeat = std::max(1, std::atoi(argv[++i]));
    else sizes.push_back(std::atof(a.c_str()));
  }
  if (sizes.empty()) sizes = {1e4, 1e5, 1e6};
  froth::Domain cube = froth::make_box_domain({0, 0, 0}, {1, 1, 1});

  struct Later {
    size_t cells;
    double mesh, weld, quality;
    uint64_t collapsed;
  };
  std::vector<Later> later;
  fmt::print("froth pipeline on the unit cube, {} threads; voro++ (1 thread) on the same seeds\n", threads);
  fmt::print("{:>9} {:>8} {:>4} | {:>8} {:>10} | {:>8} {:>10} {:>8} {:>8} {:>9} {:>8} | {:>9} {:>8} | {:>8} {:>7}\n",
             "cells", "r", "runs", "sample s", "seeds/s", "cells s", "cells/s", "assem s", "check s", "total s", "us/cell",
             "peak MiB", "B/cell", "voro++ s", "ratio");
  for (double target : sizes) {
    const double r = radius_for(target);
    froth::MeshOptions opt;
    opt.r = r;
    opt.seed = seed;
    opt.threads = threads;
    opt.weld = 0, opt.quality = false;  // welding and quality are timed on their own below
    struct Run {
      froth::RunReport report;
      double total = 0, voro = 0;
    };
    std::vector<Run> runs;
    froth::PolyMesh mesh;
    size_t first_peak_kib = 0, first_base_kib = 0;  // the first run's: later ones reuse freed memory
    for (int k = 0; k < repeat && (k == 0 || runs[0].total <= 5); ++k) {
      Run run;
      reset_peak_rss();
      const size_t base_kib = rss_kib("VmRSS:");
      omp_set_num_threads(threads);
      mesh = froth::PolyMesh();
      auto t0 = Clock::now();
      mesh = froth::generate_mesh(cube, opt, &run.report);
      run.total = since(t0);
      if (k == 0) first_peak_kib = rss_kib("VmHWM:"), first_base_kib = base_kib;
      omp_set_num_threads(1);
      double volume;
      std::tie(run.voro, volume) = voro_cells(mesh.seeds);
      if (std::abs(volume - 1) > 1e-8) fmt::print(stderr, "voro++ volume sum {} != 1\n", volume);
      runs.push_back(std::move(run));
    }
    // The run of median total time, and the median voro++ time.
    std::vector<double> voro_times;
    for (const Run& x : runs) voro_times.push_back(x.voro);
    std::sort(voro_times.begin(), voro_times.end());
    std::sort(runs.begin(), runs.end(), [](const Run& a, const Run& b) { return a.total < b.total; });
    const Run& median = runs[runs.size() / 2];
    const froth::RunReport& run = median.report;
    const double total = median.total, voro_s = voro_times[voro_times.size() / 2];
    auto stage = [&](const char* name) {
      for (auto& s : run.stages)
        if (s.stage == name) return s.seconds;
      return 0.0;
    };
    const double n = double(run.cells);
    fmt::print("{:>9} {:>8.5f} {:>4} | {:>8.3f} {:>10.0f} | {:>8.3f} {:>10.0f} {:>8.3f} {:>8.3f} {:>9.3f} {:>8.2f} | "
               "{:>9.1f} {:>8.0f} | {:>8.3f} {:>7.2f}\n",
               run.cells, r, runs.size(), stage("sampling"), n / stage("sampling"), stage("cells"),
               n / stage("cells"), stage("assembly"), stage("validation"), total, 1e6 * total / n,
               first_peak_kib / 1024.0, (first_peak_kib - first_base_kib) * 1024.0 / n, voro_s, total / voro_s);
    std::fflush(stdout);
    // Welding (w = 1e-4 r, the CLI's default) and the quality of the welded mesh, timed apart.
    omp_set_num_threads(threads);
    auto t0 = Clock::now();
    const froth::WeldStats ws = froth::weld_mesh(mesh, 1e-4 * r, r);
    const double weld_s = since(t0);
    t0 = Clock::now();
    froth::assess_quality(mesh, &mesh.quality);
    later.push_back({run.cells, total, weld_s, since(t0), ws.edges_collapsed});
  }
  fmt::print("runs: the row is the run of median total time (a size whose first run took over 5 s runs once);\n"
             "total s = sampling + cells + assembly + check (file writing excluded); cells/s = cells stage only;\n"
             "ratio = froth total ({} threads) / median voro++ cells (1 thread);\n"
             "B/cell = (peak RSS of the first run - RSS before it) / cells (later runs reuse memory the allocator kept).\n",
             threads);
  fmt::print("\nwelding (w = 1e-4 r) and quality of the welded mesh, {} threads\n", threads);
  fmt::print("{:>9} | {:>8} | {:>8} {:>9} {:>10} | {:>9} {:>12}\n", "cells", "mesh s", "weld s", "weld/mesh",
             "collapsed", "quality s", "quality/mesh");
  for (const Later& l : later)
    fmt::print("{:>9} | {:>8.3f} | {:>8.3f} {:>8.1f}% {:>10} | {:>9.3f} {:>12.2f}\n", l.cells, l.mesh, l.weld,
               100 * l.weld / l.mesh, l.collapsed, l.quality, l.quality / l.mesh);
}

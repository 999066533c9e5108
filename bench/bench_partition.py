#!/usr/bin/python3
"""Weak scaling of `froth mesh --partition` (issue 5): a fixed problem per rank, box 1 x 1 x K on K
ranks, one thread per rank. Prints a table: cells, halo overhead (ghost seeds / owned seeds, ghost
cells / owned cells), neighbour exchanges in sampling, the slowest rank's time (pipeline without
writing, and writing), and the time per cell of one rank against one rank's.

    bench/bench_partition.py build-mpi/froth [--cells-per-rank 1e5] [--ranks 1,2,3]

With --part, strong scaling instead: the same mesh of that part on K ranks (options after --,
e.g. `--part tests/data/models/ADIS16480.STL -- --cells 1e5 --grade`), with the sampling
stage's seconds beside (a graded part samples its slab on each rank).

Run as root: export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1. More ranks than
cores are oversubscribed (and then slower by the ratio, whatever froth does)."""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile

ap = argparse.ArgumentParser()
ap.add_argument("froth")
ap.add_argument("--cells-per-rank", type=float, default=1e5)
ap.add_argument("--ranks", default="1,2,3")
ap.add_argument("--mpirun", default=shutil.which("mpirun") or "mpirun")
ap.add_argument("--seed", default="1")
ap.add_argument("--part", help="strong scaling: mesh this part, the options after --")
argv = sys.argv[1:]
a = ap.parse_args(argv[:argv.index("--")] if "--" in argv else argv)
a.options = argv[argv.index("--") + 1:] if "--" in argv else []

if a.part:
    tmp = tempfile.mkdtemp()
    print(f"froth mesh {os.path.basename(a.part)} {' '.join(a.options)} --partition, 1 thread per rank, "
          f"{os.cpu_count()} cores")
    print(f"{'ranks':>5} {'cells':>9} {'choosing r s':>12} {'sampling s':>10} {'pipeline s':>10} {'vs 1 rank':>9}")
    base = None
    for k in [int(x) for x in a.ranks.split(",")]:
        out, report = os.path.join(tmp, f"np{k}.pvtu"), os.path.join(tmp, f"np{k}.json")
        subprocess.run([a.mpirun, "--oversubscribe", "-np", str(k), a.froth, "mesh", a.part, *a.options, "--seed",
                        a.seed, "--threads", "1", "--partition", "-o", out, "--report", report],
                       check=True, capture_output=True)
        j = json.load(open(report))
        cells = sum(x["seeds"] for x in j["partition"]["per_rank"])
        total = j["seconds_total"]
        base = base or total
        print(f"{k:>5} {cells:>9} {j['seconds'].get('choosing r', 0):>12.2f} {j['seconds']['sampling']:>10.2f} "
              f"{total:>10.2f} {total / base:>9.2f}")
    shutil.rmtree(tmp)
    raise SystemExit(0)

# Seeds per unit volume of a maximal r-sample: 0.796 / r^3 (measured on boxes, walls included).
r = (0.796 / a.cells_per_rank) ** (1 / 3)
tmp = tempfile.mkdtemp()
cores = os.cpu_count()
print(f"froth mesh --partition, box 1 x 1 x K on K ranks, r = {r:.6g}, 1 thread per rank, {cores} cores")
print(f"{'ranks':>5} {'cells':>9} {'cells/rank':>10} {'ghost/owned seeds':>17} {'ghost/owned cells':>17} "
      f"{'exchanges':>9} {'pipeline s':>10} {'writing s':>9} {'us/cell/rank':>12} {'vs 1 rank':>9}")
base = None
for k in [int(x) for x in a.ranks.split(",")]:
    out, report = os.path.join(tmp, f"np{k}.pvtu"), os.path.join(tmp, f"np{k}.json")
    cmd = [a.mpirun, "--oversubscribe", "-np", str(k), a.froth, "mesh", f"box:0,0,0,1,1,{k}", "-r", f"{r:.17g}",
           "--seed", a.seed, "--threads", "1", "--partition", "-o", out, "--report", report]
    subprocess.run(cmd, check=True, capture_output=True)
    j = json.load(open(report))
    p = j["partition"]
    owned = sum(x["seeds"] for x in p["per_rank"])
    ghost_cells = sum(x["ghost_cells"] for x in p["per_rank"])
    pipeline = j["seconds_total"]  # the slowest rank's, writing excluded
    writing = j["seconds"].get("writing", 0.0)
    per_cell = pipeline / (owned / k) * 1e6
    base = base or per_cell
    print(f"{k:>5} {owned:>9} {owned // k:>10} {p['ghost_over_owned_seeds']:>17.3f} {ghost_cells / owned:>17.3f} "
          f"{max(x['sampling_exchanges'] for x in p['per_rank']):>9} {pipeline:>10.2f} {writing:>9.2f} "
          f"{per_cell:>12.2f} {per_cell / base:>9.2f}")
shutil.rmtree(tmp)

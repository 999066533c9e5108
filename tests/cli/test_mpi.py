"""MPI: `mpirun -np K froth ensemble` for K = 1, 2, 3 (oversubscribed on a 2-core machine) writes
the same member files, byte for byte, as one process; ranks share out the members."""
import json
import os
import subprocess
import sys
import tempfile

FROTH, MPIRUN = sys.argv[1], sys.argv[2]
failures = []
tmp = tempfile.mkdtemp()
args = ["ensemble", "box:0,0,0,1,1,1", "-r", "0.08", "-n", "5", "--seed", "21", "--threads", "1"]
ref = os.path.join(tmp, "serial")
p = subprocess.run([FROTH, *args, "-o", ref], capture_output=True, text=True)
if p.returncode != 0:
    failures.append(f"serial ensemble: {p.stderr}")
for k in (1, 2, 3):
    out = os.path.join(tmp, f"np{k}")
    p = subprocess.run([MPIRUN, "--oversubscribe", "-np", str(k), FROTH, *args, "-o", out], capture_output=True,
                       text=True)
    if p.returncode != 0:
        failures.append(f"mpirun -np {k}: exit {p.returncode}: {p.stderr[-2000:]}")
        continue
    if f"on {k} ranks" not in p.stdout and k > 1:
        failures.append(f"mpirun -np {k}: summary does not say it used {k} ranks: {p.stdout}")
    summary = json.load(open(os.path.join(out, "ensemble.json")))
    if summary["this_run"]["built"] != 5:
        failures.append(f"mpirun -np {k}: built {summary['this_run']}")
    for m in range(5):
        name = f"member_{m:05d}.vtu"
        if open(os.path.join(ref, name), "rb").read() != open(os.path.join(out, name), "rb").read():
            failures.append(f"mpirun -np {k}: {name} differs from the serial ensemble's")
for f in failures:
    print("FAIL:", f)
print(f"{'FAILED' if failures else 'passed'}: MPI ensembles on 1, 2 and 3 ranks")
sys.exit(1 if failures else 0)

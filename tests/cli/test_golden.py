#!/usr/bin/env python3
"""Output bytes before and after: a few runs whose VTU must keep the SHA-256 recorded in
tests/data/golden/meshes.sha256. A change that is meant to change meshes (a fix in sampling,
cells, welding or the writer) updates the record in the same commit, and its message says why:

    test_golden.py FROTH MODELS_DIR [--update]

A refactoring must leave every digest alone. The runs cover a box, a non-convex part by cell
count, --grade, --weld 0, a set welding tolerance and the heater's five regions.
"""
import hashlib
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
RECORD = os.path.join(HERE, "..", "data", "golden", "meshes.sha256")


def runs(models):
    heater = [os.path.join(models, "multi_region_heater", f + ".stl")
              for f in ("bottomAir", "topAir", "heater", "leftSolid", "rightSolid")]
    m = lambda f: os.path.join(models, f)
    return {
        "box": ["box:0,0,0,1,1,1", "-r", "0.1", "--seed", "3"],
        "adis_cells": [m("ADIS16480.STL"), "--cells", "3000", "--seed", "7"],
        "plate_graded": [m("plate_holes.STL"), "--cells", "4000", "--seed", "9", "--grade"],
        "torus_unwelded": [m("torus.STL"), "--cells", "2000", "--seed", "2", "--weld", "0"],
        "tray_weld": [m("1002_tray_bottom.STL"), "--cells", "5000", "--seed", "11", "--weld", "0.05"],
        "heater_regions": heater + ["--cells", "3000", "--seed", "4"],
    }


def digest(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def main():
    froth, models = sys.argv[1], sys.argv[2]
    update = "--update" in sys.argv[3:]
    found = {}
    with tempfile.TemporaryDirectory() as tmp:
        for name, args in runs(models).items():
            out = os.path.join(tmp, name + ".vtu")
            p = subprocess.run([froth, "mesh", *args, "-o", out, "--quiet"], capture_output=True, text=True)
            if p.returncode != 0:
                print(f"FAIL: {name}: froth mesh {' '.join(args)} exited {p.returncode}: {p.stderr.strip()}")
                sys.exit(1)
            found[name] = digest(out)
    if update:
        os.makedirs(os.path.dirname(RECORD), exist_ok=True)
        with open(RECORD, "w") as f:
            f.writelines(f"{h}  {name}.vtu\n" for name, h in found.items())
        print(f"golden: recorded {len(found)} digests in {os.path.relpath(RECORD)}")
        return
    with open(RECORD) as f:
        recorded = {line.split()[1][:-4]: line.split()[0] for line in f if line.strip()}
    failed = 0
    for name, h in found.items():
        if name not in recorded:
            print(f"FAIL: {name}: no recorded digest (run with --update and commit the record)")
            failed += 1
        elif recorded[name] != h:
            print(f"FAIL: {name}: the mesh's bytes changed ({recorded[name][:12]} recorded, {h[:12]} now): "
                  f"froth mesh {' '.join(runs(models)[name])}")
            failed += 1
    if failed:
        sys.exit(1)
    print(f"golden: {len(found)} meshes byte for byte as recorded")


if __name__ == "__main__":
    main()

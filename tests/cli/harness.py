"""What the end-to-end scripts share: counted checks, running froth, VTK's readers."""
import os
import shutil
import subprocess
import sys

import vtk

FROTH = sys.argv[1]
# The sanitizer tier runs each case at its first seed only: the instrumented build is ten times
# slower, and the second seed adds a sample, not code paths.
SEEDS = (1,) if os.environ.get("FROTH_SANITIZED") == "1" else (1, 2)
failures = []
counts = {"passed": 0}


def check(cond, what):
    if cond:
        counts["passed"] += 1
    else:
        failures.append(what)
        print("FAIL:", what)


def froth(*args):
    return subprocess.run([FROTH, *args], capture_output=True, text=True)


def read_vtk(path):
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    return r.GetOutput()


def face_stream(grid, cell, point_id=int):
    """A polyhedral cell's faces as tuples of point ids (mapped through point_id)."""
    ids = vtk.vtkIdList()
    grid.GetFaceStream(cell, ids)
    stream = [ids.GetId(k) for k in range(ids.GetNumberOfIds())]
    faces, k = [], 1
    for _ in range(stream[0]):
        n = stream[k]
        faces.append(tuple(point_id(v) for v in stream[k + 1:k + 1 + n]))
        k += 1 + n
    return faces


CHECKMESH = shutil.which("checkMesh") or "/usr/bin/checkMesh"


def checkmesh(case):
    """OpenFOAM's checkMesh, in the environment Debian's OpenFOAM sets up."""
    return subprocess.run(["bash", "-c", 'source /usr/share/openfoam/etc/bashrc >/dev/null 2>&1; checkMesh -case "$0"', case],
                          capture_output=True, text=True)


def summary():
    """The closing line ctest reads, and the exit code."""
    print(f"{counts['passed']} passed, {len(failures)} failed")
    return 1 if failures else 0

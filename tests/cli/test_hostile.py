"""Hostile use of the command line (issue 25's table): each row an exit code and what must be
left on disk. Self-contained: made shapes and box specs only. Run with Debian's /usr/bin/python3."""
import glob
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

FROTH = os.path.abspath(sys.argv[1])
tmp = tempfile.mkdtemp()
failures, passed = [], 0


def froth(*args, **kw):
    return subprocess.run([FROTH, *args], capture_output=True, text=True, cwd=tmp, **kw)


def row(what, p, code, message=None, absent=(), present=()):
    """Exit `code`, stderr containing `message`, the files `absent` gone and `present` kept."""
    global passed
    problems = []
    if p.returncode != code:
        problems.append(f"exit {p.returncode}, expected {code}")
    if message and message not in p.stderr:
        problems.append(f"stderr lacks {message!r}: {p.stderr.strip()[:300]}")
    for pattern in absent:
        if glob.glob(os.path.join(tmp, pattern)):
            problems.append(f"{pattern} left behind")
    for name, content in present:
        if open(os.path.join(tmp, name), "rb").read() != content:
            problems.append(f"{name} was changed")
    if problems:
        failures.append(f"{what}: {'; '.join(problems)}")
    else:
        passed += 1


cube = b"OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n" \
       b"4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 2 3 7 6\n4 1 2 6 5\n4 0 4 7 3\n"
open(os.path.join(tmp, "in.off"), "wb").write(cube)

# Data loss: an output that is the input or another output.
# Messages that name the real problem: an infinite weld (not the range up to DBL_MAX in full),
# a part whose volume overflows double precision (not "no volume (-nan)").
p = froth("mesh", "box:0,0,0,1,1,1", "-r", "0.3", "--weld", "inf")
row("--weld inf", p, 2, "finite number >= 0, got inf")
if len(p.stderr) > 200:
    failures.append(f"--weld inf: a {len(p.stderr)}-character message")
open(os.path.join(tmp, "huge.off"), "w").write(
    "OFF\n4 4 0\n0 0 0\n1e308 0 0\n0 1e308 0\n0 0 1e308\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n")
row("a tetrahedron scaled by 1e308", froth("mesh", "huge.off", "-r", "1e307"), 3, "overflows double precision")
row("-o onto the input", froth("mesh", "in.off", "-r", "0.3", "-o", "in.off"), 2, "same file", present=[("in.off", cube)])
row("--report onto the input", froth("mesh", "in.off", "-r", "0.3", "--report", "in.off"), 2, "same file",
    absent=["in.vtu"], present=[("in.off", cube)])
row("--report onto -o", froth("mesh", "in.off", "-r", "0.3", "-o", "m.vtu", "--report", "m.vtu"), 2, "same file",
    absent=["m.vtu*"])
p = froth("mesh", "in.off", "-r", "0.3", "-o", "m.vtu")
mesh = open(os.path.join(tmp, "m.vtu"), "rb").read() if p.returncode == 0 else b""
open(os.path.join(tmp, "afile.txt"), "w").write("x")
row("quality --json onto its mesh", froth("quality", "m.vtu", "--json", "m.vtu"), 2, "same file",
    present=[("m.vtu", mesh)])
# A report that cannot be written: no mesh either.
row("--report unwritable", froth("mesh", "in.off", "-r", "0.3", "-o", "n.vtu", "--report", "/nonexistent/r.json"), 4,
    "/nonexistent/r.json", absent=["n.vtu*"])

# Arguments that do not mean what they say.
row("--seed 2^64", froth("mesh", "in.off", "-r", "0.3", "--seed", "18446744073709551616"), 2, "--seed", absent=["in.vtu"])
row("--seed -1", froth("mesh", "in.off", "-r", "0.3", "--seed", "-1"), 2, "--seed", absent=["in.vtu"])
row("scale out of range", froth("mesh", "box:0,0,0,1e-300,1e-300,1e-300", "-r", "1e-301"), 2, "scale out of range",
    absent=["box.vtu"])
t0 = time.time()
row("box thinner than 1e-6 r", froth("mesh", "box:0,0,0,1,1,1e-12", "-r", "0.1", timeout=60), 2, "thick along z",
    absent=["box.vtu"])
if time.time() - t0 > 10:
    failures.append("box thinner than 1e-6 r: not refused at once")
row("more memory than the machine has", froth("mesh", "box:0,0,0,1,1,1", "-r", "0.0014", timeout=60), 2, "GB",
    absent=["box.vtu"])
row("--plots onto a file", froth("quality", "m.vtu", "--plots", "afile.txt"), 4, "afile.txt")
row("--plots where nothing can be written", froth("quality", "m.vtu", "--plots", "/proc/froth-plots"), 4,
    "/proc/froth-plots")
os.mkdir(os.path.join(tmp, "adir.stl"))
row("input is a directory", froth("mesh", "adir.stl", "-r", "0.3"), 4, "is a directory")

# Outputs that cannot be written are refused before any work (issue 40: a read-only folder failed
# only after the whole mesh). /proc takes no new file, even from root, whom permissions let by.
t0 = time.time()
row("-o where nothing can be written", froth("mesh", "box:0,0,0,1,1,1", "-r", "0.01", "-o", "/proc/m.vtu"), 4,
    "no file can be made in /proc")
if time.time() - t0 > 5:
    failures.append("-o where nothing can be written: refused only after meshing")
row("convert where nothing can be written", froth("convert", "m.vtu", "-o", "/proc/case/constant/polyMesh"), 4,
    "no file can be made in /proc")
row("ensemble where nothing can be written", froth("ensemble", "in.off", "-r", "0.3", "-n", "2", "-o", "/proc/ens"),
    4, "no file can be made in /proc")
row("render where nothing can be written", froth("render", "m.vtu", "-o", "/proc/m.png"), 4,
    "no file can be made in /proc")
row("render --color of no array", froth("render", "m.vtu", "--color", "nosuch", "-o", "m.png"), 2,
    "no cell array named nosuch (it has", absent=["m.png*"])
row("--feature-angle 0", froth("mesh", "in.off", "-r", "0.3", "--feature-angle", "0"), 2,
    "strictly between 0 and 180 degrees, got 0")
open(os.path.join(tmp, "back.obj"), "w").write(
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 -9\nf 2 3 4\n")
row("OBJ index counting back past the first vertex", froth("mesh", "back.obj", "-r", "0.3"), 3,
    "line 7: vertex index -9 counts back past the first vertex (4 are defined so far)")
two = "solid a\n" + "".join(
    f"facet normal 0 0 0\nouter loop\nvertex {a}\nvertex {b}\nvertex {c}\nendloop\nendfacet\n"
    for a, b, c in [("0 0 0", "0 1 0", "1 0 0"), ("0 0 0", "1 0 0", "0 0 1"), ("0 0 0", "0 0 1", "0 1 0"),
                    ("1 0 0", "0 1 0", "0 0 1")]) + "endsolid a\n"
open(os.path.join(tmp, "twice.stl"), "w").write(two + two.replace("solid a", "solid b"))
row("two solids of one file on one face", froth("mesh", "twice.stl", "-r", "0.3"), 3, "two solids of this file")

# Ensembles: onto a file, and a usage error, leave nothing new.
open(os.path.join(tmp, "afile"), "w").write("x")
row("ensemble -o onto a file", froth("ensemble", "in.off", "-r", "0.3", "-n", "2", "-o", "afile"), 4, "not a folder",
    present=[("afile", b"x")])
row("ensemble with r = 0", froth("ensemble", "in.off", "-r", "0", "-n", "2", "-o", "ens"), 2, "r must be positive",
    absent=["ens"])

# Hostile VTUs for froth quality: VTK's zlib-compressed, appended raw encoding of a small froth
# mesh, with its first block's header made to lie (a block count past the file; a block that
# claims 2^31 bytes from a few hundred: a zlib bomb). Refused with exit 3, nothing allocated.
import struct  # noqa: E402

import vtk  # noqa: E402

p = froth("mesh", "box:0,0,0,1,1,1", "-r", "0.4", "--no-quality", "-o", "small.vtu")
reader = vtk.vtkXMLUnstructuredGridReader()
reader.SetFileName(os.path.join(tmp, "small.vtu"))
reader.Update()
writer = vtk.vtkXMLUnstructuredGridWriter()
writer.SetInputData(reader.GetOutput())
writer.SetFileName(os.path.join(tmp, "zlib.vtu"))
writer.SetCompressorTypeToZLib()
writer.SetDataModeToAppended()
writer.EncodeAppendedDataOff()
writer.SetHeaderTypeToUInt64()
writer.Write()
data = open(os.path.join(tmp, "zlib.vtu"), "rb").read()
start = data.index(b"<AppendedData encoding=\"raw\">")
start = data.index(b"_", start) + 1  # the first array's block header: blocks, block size, last size, sizes
blocks, block, last = struct.unpack_from("<QQQ", data, start)
row("the zlib VTU as VTK wrote it", froth("quality", "zlib.vtu"), 0)
for name, patch in (("block count past the file", struct.pack("<Q", 1 << 40)),
                    ("zlib bomb", struct.pack("<QQQ", blocks, 1 << 31, 1 << 31))):
    bad = bytearray(data)
    bad[start:start + len(patch)] = patch
    open(os.path.join(tmp, "bad.vtu"), "wb").write(bytes(bad))
    row(f"VTU with a {name}", froth("quality", "bad.vtu"), 3)


# A real zlib bomb: honest block sizes that inflate to 64 MB for 4 points. Refused from the sizes
# the counts allow (96 bytes), before inflating: at once and in little memory.
import base64  # noqa: E402
import zlib  # noqa: E402

deflate = zlib.compressobj(9)
packed = b"".join(deflate.compress(bytes(1 << 20)) for _ in range(64)) + deflate.flush()
header = struct.pack("<QQQQ", 1, 64 << 20, 64 << 20, len(packed))
open(os.path.join(tmp, "bomb.vtu"), "w").write(
    '<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" '
    'header_type="UInt64" compressor="vtkZLibDataCompressor">\n<UnstructuredGrid><Piece NumberOfPoints="4" '
    'NumberOfCells="1"><Points><DataArray type="Float64" NumberOfComponents="3" format="binary">'
    + base64.b64encode(header).decode() + base64.b64encode(packed).decode()
    + "</DataArray></Points></Piece></UnstructuredGrid></VTKFile>\n")
t0 = time.time()
# froth's peak memory, from a fresh interpreter whose one child it is (Debian's `time` may be absent).
PEAK = ("import resource, subprocess, sys\n"
        "code = subprocess.run(sys.argv[1:]).returncode\n"
        "print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss, file=sys.stderr)\n"
        "sys.exit(code)\n")
p = subprocess.run([sys.executable, "-c", PEAK, FROTH, "quality", "bomb.vtu"], capture_output=True, text=True, cwd=tmp)
row("VTU whose blocks inflate to 64 MB for 4 points", p, 3, "declares 67108864 bytes, but its 12 values take 96")
peak_kib = int(p.stderr.strip().splitlines()[-1])
# Against froth's own footprint reading a small mesh (larger under the sanitizers): inflating
# would add the 64 MB.
base = subprocess.run([sys.executable, "-c", PEAK, FROTH, "quality", "small.vtu"], capture_output=True, text=True, cwd=tmp)
base_kib = int(base.stderr.strip().splitlines()[-1])
if peak_kib > base_kib + 32768:
    failures.append(f"zlib bomb: {peak_kib} KiB at the peak against {base_kib} for a small mesh: inflated before it was "
                    "refused")

# Endless and zeroed inputs are refused from their first bytes (issue 40: /dev/zero grew past
# 2.7 GB; 1 GB of NUL bytes took 45 s and 5.3 GB, and the message stopped at the first NUL).
os.symlink("/dev/zero", os.path.join(tmp, "zero.stl"))
t0 = time.time()
row("/dev/zero as an STL", froth("mesh", "zero.stl", "-r", "0.3", "--max-memory", "0.5", timeout=60), 3,
    "neither binary STL", absent=["zero.vtu"])
with open(os.path.join(tmp, "zeros.off"), "wb") as f:
    f.truncate(1 << 30)
p = froth("mesh", "zeros.off", "-r", "0.3", timeout=60)
row("1 GB of NUL bytes as an OFF", p, 3, "byte 1 is a NUL byte, which OFF text cannot hold")
if "\0" in p.stderr or "\\x00" not in p.stderr:
    failures.append("NUL bytes: the message does not show them escaped")
if time.time() - t0 > 5:
    failures.append(f"endless and zeroed inputs: {time.time() - t0:.1f} s to refuse")
os.remove(os.path.join(tmp, "zeros.off"))
with open(os.path.join(tmp, "large.off"), "wb") as f:
    f.truncate(300 << 20)
    f.seek(0)
    f.write(b"OFF\n")
row("a 300 MB file with 0.5 GB of memory", froth("mesh", "large.off", "-r", "0.3", "--max-memory", "0.5"), 2,
    "more than a quarter of the 0.5 GB of memory")
os.remove(os.path.join(tmp, "large.off"))

# Welding that refuses its clusters says so, and why a larger w can collapse fewer edges.
p = froth("mesh", "box:0,0,0,1,1,1", "-r", "0.1", "--weld", "0.09", "-o", "weld.vtu")
row("--weld 0.9 r", p, 0)
if "welding refused 1 clusters" not in p.stdout or "a larger w" not in p.stdout:
    failures.append(f"--weld 0.9 r: the summary does not say the clusters were refused: {p.stdout}")

# convert keeps every array and field of froth's VTU (the bytes come back), and refuses a mesh
# whose cells are open or inverted instead of handing a solver a negative volume.
row("convert a VTU to a VTU", froth("convert", "m.vtu", "-o", "back.vtu"), 0)
if open(os.path.join(tmp, "back.vtu"), "rb").read() != mesh:
    failures.append("convert VTU to VTU: the bytes changed (arrays or field data dropped)")
grid = reader.GetOutput()  # the small box, read by VTK above
ids = vtk.vtkIdList()
grid.GetFaceStream(0, ids)
stream = [ids.GetId(k) for k in range(ids.GetNumberOfIds())]
faces, k = [], 1
for _ in range(stream[0]):  # cell 0 turned inside out: every face reversed
    n = stream[k]
    faces.append(list(reversed(stream[k + 1:k + 1 + n])))
    k += 1 + n
inverted = vtk.vtkUnstructuredGrid()
inverted.SetPoints(grid.GetPoints())
for c in range(grid.GetNumberOfCells()):
    grid.GetFaceStream(c, ids)
    flat = faces if c == 0 else None
    if flat is None:
        st = [ids.GetId(j) for j in range(ids.GetNumberOfIds())]
        flat, j = [], 1
        for _ in range(st[0]):
            flat.append(st[j + 1:j + 1 + st[j]])
            j += 1 + st[j]
    face_stream = vtk.vtkIdList()
    for x in [len(flat)] + [x for f in flat for x in [len(f), *f]]:
        face_stream.InsertNextId(x)
    inverted.InsertNextCell(vtk.VTK_POLYHEDRON, face_stream)
w = vtk.vtkXMLUnstructuredGridWriter()
w.SetInputData(inverted)
w.SetFileName(os.path.join(tmp, "inverted.vtu"))
w.Write()
row("convert an inverted cell", froth("convert", "inverted.vtu", "-o", "inverted.nodes"), 3,
    "not a valid mesh, so it is not converted", absent=["inverted.nodes*"])

# A symbolic link to an output stays a link (the Exodus writer replaced it with a file), and a
# temporary a killed run left beside the output is removed by the next run to it.
open(os.path.join(tmp, "target.exo"), "w").write("old")
os.symlink("target.exo", os.path.join(tmp, "link.exo"))
p = froth("convert", "m.vtu", "-o", "link.exo")
if p.returncode == 0:
    row("Exodus through a symbolic link", p, 0)
    if not os.path.islink(os.path.join(tmp, "link.exo")) or os.path.getsize(os.path.join(tmp, "target.exo")) < 100:
        failures.append("Exodus through a symbolic link: the link was replaced, or its target not written")
dead = subprocess.Popen(["true"])
dead.wait()
open(os.path.join(tmp, f"fresh.vtu.tmp{dead.pid}"), "w").write("a SIGKILL'd run's half")
row("a dead run's temporary", froth("mesh", "box:0,0,0,1,1,1", "-r", "0.3", "-o", "fresh.vtu"), 0,
    absent=[f"fresh.vtu.tmp{dead.pid}"])
row("render into a folder not made yet", froth("render", "m.vtu", "-o", "pictures/m.png"), 0, absent=["pictures/*.tmp*"])

# Signals while writing: the temporary file is removed, the exit code is 128 + the signal.
for sig in (signal.SIGINT, signal.SIGTERM):
    proc = subprocess.Popen([FROTH, "mesh", "box:0,0,0,1,1,1", "-r", "0.012", "--no-quality", "-o", "big.vtu"],
                            cwd=tmp, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline, seen = time.time() + 120, False
    while time.time() < deadline and proc.poll() is None and not seen:
        seen = bool(glob.glob(os.path.join(tmp, "big.vtu.tmp*")))
        time.sleep(0.002)
    proc.send_signal(sig)
    code = proc.wait()
    left = glob.glob(os.path.join(tmp, "big.vtu*"))
    if not seen:
        print(f"note: {sig.name}: the temporary file was not seen before the run ended")
    if seen and (code != 128 + sig or left):
        failures.append(f"{sig.name} while writing: exit {code}, left {left}")
    else:
        passed += 1
    for f in left:
        os.remove(f)

# A write that fails midway (here a file-size limit, as a full disk does) leaves no case folder.
import resource  # noqa: E402


def small_files():
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (100 << 10, 100 << 10))


p = subprocess.run([FROTH, "mesh", "box:0,0,0,1,1,1", "-r", "0.05", "-o", "full/constant/polyMesh"], cwd=tmp,
                   capture_output=True, text=True, preexec_fn=small_files)
row("OpenFOAM case on a full disk", p, 4, "write failed", absent=["full"])

# Signals while an OpenFOAM case is written: neither its files nor the folders made for them stay.
for sig in (signal.SIGINT, signal.SIGTERM):
    proc = subprocess.Popen([FROTH, "mesh", "box:0,0,0,1,1,1", "-r", "0.012", "--no-quality", "-o",
                             "case/constant/polyMesh"], cwd=tmp, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.time() + 120
    while time.time() < deadline and proc.poll() is None and not os.path.isdir(os.path.join(tmp, "case")):
        time.sleep(0.002)
    proc.send_signal(sig)
    code = proc.wait()
    if os.path.exists(os.path.join(tmp, "case")):
        failures.append(f"{sig.name} while writing an OpenFOAM case: exit {code}, left "
                        f"{[d for d, _, _ in os.walk(os.path.join(tmp, 'case'))]}")
        shutil.rmtree(os.path.join(tmp, "case"))
    else:
        passed += 1

shutil.rmtree(tmp)
for f in failures:
    print("FAIL:", f)
print(f"{'FAILED' if failures else 'passed'}: {passed} hostile-input checks")
sys.exit(1 if failures else 0)

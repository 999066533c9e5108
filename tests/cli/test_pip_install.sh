#!/usr/bin/env bash
# pip install, the Python way (README "From Python"): a copy of the sources installed with
# `pip install --no-build-isolation --no-index` into a virtual environment made with
# --system-site-packages (Debian's numpy, setuptools and wheel; no package index), then
# `import froth` from another folder meshes, and the stubs are installed beside the module.
#   test_pip_install.sh SOURCE_DIR
set -euo pipefail
src="$1"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
mkdir "$work/src"
tar -C "$src" --exclude='./build' --exclude='./build-*' --exclude='./.git' -cf - . | tar -x -C "$work/src"
/usr/bin/python3 -m venv --system-site-packages "$work/venv"
FROTH_BUILD_JOBS="${FROTH_BUILD_JOBS:-2}" "$work/venv/bin/pip" install --no-build-isolation --no-index -q "$work/src"
cd "$work"
"$work/venv/bin/python" - <<'PY'
import os, sys
import froth
where = os.path.dirname(froth.__file__)
assert where.startswith(sys.prefix), f"froth imported from {where}, not the virtual environment {sys.prefix}"
for f in ("__init__.pyi", "py.typed"):
    assert os.path.exists(os.path.join(where, f)), f"{f} not installed"
m = froth.mesh("box:0,0,0,1,1,1", r=0.3, seed=1)
assert len(m) > 10 and abs(m.cell_data["volume"].sum() - 1) < 1e-9, (len(m), m.cell_data["volume"].sum())
assert froth.__version__ == froth.version
assert froth.load.__doc__ and "surface file" in froth.load.__doc__
print(f"pip-installed froth {froth.__version__} from {where}: {len(m)} cells")
PY
shown="$("$work/venv/bin/pip" show froth)"
grep -q "^Version: " <<<"$shown"
echo "pip install: passed"

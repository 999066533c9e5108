#!/usr/bin/env bash
# Install and use (issue: froth as a library): cmake --install into a fresh prefix, build
# examples/ against the installed package alone (find_package(froth), froth::froth), run it, and
# run the installed froth, whose scripts must come from PREFIX/share/froth.
# Usage: test_install.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1 source=$2
prefix=$(mktemp -d)
trap 'rm -rf "$prefix"' EXIT
cmake --install "$build" --prefix "$prefix" > "$prefix/install.log"
for f in bin/froth include/froth/froth.hpp lib/libfroth.a lib/cmake/froth/frothConfig.cmake \
         lib/cmake/froth/frothTargets.cmake share/froth/quality_plots.py share/froth/render_mesh.py; do
  [ -e "$prefix/$f" ] || { echo "FAIL: $f is not installed"; exit 1; }
done
# The example sees only the prefix: no source or build tree on its include path.
cmake -S "$source/examples" -B "$prefix/example" -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$prefix" > "$prefix/configure.log"
cmake --build "$prefix/example" -j2 > "$prefix/build.log"
if grep -q -- "-I$source\|$source/src\|$build" "$prefix/example/CMakeFiles/mesh_a_part.dir/flags.make"; then
  echo "FAIL: the example is compiled against the source or build tree"; exit 1
fi
out=$("$prefix/example/mesh_a_part" "$source/examples/unit_sphere.stl" 0.2 "$prefix/sphere.vtu")
echo "$out"
grep -q "cells (" <<<"$out" && [ -s "$prefix/sphere.vtu" ] || { echo "FAIL: the example did not mesh"; exit 1; }
# One default, owned by the library: the installed program given only the radius and the seed
# writes the very bytes the library example writes.
"$prefix/bin/froth" mesh "$source/examples/unit_sphere.stl" -r 0.2 --seed 1 -o "$prefix/sphere_cli.vtu" -q
cmp "$prefix/sphere.vtu" "$prefix/sphere_cli.vtu" || { echo "FAIL: the library and the program mesh differently"; exit 1; }
# A multi-region input: cells of the interface kinds are counted too (kinds 4 and 5).
heater="$source/tests/data/models/multi_region_heater"
out=$("$prefix/example/mesh_a_part" "$heater"/bottomAir.stl "$heater"/topAir.stl "$heater"/heater.stl \
      "$heater"/leftSolid.stl "$heater"/rightSolid.stl 0.012 "$prefix/heater.vtu")
echo "$out"
grep -Eq "[1-9][0-9]* interface face, [0-9]+ interface edge" <<<"$out" && [ -s "$prefix/heater.vtu" ] ||
  { echo "FAIL: the example did not mesh the heater's regions"; exit 1; }
# The installed program reads the example's mesh and draws its plots with the installed script
# (not the source tree's, which is also on this machine): the installed one is wrapped to leave a
# mark when it runs.
mv "$prefix/share/froth/quality_plots.py" "$prefix/share/froth/real_quality_plots.py"
printf 'import os, runpy, sys\nopen(os.path.join(os.path.dirname(__file__), "used"), "w").close()\nsys.argv[0] = os.path.join(os.path.dirname(__file__), "real_quality_plots.py")\nrunpy.run_path(sys.argv[0], run_name="__main__")\n' \
  > "$prefix/share/froth/quality_plots.py"
"$prefix/bin/froth" quality "$prefix/sphere.vtu" --plots "$prefix/plots" -q
[ -s "$prefix/plots/aspect.png" ] || { echo "FAIL: the installed froth drew no plots"; exit 1; }
[ -e "$prefix/share/froth/used" ] || { echo "FAIL: the installed froth used the source tree's script"; exit 1; }
# The installed Python module, from the prefix alone (when the build made one).
if [ -e "$build/python/froth/__init__.py" ]; then
  site="$prefix/lib/python3/dist-packages"
  [ -e "$site/froth/__init__.py" ] && ls "$site"/froth/_froth*.so > /dev/null || { echo "FAIL: the Python module is not installed"; exit 1; }
  (cd "$prefix" && PYTHONPATH="$site" /usr/bin/python3 -c "
import froth, sys
assert froth.__file__.startswith(sys.argv[1]), froth.__file__
m = froth.mesh(sys.argv[2], r=0.3, seed=1)
assert m.cell_count > 0 and abs(m.cell_data['volume'].sum() - froth.load(sys.argv[2]).volume) < 1e-9
froth.mesh(sys.argv[2], r=0.2, seed=1).write('sphere_py.vtu')
print('installed module:', m)" "$site" "$source/examples/unit_sphere.stl") || { echo "FAIL: the installed module does not mesh"; exit 1; }
  cmp "$prefix/sphere.vtu" "$prefix/sphere_py.vtu" || { echo "FAIL: the module and the library mesh differently"; exit 1; }
fi
echo "1 passed, 0 failed"

#!/usr/bin/env bash
# The examples (examples/) against an installed incise, as a user builds them: installs the build into a
# scratch prefix, configures and builds examples/ with find_package(incise) alone, compiles the C example
# again with plain gcc and pkg-config, and runs every example: the C world's geometry must be the one the
# build's `incise replay --fast` makes, the C++ loop must open a groove, the Python examples (Debian's
# python3 importing the installed package, which must find the installed scenarios) must write their PNGs
# and tables.
#   examples_test.sh BUILD_DIR SOURCE_DIR PYTHON GENERATOR
set -euo pipefail
build=$(realpath "$1")
source=$(realpath "$2")
python=$3
generator=$4
work=$(mktemp -d /tmp/incise-examples-test.XXXXXX)
trap 'rm -rf "$work"' EXIT
prefix=$work/prefix
scenarios=$prefix/share/incise/scenarios

cmake --install "$build" --prefix "$prefix" > /dev/null
cmake -S "$source/examples" -B "$work/build" -G "$generator" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build "$work/build" > /dev/null
echo "ok - the examples build against the installed package"

(cd "$work" && "$build/apps/incise" replay --fast --out reference > /dev/null)
expected=$(grep -o '"geometry_hash": *"[0-9a-f]*"' "$work/reference/report.json" | grep -o '[0-9a-f]\{16\}')
"$work/build/step_world" "$scenarios/bunny-straight.json" > "$work/step_world.txt"
grep -q "^geometry $expected$" "$work/step_world.txt"
grep -q "exact: yes" "$work/step_world.txt"
echo "ok - step_world (C) stepped bunny-straight to incise replay's geometry ($expected), its copy exact"

export PKG_CONFIG_PATH=$prefix/lib/pkgconfig
# shellcheck disable=SC2046
gcc -std=c99 -Wall -Wextra -Werror -pedantic "$source/examples/c/step_world.c" -o "$work/step_world_gcc" \
  $(pkg-config --cflags --libs incise_c) -lm -Wl,-rpath,"$prefix/lib"
"$work/step_world_gcc" "$scenarios/bunny-straight.json" | grep -q "^geometry $expected$"
echo "ok - step_world built with gcc and pkg-config alone gives the same"

"$work/build/haptic_loop" "$scenarios/meshes/bunny.obj" 0.01 > "$work/haptic_loop.txt"
grep -q "^incision 1: stroke 4[0-9.]* mm, groove [34][0-9.]* mm$" "$work/haptic_loop.txt"
echo "ok - haptic_loop (C++) cut a groove in its own loop"

export PYTHONPATH=$(ls -d "$prefix"/lib/python3*/dist-packages)
export MPLBACKEND=Agg
unset INCISE_SCENARIOS
cd "$work"
"$python" -c "import incise, sys; d = str(incise.data_dir()); sys.exit(0 if d.startswith('$prefix/') else 'data_dir: ' + d)"
png() { [ "$(head -c 8 "$1" | od -An -tx1 | tr -d ' \n')" = "89504e470d0a1a0a" ] && [ "$(stat -c %s "$1")" -gt 10000 ]; }
"$python" "$source/examples/python/cut_and_plot.py" "$work/cut.png" > "$work/cut.txt"
png "$work/cut.png" && grep -q "ok: True" "$work/cut.txt"
echo "ok - cut_and_plot.py cut the bunny and drew cut.png"
mkdir "$work/traces"
cp "$scenarios/traces/pad-straight.csv" "$scenarios/traces/pad-s-curve.csv" "$work/traces/"
"$python" "$source/examples/python/score_folder.py" "$scenarios/pad-straight.json" "$work/traces" --csv "$work/scores.csv" > "$work/scores.txt"
grep -q "^pad-straight.csv " "$work/scores.txt" && grep -q "^pad-s-curve.csv " "$work/scores.txt"
[ "$(wc -l < "$work/scores.csv")" = 3 ]
echo "ok - score_folder.py scored the folder into a table and scores.csv"
"$python" "$source/examples/python/jigsaws_motion.py" --demo --out "$work/jigsaws.png" > "$work/jigsaws.txt"
png "$work/jigsaws.png" && grep -q "Demo_B001.txt (psm-right): 6.0 s" "$work/jigsaws.txt"
echo "ok - jigsaws_motion.py read a JIGSAWS file, scored its motion and drew jigsaws.png"

#!/usr/bin/env bash
# An installed incise stands without its source tree: installs the build into a scratch prefix, hides the
# source tree (an empty tmpfs mounted over it in a private mount namespace: `unshare -m`, root only), then
# runs the installed `incise replay --fast` (default scenario) and `incise cut` (default mesh) from another
# folder. Their geometry must equal what the build tree's incise makes from the source tree.
#   install_test.sh BUILD_DIR SOURCE_DIR
# Exit 77 (CTest: skipped) where a private mount namespace cannot be made (not root).
set -euo pipefail
build=$(realpath "$1")
source=$(realpath "$2")
work=$(mktemp -d /tmp/incise-install-test.XXXXXX)
trap 'rm -rf "$work"' EXIT

if ! unshare -m true 2> /dev/null; then
  echo "install_test: cannot make a private mount namespace (unshare -m needs root): skipped"
  exit 77
fi

cmake --install "$build" --prefix "$work/prefix" > /dev/null
test -f "$work/prefix/share/incise/scenarios/bunny-straight.json"
test -f "$work/prefix/share/incise/scenarios/meshes/bunny.obj"
test -f "$work/prefix/share/incise/scenarios/traces/bunny-straight.csv"

# The reference: the build tree's binary on the source tree's scenarios.
(cd "$work" && "$build/apps/incise" replay --fast --out ref/replay > /dev/null &&
   "$build/apps/incise" cut --out ref/cut > /dev/null)

unshare -m bash -c "
  set -euo pipefail
  mount -t tmpfs -o size=1m tmpfs '$source'
  test ! -e '$source/scenarios'
  cd '$work'
  '$work/prefix/bin/incise' replay --fast --out installed/replay > /dev/null
  '$work/prefix/bin/incise' cut --out installed/cut > /dev/null
"
hash() { grep -o '"geometry_hash": *"[0-9a-f]*"' "$1"; }
[ "$(hash "$work/installed/replay/report.json")" = "$(hash "$work/ref/replay/report.json")" ]
cmp "$work/installed/replay/cut.obj" "$work/ref/replay/cut.obj"
cmp "$work/installed/cut/cut.obj" "$work/ref/cut/cut.obj"
grep -q "\"$work/prefix/share/incise/scenarios/meshes/bunny.obj\"" "$work/installed/cut/summary.json"
echo "install_test: the installed incise replays and cuts from $work/prefix/share/incise with the source tree hidden"

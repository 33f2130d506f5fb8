#!/usr/bin/env bash
# incise view, render and replay --png end to end (run under xvfb-run by CTest): pictures are written
# through a .tmp and are PNGs; the viewer does not change the replay's bytes; a window closed at the end
# still writes what replay writes; bad options, no display and an old OpenGL are refused with exit 2 and a
# message that says what to do.
#   viewer_cli_test.sh INCISE_BINARY SCENARIOS_DIR
set -u
incise=$1
scenarios=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
check() {  # check NAME CONDITION...
  local name=$1; shift
  if "$@"; then echo "ok   $name"; else echo "FAIL $name"; failures=$((failures + 1)); fi
}
expect_exit() {  # expect_exit CODE PATTERN -- COMMAND...: exit code and a message on stderr matching PATTERN
  local code=$1 pattern=$2; shift 3
  "$@" > "$work/stdout" 2> "$work/stderr"
  local got=$?
  [ "$got" -eq "$code" ] && grep -q -- "$pattern" "$work/stderr" || { echo "  exit $got, stderr: $(cat "$work/stderr")"; return 1; }
}
is_png() { [ "$(head -c 8 "$1" | od -An -tx1 | tr -d ' \n')" = "89504e470d0a1a0a" ]; }
straight=$scenarios/bunny-straight.json

check "render writes a picture of the end state" "$incise" render "$straight" --out "$work/end.png" --size 320x200
check "... a PNG" is_png "$work/end.png"
check "... and no .tmp" test ! -e "$work/end.png.tmp"
check "render --at and --camera" "$incise" render "$straight" --out "$work/mid.png" --at 0.6 --camera 30,20,0.1 --size 320x200
check "... a PNG of its own" bash -c "is_png() { [ \"\$(head -c 8 \"\$1\" | od -An -tx1 | tr -d ' \n')\" = 89504e470d0a1a0a ]; }; is_png '$work/mid.png' && ! cmp -s '$work/mid.png' '$work/end.png'"
check "render without any display goes through EGL" env -u DISPLAY -u WAYLAND_DISPLAY "$incise" render "$straight" --out "$work/egl.png" --size 320x200
check "... the same picture as through the display" cmp -s "$work/egl.png" "$work/end.png"

check "render --tets draws the tet mesh's boundary" "$incise" render "$scenarios/bunny-tets.json" --tets --out "$work/tets.png" --size 320x200
check "... a PNG" is_png "$work/tets.png"
check "render --tets without tets is refused, naming the option" \
  expect_exit 2 "\-\-tets: .*has no tet tissue" -- "$incise" render "$straight" --tets --out "$work/bad-tets.png"

# The viewer must not change the replay's bytes.
check "replay --fast" "$incise" replay "$straight" --fast --out "$work/plain"
check "replay --fast --png" "$incise" replay "$straight" --fast --out "$work/png" --png "$work/png/end.png"
check "... the picture is written" is_png "$work/png/end.png"
check "... and the mesh is byte for byte the same" cmp -s "$work/plain/cut.obj" "$work/png/cut.obj"
check "view --until-end (a real-time run in a window, closed at its end)" \
  bash -c "'$incise' view '$straight' --until-end --speed 2 --size 480x300 --out '$work/view' > '$work/view.txt'"
check "... reports display frames and the latency on screen" grep -q "display frames.*on screen" "$work/view.txt"
check "... writes what replay writes, the mesh byte for byte the same" cmp -s "$work/plain/cut.obj" "$work/view/cut.obj"
check "... and the report" grep -q '"mode": "realtime"' "$work/view/report.json"

# Bad input: exit 2, the option and the value, nothing written.
check "a bad --size is refused with its value" expect_exit 2 "\-\-size '300'" -- "$incise" render "$straight" --out "$work/bad1.png" --size 300
check "a bad --camera is refused with its value" expect_exit 2 "\-\-camera '10,95'" -- "$incise" render "$straight" --out "$work/bad2.png" --camera 10,95
check "a picture not named .png is refused" expect_exit 2 "must end in .png" -- "$incise" render "$straight" --out "$work/bad3.jpg"
check "... and none of them wrote anything" bash -c "! ls '$work' | grep -q '^bad'"
check "view --size is checked too" expect_exit 2 "\-\-size 'big'" -- "$incise" view "$straight" --size big --out "$work/bad-view"
check "view without a display names incise render and xvfb-run" \
  expect_exit 2 "incise render.*xvfb-run" -- env -u DISPLAY -u WAYLAND_DISPLAY "$incise" view "$straight" --out "$work/nodisplay"
check "an old OpenGL is refused with what the driver offers" \
  expect_exit 2 "OpenGL 3.3 core profile is not available.*offers OpenGL 3.0" -- env MESA_GL_VERSION_OVERRIDE=3.0 "$incise" render "$straight" --out "$work/old.png"
check "... through EGL too" \
  expect_exit 2 "OpenGL 3.3 core profile is not available.*offers OpenGL 3.0" -- env -u DISPLAY MESA_GL_VERSION_OVERRIDE=3.0 "$incise" render "$straight" --out "$work/old.png"
check "... before any run, writing nothing" test ! -e "$work/old.png"
echo "viewer cli: $failures check(s) failed"
[ "$failures" -eq 0 ]

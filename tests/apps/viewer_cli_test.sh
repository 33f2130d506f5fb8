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

# A replay that ends and a window that stays open: the run's 1363 frames take 0.7 s at --speed 2, the window
# then shows its last snapshot for 4 s more before Esc. The latency on screen counts each snapshot once, at
# the first display frame showing it: the redraws after the end add nothing, so its maximum stays far below
# the 4 s the window stayed open (counting them, it would be over 4000 ms), and no more snapshots were shown
# than the run has frames.
"$incise" view "$straight" --speed 2 --size 480x300 --out "$work/open" > "$work/open.txt" 2> "$work/open.err" &
view_pid=$!
view_wid=$(xdotool search --sync --name "incise view" | head -1)
sleep 4.7
xdotool key --window "$view_wid" Escape
wait "$view_pid"; view_code=$?
check "view left open after the replay ended, then closed: exit 0" test "$view_code" -eq 0
on_screen() {  # on_screen P50_MAX MAX_MAX: the summary's figures under the bounds, its snapshots <= frames
  python3 - "$work/open.txt" "$@" <<'PY'
import re, sys
text = open(sys.argv[1]).read()
m = re.search(r'on screen ([0-9.]+) ms p50, ([0-9.]+) ms max .* over ([0-9]+) snapshots', text)
frames = re.search(r'\(realtime\): ([0-9]+) frames', text)
if not m or not frames:
    sys.exit('no on-screen figures or frames in: ' + text)
p50, worst, shown = float(m.group(1)), float(m.group(2)), int(m.group(3))
ok = p50 <= float(sys.argv[2]) and worst <= float(sys.argv[3]) and 0 < shown <= int(frames.group(1))
print('  on screen %.1f ms p50, %.1f ms max over %d snapshots (%s frames)' % (p50, worst, shown, frames.group(1)))
sys.exit(0 if ok else 1)
PY
}
check "... its latency on screen leaves out the 4 s of redraws: p50 under 1000 ms, max under 2500 ms" on_screen 1000 2500

# Bad input: exit 2, the option and the value, nothing written.
check "a bad --size is refused with its value" expect_exit 2 "\-\-size '300'" -- "$incise" render "$straight" --out "$work/bad1.png" --size 300
check "a bad --camera is refused with its value" expect_exit 2 "\-\-camera '10,95'" -- "$incise" render "$straight" --out "$work/bad2.png" --camera 10,95
check "a picture not named .png is refused" expect_exit 2 "must end in .png" -- "$incise" render "$straight" --out "$work/bad3.jpg"
check "... and none of them wrote anything" bash -c "! ls '$work' | grep -q '^bad'"
# A textured tissue: drawn with its images; a skin image that is not a PNG stops the command before its run.
check "render draws a textured training scenario" "$incise" render "$scenarios/pad-straight.json" --out "$work/textured.png" --size 320x200
check "... a PNG" is_png "$work/textured.png"
mkdir -p "$work/badtex"
printf 'not a png' > "$work/badtex/skin.png"
python3 -c "
import json; s = json.load(open('$scenarios/pad-straight.json'))
s['tissue']['texture']['skin'] = 'skin.png'; s['tissue']['texture']['wall'] = '$scenarios/textures/flesh.png'
s['pose_source']['path'] = '$scenarios/traces/pad-straight.csv'; json.dump(s, open('$work/badtex/pad.json', 'w'))"
check "a skin image that is not a PNG is refused by render, naming it" \
  expect_exit 2 "the skin image: .*badtex/skin.png: not a PNG file" -- "$incise" render "$work/badtex/pad.json" --out "$work/badtex/bad.png"
check "... and by replay --png, before the run: nothing written" \
  expect_exit 2 "badtex/skin.png: not a PNG file" -- "$incise" replay "$work/badtex/pad.json" --out "$work/badtex/out" --png "$work/badtex/out/end.png"
check "... no picture, no output folder" bash -c "test ! -e '$work/badtex/bad.png' && test ! -e '$work/badtex/out'"
check "view --size is checked too" expect_exit 2 "\-\-size 'big'" -- "$incise" view "$straight" --size big --out "$work/bad-view"
check "view without a display names incise render and xvfb-run" \
  expect_exit 2 "incise render.*xvfb-run" -- env -u DISPLAY -u WAYLAND_DISPLAY "$incise" view "$straight" --out "$work/nodisplay"
check "view on a display no server answers: exit 2, naming the display" \
  expect_exit 2 "cannot open the display DISPLAY=:987 .*no server answers there" -- env DISPLAY=:987 "$incise" view "$straight" --out "$work/deaddisplay"
check "... and no file written" test -z "$(ls -A "$work/deaddisplay" 2> /dev/null)"
check "an old OpenGL is refused with what the driver offers" \
  expect_exit 2 "OpenGL 3.3 core profile is not available.*offers OpenGL 3.0" -- env MESA_GL_VERSION_OVERRIDE=3.0 "$incise" render "$straight" --out "$work/old.png"
check "... through EGL too" \
  expect_exit 2 "OpenGL 3.3 core profile is not available.*offers OpenGL 3.0" -- env -u DISPLAY MESA_GL_VERSION_OVERRIDE=3.0 "$incise" render "$straight" --out "$work/old.png"
check "... before any run, writing nothing" test ! -e "$work/old.png"
echo "viewer cli: $failures check(s) failed"
[ "$failures" -eq 0 ]

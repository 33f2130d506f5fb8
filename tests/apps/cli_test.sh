#!/usr/bin/env bash
# The incise CLI end to end: the main job works and writes its outputs; bad input gives a clear message,
# exit code 2 and no output at all (nothing half-written).
#   cli_test.sh INCISE_BINARY SCENARIOS_DIR
set -u
incise=$1
scenarios=$2
source "$(dirname "$0")/harness.sh"

# The main job on the default scenario.
check "replay runs the default scenario" "$incise" replay --out "$work/ok"
check "replay writes the cut mesh" test -s "$work/ok/cut.obj"
check "replay writes the report" grep -q '"geometry_hash"' "$work/ok/report.json"
check "no temporary file is left" bash -c "! ls '$work/ok' | grep -q tmp"

# Per incision, the stroke length in contact and the groove length made: the crossing scenario's second
# stroke is cut on both sides of the first groove, each groove about as long as its stroke.
check "replay reports each incision's stroke and groove lengths" "$incise" replay "$scenarios/bunny-crossing.json" --fast --out "$work/cross"
check "... three incisions, every groove at least 80% of its stroke" python3 -c "
import json, sys
f = json.load(open('$work/cross/report.json'))['incision_figures']
sys.exit(0 if len(f) == 3 and all(x['groove_length_m'] >= 0.8 * x['stroke_length_m'] > 0 for x in f) else 1)"
check "cut reports its incision's stroke and groove lengths" "$incise" cut --out "$work/cutfig"
check "... the groove as long as the stroke within 10%" python3 -c "
import json, sys
f = json.load(open('$work/cutfig/summary.json'))['incision_figures']
sys.exit(0 if len(f) == 1 and abs(f[0]['groove_length_m'] - f[0]['stroke_length_m']) <= 0.1 * f[0]['stroke_length_m'] else 1)"

# A cut that did nothing never reports success: a 10 cm box of 12 triangles (a CAD model's large
# flat faces) is coarser than the lattice; cut exits 1 and the summary's failure says why and where.
cat > "$work/cadbox.obj" <<'OBJ'
v -0.05 -0.02 -0.05
v 0.05 -0.02 -0.05
v 0.05 0 -0.05
v -0.05 0 -0.05
v -0.05 -0.02 0.05
v 0.05 -0.02 0.05
v 0.05 0 0.05
v -0.05 0 0.05
f 1 4 3
f 1 3 2
f 5 6 7
f 5 7 8
f 1 2 6
f 1 6 5
f 4 8 7
f 4 7 3
f 1 5 8
f 1 8 4
f 2 3 7
f 2 7 6
OBJ
# With local refinement off (--refine off) it is cut as it is:
check "cut on a mesh coarser than the lattice, refinement off, exits 1 and says why" expect_exit 1 \
  "the mesh is coarse next to the lattice" \
  -- "$incise" cut --mesh "$work/cadbox.obj" --scale 1 --subdivide 0 --start -0.02 0.05 0.003 --length 0.04 \
  --refine off --out "$work/cadcut"
check "... its summary's failure names the empty lattice columns" grep -q '"failure": ".*80 of 80 lattice columns' "$work/cadcut/summary.json"
check "... and the incision's shortfall" grep -q '"shortfall": "coarse_mesh"' "$work/cadcut/summary.json"
# With it (the default) the faces along the stroke are bisected until the lattice holds them: a
# groove as long as the stroke within 2 mm, a closed mesh, and the summary gives what refinement added.
check "cut on the same coarse box with local refinement cuts a groove" "$incise" cut --mesh "$work/cadbox.obj" \
  --scale 1 --subdivide 0 --start -0.02 0.05 0.003 --length 0.04 --out "$work/cadrefined"
check "... as long as its stroke, closed, with the faces and vertices refinement added" python3 -c "
import json, sys
s = json.load(open('$work/cadrefined/summary.json'))
f = s['incision_figures'][0]
ok = (s['failure'] == '' and s['mesh']['closed_two_manifold'] and s['refined_vertices'] > 0
      and s['refined_faces'] == 2 * s['refined_vertices'] == 2 * f['refined_vertices']
      and f['groove_length_m'] >= f['stroke_length_m'] - 0.002 and s['options']['refine'] == 'linear')
sys.exit(0 if ok else 1)"
# The shipped bunny as it is, not subdivided (3.8 mm edges at 10 cm: coarser than the lattice): refined along
# the stroke, a groove as long as it; without refinement, no groove and a reason.
check "cut on the bunny not subdivided cuts through refinement" "$incise" cut --subdivide 0 --out "$work/bunny0"
check "... a groove within 2 mm of the stroke, refinement counted" python3 -c "
import json, sys
s = json.load(open('$work/bunny0/summary.json')); f = s['incision_figures'][0]
sys.exit(0 if s['refined_vertices'] > 100 and f['groove_length_m'] >= f['stroke_length_m'] - 0.002 else 1)"
check "cut on the bunny not subdivided, refinement off, exits 1 and says why" expect_exit 1 "coarse next to the lattice" \
  -- "$incise" cut --subdivide 0 --refine off --out "$work/bunny0off"
check "cut --refine pn is accepted" "$incise" cut --mesh "$work/cadbox.obj" --scale 1 --subdivide 0 \
  --start -0.02 0.05 0.003 --length 0.04 --refine pn --out "$work/cadpn"
check "cut --refine with another word exits 2" expect_exit 2 "refine" -- "$incise" cut --refine cubic --out "$work/badrefine"

# Meshes as other tools write them: the bunny as an OFF headed by CGAL's comments (the same cut as from the
# OBJ) and as a binary STL whose 80-byte header begins with "solid" (float positions, corners welded).
python3 - "$scenarios/meshes/bunny.obj" "$work" <<'PY'
import struct, sys
v, f = [], []
for line in open(sys.argv[1]):
    t = line.split('#')[0].split()
    if t and t[0] == 'v': v.append(t[1:4])
    if t and t[0] == 'f': f.append([int(x.split('/')[0]) - 1 for x in t[1:]])
with open(sys.argv[2] + '/bunny.off', 'w') as out:
    out.write('# written by CGAL\n# a comment block before the header\nOFF\n%d %d 0\n\n' % (len(v), len(f)))
    out.writelines(' '.join(p) + '\n' for p in v)
    out.writelines('%d %s\n' % (len(x), ' '.join(map(str, x))) for x in f)
with open(sys.argv[2] + '/bunny.stl', 'wb') as out:
    out.write(b'solid bunny, but binary'.ljust(80) + struct.pack('<I', len(f)))
    for x in f:
        out.write(struct.pack('<3f', 0, 0, 0) + b''.join(struct.pack('<3f', *map(float, v[i])) for i in x) + b'\0\0')
with open(sys.argv[2] + '/bad.off', 'w') as out:
    out.write('OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n')
PY
check "cut accepts an OFF whose first lines are comments" "$incise" cut --mesh "$work/bunny.off" --out "$work/cutoff"
check "... the same cut mesh as from the OBJ" cmp -s "$work/cutfig/cut.obj" "$work/cutoff/cut.obj"
check "cut accepts a binary STL whose header begins with 'solid'" "$incise" cut --mesh "$work/bunny.stl" --out "$work/cutstl"
check "... closed and cut" python3 -c "
import json, sys
b = json.load(open('$work/cutstl/summary.json'))
sys.exit(0 if b['failure'] == '' and b['mesh']['closed_two_manifold'] and b['mesh']['wall_faces'] > 0 and b['edges_split'] > 0 else 1)"
check "a bad OFF is refused with file:line" expect_exit 2 "bad.off:6: face 0 has index 7 but there are 3 vertices" -- "$incise" cut --mesh "$work/bad.off" --out "$work/cutbad"
check "... and nothing is written" test ! -e "$work/cutbad/cut.obj"

# A tet tissue: the cut tets beside the cut surface, their figures in the report.
check "replay runs the tet scenario" "$incise" replay "$scenarios/bunny-tets.json" --out "$work/tets"
for f in tets.vtu tets.node tets.ele cut.obj; do check "the tet replay writes $f" test -s "$work/tets/$f"; done
check "the report has the tet counts, volume and smallest dihedral angle" \
  grep -q '"min_split_dihedral_deg"' "$work/tets/report.json"
check "the .ele names its per-tet attributes" grep -q '^# attributes: side split' "$work/tets/tets.ele"
check "the .vtu has the side field" grep -q 'Name="side"' "$work/tets/tets.vtu"
check "a tissue without a material writes no rest files" test ! -e "$work/tets/cut_rest.obj" -a ! -e "$work/tets/tets_rest.node"

# A simulated tissue: written as simulated and at rest (same vertices and faces, same tets), the physics'
# figures in the report and the summary line.
check "replay runs the simulated pad" "$incise" replay "$scenarios/pad-tension.json" --out "$work/sim"
for f in cut.obj cut_rest.obj tets.node tets_rest.node tets.ele tets_rest.ele; do
  check "the simulated replay writes $f" test -s "$work/sim/$f"
done
check "... the same faces and tets, the vertices moved by the tissue's tension" python3 -c "
import math, sys
def obj(p):
    lines = open(p).read().split(chr(10))
    return [list(map(float, l.split()[1:4])) for l in lines if l.startswith('v ')], [l for l in lines if l.startswith('f ')]
def node(p):
    lines = open(p).read().split(chr(10))
    n = int(lines[0].split()[0])
    return [list(map(float, l.split()[1:4])) for l in lines[1:1 + n]]
(v, f), (rv, rf) = obj('$work/sim/cut.obj'), obj('$work/sim/cut_rest.obj')
x, r = node('$work/sim/tets.node'), node('$work/sim/tets_rest.node')
same = f == rf and len(v) == len(rv) and len(x) == len(r) and open('$work/sim/tets.ele').read() == open('$work/sim/tets_rest.ele').read()
moved = max(math.dist(a, b) for a, b in zip(v, rv)) > 5e-4 and max(math.dist(a, b) for a, b in zip(x, r)) > 5e-4
sys.exit(0 if same and moved else 1)"
check "the report has the physics block" python3 -c "
import json, sys
p = json.load(open('$work/sim/report.json'))['physics']
sys.exit(0 if p['physics_rate_hz'] == 100 and p['steps'] > 100 and p['non_finite_steps'] == 0 and 'p99' in p['physics_step_us'] and p['physics_late'] == 0 and p['physics_deferred'] == 0 and p['stale_maps'] == 0 else 1)"
# The physics on its own thread: in real time the same simulated tissue, byte for byte, and the same physics
# block but its timings.
# A build whose physics cannot keep its rate (the sanitizers' -O1: steps of 60-80 ms against a 10 ms
# period) defers cuts to later steps and maps the blade with older steps' maps, and may differ: then the
# deferral or the stale maps must be counted, and the run says so.
check "replay runs the simulated pad in real time" "$incise" replay "$scenarios/pad-tension.json" --realtime --out "$work/simrt"
behind=$(python3 -c "import json; p = json.load(open('$work/simrt/report.json'))['physics']; print(p['physics_deferred'] + p['stale_maps'])")
if [ "$behind" = 0 ]; then
  for f in cut.obj tets.node tets.ele; do
    check "... the same $f as fast" cmp "$work/sim/$f" "$work/simrt/$f"
  done
  check "... the same physics block but its timings" python3 -c "
import json, sys
a, b = (json.load(open(d + '/report.json'))['physics'] for d in ('$work/sim', '$work/simrt'))
for p in (a, b):
    del p['physics_step_us'], p['physics_late']
sys.exit(0 if a == b else 1)"
else
  echo "note the physics could not keep its rate in this build: $behind cuts deferred or poses mapped stale, so real time may differ from fast"
  check "... its late steps are counted" python3 -c "
import json, sys
sys.exit(0 if json.load(open('$work/simrt/report.json'))['physics']['physics_late'] > 0 else 1)"
fi

# Bad scenarios: exit 2, a message naming the file, nothing in the output directory.
printf '{\n  "tissue": { "mesh": "meshes/bunny.obj" },\n  "pose_source": { "kind": "trace", "path": "traces/missing.csv" }\n}\n' > "$work/missing-trace.json"
mkdir -p "$work/meshes" && cp "$scenarios/meshes/bunny.obj" "$work/meshes/"
check "a scenario naming a missing file is refused" expect_exit 2 "missing.csv does not exist" -- "$incise" replay "$work/missing-trace.json" --out "$work/out1"
check "... and writes nothing" test ! -e "$work/out1"

printf '{ "tissue": { "mesh": "meshes/bunny.obj" ,, }' > "$work/syntax.json"
check "a JSON syntax error names file:line:column" expect_exit 2 "syntax.json:1:" -- "$incise" replay "$work/syntax.json" --out "$work/out2"

# A trace with NaN, a missing column, time going back: file:line and column.
mkdir -p "$work/traces"
header="time_s,tip_x_m,tip_y_m,tip_z_m,q_w,q_x,q_y,q_z,buttons,pressure"
printf '%s\n0,0,0.1,0,1,0,0,0,0,\n0.001,0,nan,0,1,0,0,0,0,\n' "$header" > "$work/traces/nan.csv"
printf 'time_s,tip_x_m,tip_y_m,q_w,q_x,q_y,q_z,buttons,pressure\n' > "$work/traces/columns.csv"
printf '%s\n0.002,0,0.1,0,1,0,0,0,0,\n0.001,0,0.1,0,1,0,0,0,0,\n' "$header" > "$work/traces/back.csv"
for case in nan:"nan.csv:3: column 3 (tip_y_m)" columns:"tip_z_m" back:"back.csv:3"; do
  name=${case%%:*}; pattern=${case#*:}
  printf '{ "tissue": { "mesh": "meshes/bunny.obj", "scale": 0.01 }, "pose_source": { "kind": "trace", "path": "traces/%s.csv" } }' "$name" > "$work/$name.json"
  check "a trace with $name is refused with its place" expect_exit 2 "$pattern" -- "$incise" replay "$work/$name.json" --out "$work/out-$name"
  check "... and writes nothing ($name)" test ! -e "$work/out-$name"
done
# A truncated last line is what a killed recorder leaves: the trace before it replays.
printf '%s\n0,0,0.2,0,1,0,0,0,0,\n0.001,0,0.2,0,1,0,0,0,0,\n0.002,0,0.2' "$header" > "$work/traces/cut.csv"
printf '{ "tissue": { "mesh": "meshes/bunny.obj", "scale": 0.01 }, "pose_source": { "kind": "trace", "path": "traces/cut.csv" } }' > "$work/cut.json"
# Its poses stay 20 cm above the bunny: the replay runs, writes its report and exits 0 (no check failed),
# its summary line saying that nothing was cut.
check "a trace with a truncated last line replays (2 poses, no incision: exit 0, said in the summary)" bash -c \
  "'$incise' replay '$work/cut.json' --out '$work/out-cut' > '$work/cut.txt' && grep -q 'no incision: none of the 2 poses cut the tissue' '$work/cut.txt'"
check "... and its report says so, with no failure" bash -c \
  "grep -q '\"note\": \"no incision: none of the 2 poses' '$work/out-cut/report.json' && grep -q '\"cut_failure\": \"\"' '$work/out-cut/report.json'"

# A tissue that is not a closed two-manifold.
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' > "$work/meshes/open.obj"
printf '{ "tissue": { "mesh": "meshes/open.obj" }, "pose_source": { "kind": "trace", "path": "traces/nan.csv" } }' > "$work/open.json"
check "an open tissue is refused with the edge at fault" expect_exit 2 "open surface: edge" -- "$incise" replay "$work/open.json" --out "$work/out3"
check "... and writes nothing (open)" test ! -e "$work/out3"

# A tissue that intersects itself, with tets: refused before TetGen sees it, naming the two faces.
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 0.2 0.2 -0.5\nv 0.3 0.2 0.8\nv 0.2 0.3 0.8\nv 0.25 0.25 1.5\n' > "$work/meshes/twisted.obj"
printf 'f 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\nf 5 7 6\nf 5 6 8\nf 6 7 8\nf 7 5 8\n' >> "$work/meshes/twisted.obj"
printf '{ "tissue": { "mesh": "meshes/twisted.obj", "tets": {} }, "pose_source": { "kind": "trace", "path": "traces/cut.csv" } }' > "$work/twisted.json"
check "a self-intersecting tissue is refused before TetGen, naming faces" expect_exit 2 "intersect" -- "$incise" replay "$work/twisted.json" --out "$work/out4"
check "... and writes nothing (self-intersecting)" test ! -e "$work/out4"

# The global DFFD: a squashed sphere through a cylinder, a mesh and a JSON line per frame.
check "wrap runs the sphere and cylinder" "$incise" wrap "$scenarios/wrap/sphere-cylinder.json" --out "$work/wrap"
check "wrap writes a mesh per frame" test -s "$work/wrap/frame_0014.obj"
check "wrap writes a JSON line per frame" test "$(wc -l < "$work/wrap/frames.jsonl")" -eq 15
check "no frame penetrates the obstacle" bash -c "! grep -q '\"worst_penetration_m\":[1-9]' '$work/wrap/frames.jsonl'"
check "the same scene gives the same bytes" bash -c "'$incise' wrap '$scenarios/wrap/sphere-cylinder.json' --out '$work/wrap2' > /dev/null && cmp -s '$work/wrap/frame_0007.obj' '$work/wrap2/frame_0007.obj'"
# The open treatment: no two faces cross or touch other than along what they share (the lips F leaves
# together are welded), in every frame. The robot scenes give 0 too but take a minute each (docs/reliability.md);
# the bunny's frame 8 keeps one pair: two skin faces sharing a vertex, folded where the skin wraps the tool.
check "no frame's faces cross (open sphere)" bash -c "grep -c '\"self_intersections\":0,' '$work/wrap/frames.jsonl' | grep -qx 15"
check "no frame's faces cross (open sphere, no v-knots)" bash -c "'$incise' wrap '$scenarios/wrap/sphere-cylinder-no-v-knots.json' --out '$work/nov' > /dev/null && grep -c '\"self_intersections\":0,' '$work/nov/frames.jsonl' | grep -qx 15"
check "at least 20 of 21 frames with no faces crossing (open bunny)" bash -c "'$incise' wrap '$scenarios/wrap/bunny-tool-open.json' --out '$work/bunny-open' > /dev/null && test \$(grep -c '\"self_intersections\":0,' '$work/bunny-open/frames.jsonl') -ge 20"
check "the capped part is closed in every frame" "$incise" wrap "$scenarios/wrap/part-silhouette.json" --out "$work/part"
check "... no boundary loop" bash -c "! grep -q '\"boundary_loops\":[1-9]' '$work/part/frames.jsonl'"
# Capped only where F separates the sides: no cap lies on the other side's, and no crossing face's piece
# beyond a plane is split along its longer diagonal into a sliver whose image flips (frame 7's three pairs).
check "no frame's faces cross (capped part)" bash -c "grep -c '\"self_intersections\":0,' '$work/part/frames.jsonl' | grep -qx 21"
check "the stitched bunny is closed and clear of the tool in every frame" "$incise" wrap "$scenarios/wrap/bunny-tool-stitched.json" --out "$work/stitched"
check "... no boundary loop (stitched)" bash -c "! grep -q '\"boundary_loops\":[1-9]' '$work/stitched/frames.jsonl'"
obstacle() { printf '{ "name": "%s", "shape": "cylinder", "base_m": [%s, 0, -0.03], "axis_m": [0, 0, 0.06], "radius_m": 0.005 }' "$1" "$2"; }
printf '{ "model": { "shape": "sphere" }, "obstacles": [ %s, %s ] }' "$(obstacle left -0.008)" "$(obstacle right 0.008)" > "$work/close.json"
check "obstacles too close are refused with the count needed" expect_exit 2 "'left' and 'right' are too close" -- "$incise" wrap "$work/close.json" --out "$work/out5"
check "... and writes nothing (too close)" test ! -e "$work/out5"
printf '{ "model": { "shape": "sphere" }, "obstacles": [ { "name": "lid", "mesh": "meshes/open.obj" } ] }' > "$work/openob.json"
check "an open obstacle is refused by name" expect_exit 2 "obstacle 'lid': .*open surface" -- "$incise" wrap "$work/openob.json" --out "$work/out6"
printf '{ "model": { "shape": "sphere" }, "obstacles": [ %s ], "treatment": "glued" }' "$(obstacle bar 0)" > "$work/treat.json"
check "a bad treatment names the key" expect_exit 2 "treat.json: treatment: must be" -- "$incise" wrap "$work/treat.json" --out "$work/out7"
check "... and writes nothing (treatment)" test ! -e "$work/out7"

# import jigsaws: one arm of a JIGSAWS kinematics file (76 columns a frame, JIGSAWS's padding) to a trace
# that replays; bad input is refused with file:line and writes nothing.
jigsaws_row() {  # jigsaws_row COLUMNS: a frame, every arm at tip (0, 0.1, 0), R = I, gripper -0.1 (closed)
  python3 -c "import sys; n = int(sys.argv[1]); arm = [0, 0.1, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, -0.1]
print('   ' + '   '.join('%.6f' % v for v in (arm * 5)[:n]) + '   ')" "$1"
}
for i in 1 2 3 4 5; do jigsaws_row 76; done > "$work/Suturing_B001.txt"
check "import jigsaws writes a trace" "$incise" import jigsaws "$work/Suturing_B001.txt" --arm psm-right --scale 2 --offset 0.001 0 0 --out "$work/jig.csv"
check "... the documented header, then the comments" bash -c "head -1 '$work/jig.csv' | grep -qx '$header' && grep -qx '# arm: psm-right (columns 58-76)' '$work/jig.csv'"
check "... a sample per frame: tip scaled then offset, R = I, gripper closed = button 0" bash -c "[ \$(grep -vc '^#' '$work/jig.csv') -eq 6 ] && grep -qx '0.033333333333333333,0.001,0.20000000000000001,0,1,0,0,0,1,' '$work/jig.csv'"
check "... no temporary file is left" test ! -e "$work/jig.csv.tmp"
printf '{ "tissue": { "mesh": "meshes/bunny.obj", "scale": 0.01 }, "pose_source": { "kind": "trace", "path": "jig.csv" } }' > "$work/jig.json"
check "... and the trace replays (its 5 poses above the bunny: no incision, exit 0)" bash -c \
  "'$incise' replay '$work/jig.json' --fast --out '$work/out-jig' > '$work/jig.txt' && grep -q 'no incision: none of the 5 poses' '$work/jig.txt'"
{ jigsaws_row 76; jigsaws_row 75; } > "$work/short.txt"
check "a JIGSAWS file with a wrong column count is refused with file:line" expect_exit 2 "short.txt:2: 75 columns, expected 76" -- "$incise" import jigsaws "$work/short.txt" --arm psm-left --out "$work/short.csv"
check "... and writes nothing (column count)" bash -c "! ls '$work' | grep -q '^short.csv'"
check "a bad --arm is refused" expect_exit 2 "psm-middle" -- "$incise" import jigsaws "$work/Suturing_B001.txt" --arm psm-middle --out "$work/arm.csv"
check "... and writes nothing (arm)" test ! -e "$work/arm.csv"

# record then replay: the generator round trip.
check "record writes a trace from generated strokes" "$incise" record "$scenarios/generate/bunny-straight.json" --out "$work/rec.csv"
check "the recorded trace has the documented header" bash -c "head -1 '$work/rec.csv' | grep -qx '$header'"
check "the shipped trace is what the generator makes" cmp -s "$work/rec.csv" "$scenarios/traces/bunny-straight.csv"

check "an unknown option is refused" expect_exit 2 "not expected" -- "$incise" replay --bogus
finish cli

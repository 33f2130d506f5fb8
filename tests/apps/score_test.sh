#!/usr/bin/env bash
# incise score end to end: the shipped training scenarios' traces scored (a groove along the plan), the
# plots, the bad inputs (exit 2, a message naming the file, nothing written), and scripts/score_all.sh over
# a folder of traces with GNU parallel.
#   tests/apps/score_test.sh INCISE SCENARIOS_DIR
set -u
incise=$1 scenarios=$(cd "$2" && pwd)
source "$(dirname "$0")/harness.sh"
root=$(cd "$(dirname "$0")/../.." && pwd)

for name in pad-straight pad-s-curve bunny-back; do
  check "$name: its trace scores" "$incise" score "$scenarios/$name.json" "$scenarios/traces/$name.csv" --out "$work/$name.jsonl" > /dev/null
  check "... one line for the trace, one summary" test "$(wc -l < "$work/$name.jsonl")" -eq 2
  check "... the groove follows the plan: 95% within the band, 1 stroke" python3 -c "
import json; d = json.loads(open('$work/$name.jsonl').readline())
assert d['strokes_count'] == 1 and d['plan']['share_within_lateral_tolerance'] >= 0.95, d['plan']
assert d['plan']['lateral_mean_abs_m'] < 0.0005 and d['plan']['share_uncut'] < 0.05, d['plan']"
done
check "incise replay cuts the pad cleanly: a closed two-manifold, a groove along 95% of the stroke" bash -c "'$incise' replay '$scenarios/pad-straight.json' --fast --out '$work/pad-replay' | grep -q 'closed two-manifold: yes' && python3 -c \"
import json; f = json.load(open('$work/pad-replay/report.json'))['incision_figures']
assert len(f) == 1 and f[0]['groove_length_m'] >= 0.95 * f[0]['stroke_length_m'] > 0.045, f\""
check "the same trace scores to the same bytes" bash -c "'$incise' score '$scenarios/pad-straight.json' '$scenarios/traces/pad-straight.csv' > '$work/again.jsonl' && head -1 '$work/again.jsonl' | cmp -s - <(head -1 '$work/pad-straight.jsonl' | sed 's|$work/pad-straight.jsonl||')"
check "several traces: a line each and a summary of 2" bash -c "'$incise' score '$scenarios/pad-straight.json' '$scenarios/traces/pad-straight.csv' '$scenarios/traces/pad-s-curve.csv' | tail -1 | grep -q '\"traces\":2'"
check "--plots writes the gnuplot PNG" "$incise" score "$scenarios/pad-straight.json" "$scenarios/traces/pad-straight.csv" --plots "$work/plots" > /dev/null
check "... a PNG file" bash -c "head -c 8 '$work/plots/pad-straight.png' | od -An -c | grep -q 'P   N   G'"
check "... and no temporary file" bash -c "! ls '$work/plots' | grep -q tmp"

# Pass marks: exit 1 only when a trace misses a mark the user gave, naming the trace and the figure.
pad=$scenarios/pad-straight.json
check "marks the trace meets: exit 0, the summary counts it as passed" bash -c "'$incise' score '$pad' '$scenarios/traces/pad-straight.csv' --pass-mark 'plan.share_within_lateral_tolerance>=0.9' --pass-mark 'plan.share_uncut<=0.1' | tail -1 | python3 -c \"
import json, sys; s = json.loads(sys.stdin.read())['summary']
assert s['passed'] == 1 and s['failed'] == 0 and s['pass_marks'] == ['plan.share_within_lateral_tolerance>=0.9', 'plan.share_uncut<=0.1'], s\""
check "a mark one trace misses: exit 1, that trace and its figure named, the scores still written" bash -c "'$incise' score '$pad' '$scenarios/traces/pad-straight.csv' '$scenarios/traces/pad-s-curve.csv' --pass-mark 'plan.share_within_lateral_tolerance>=0.9' --out '$work/marks.jsonl' > /dev/null 2> '$work/marks.err'; [ \$? -eq 1 ] && grep -q 'pad-s-curve.csv: plan.share_within_lateral_tolerance is 0.16, below the pass mark >= 0.9' '$work/marks.err' && ! grep -q 'pad-straight.csv' '$work/marks.err' && tail -1 '$work/marks.jsonl' | grep -q '\"passed\":1,\"failed\":1'"
check "without marks the same traces exit 0" "$incise" score "$pad" "$scenarios/traces/pad-straight.csv" "$scenarios/traces/pad-s-curve.csv" --out "$work/nomarks.jsonl"
check "a mark without >= or <= is refused: exit 2, nothing written" expect_exit 2 "\-\-pass-mark 'economy=0.5': no >= or <=" -- "$incise" score "$pad" "$scenarios/traces/pad-straight.csv" --pass-mark economy=0.5 --out "$work/badmark1.jsonl"
check "a mark on a figure the score has not is refused, naming it" expect_exit 2 "the score has no figure 'plan.share_cut'" -- "$incise" score "$pad" "$scenarios/traces/pad-straight.csv" --pass-mark 'plan.share_cut>=0.5' --out "$work/badmark2.jsonl"
check "a plan mark on a scenario without a plan is refused" expect_exit 2 "has no plan, so the score has no 'plan.share_uncut'" -- "$incise" score "$scenarios/bunny-straight.json" "$scenarios/traces/bunny-straight.csv" --pass-mark 'plan.share_uncut<=0.1' --out "$work/badmark3.jsonl"
check "... and none of them wrote anything" bash -c "! ls '$work' | grep -q badmark"

# A JIGSAWS-like trace on a scenario without a plan: the motion measures only.
check "a scenario without a plan scores the motion only" bash -c "'$incise' score '$scenarios/bunny-straight.json' '$scenarios/traces/bunny-straight.csv' | head -1 | python3 -c \"
import json, sys; d = json.loads(sys.stdin.read())
assert d['plan'] is None and d['economy_reference'] == 'straight_line' and d['session']['path_length_m'] > 0.05\""

check "progress on a terminal (util-linux script), a bar over the traces" bash -c "script -qec \"'$incise' score '$scenarios/pad-straight.json' '$scenarios/traces/pad-straight.csv' '$scenarios/traces/pad-s-curve.csv'\" /dev/null | tr '\\r' '\\n' | grep -q '^score pad-straight \\[#\\{40\\}\\] 100%'"
check "... and none into a file" bash -c "'$incise' score '$scenarios/pad-straight.json' '$scenarios/traces/pad-straight.csv' > /dev/null 2> '$work/progress.err' && ! grep -q '\\[#' '$work/progress.err'"

# A JIGSAWS trace (imported; its arm moves in the air above the bunny, never touching it) on a scenario
# without a plan: the motion measures of the whole session.
python3 -c "
import math
for k in range(90):
    a = 2 * math.pi * k / 90
    arm = [0.02 * math.cos(a), 0.12, 0.02 * math.sin(a), 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, -0.1]
    print('   ' + '   '.join('%.6f' % v for v in (arm * 5)[:76]))" > "$work/Suturing_C001.txt"
check "a JIGSAWS file imports" "$incise" import jigsaws "$work/Suturing_C001.txt" --arm psm-left --out "$work/jig.csv"
printf '{ "tissue": { "mesh": "%s/meshes/bunny.obj", "scale": 0.01 }, "pose_source": { "kind": "trace", "path": "jig.csv" } }' "$scenarios" > "$work/jig.json"
check "... and scores on the motion measures (no plan, no contact)" bash -c "'$incise' score '$work/jig.json' '$work/jig.csv' 2> '$work/jig.err' | head -1 | python3 -c \"
import json, math, sys; d = json.loads(sys.stdin.read()); m = d['session']
assert d['plan'] is None and d['strokes_count'] == 0 and d['economy_reference'] == 'straight_line', d
assert abs(m['path_length_m'] - 2 * math.pi * 0.02 * 89 / 90) < 0.002, m  # the circle, 89 of 90 steps
assert abs(m['time_s'] - 89 / 30) < 0.04 and m['economy'] < 0.1, m         # back almost where it began
assert m['sparc'] < 0 and m['log_dimensionless_jerk'] is not None, m\""
check "... with a warning that the trace carries no tissue hash" grep -q "carries no tissue hash" "$work/jig.err"

# Bad input: exit 2, the file named, nothing written.
head -5 "$scenarios/traces/pad-straight.csv" > "$work/empty.csv"
check "an empty trace is refused" expect_exit 2 "empty.csv: the trace is empty" -- "$incise" score "$scenarios/pad-straight.json" "$work/empty.csv" --out "$work/bad1.jsonl"
check "... and nothing is written" test ! -e "$work/bad1.jsonl"
check "a trace recorded on another tissue is refused" expect_exit 2 "bunny-back.csv: recorded on another tissue" -- "$incise" score "$scenarios/pad-straight.json" "$scenarios/traces/pad-s-curve.csv" "$scenarios/traces/bunny-back.csv" --out "$work/bad2.jsonl"
check "... and nothing is written (not even the good trace's line)" test ! -e "$work/bad2.jsonl"
sed 's/"lateral_tolerance_m": 0.002/"lateral_tolerance_m": 0/' "$scenarios/pad-straight.json" | sed "s|traces/|$scenarios/traces/|; s|textures/|$scenarios/textures/|" > "$work/tol.json"
check "a tolerance <= 0 is refused naming the file and key" expect_exit 2 "tol.json: plan.lateral_tolerance_m: must be > 0" -- "$incise" score "$work/tol.json" "$scenarios/traces/pad-straight.csv" --out "$work/bad3.jsonl"
python3 -c "
import json; s = json.load(open('$scenarios/pad-straight.json')); s['plan']['points_m'][1] = [0.3, 0.0, 0.0]
s['pose_source']['path'] = '$scenarios/traces/pad-straight.csv'
for k in ('skin', 'wall'): s['tissue']['texture'][k] = '$scenarios/' + s['tissue']['texture'][k]
json.dump(s, open('$work/off.json', 'w'))"
check "a plan point off the tissue is refused naming it" expect_exit 2 "off.json: plan.points_m\[1\]: .* does not project onto the tissue" -- "$incise" score "$work/off.json" "$scenarios/traces/pad-straight.csv" --out "$work/bad4.jsonl"
check "... and so is it by incise replay (plans are projected at load)" expect_exit 2 "off.json: plan.points_m\[1\]" -- "$incise" replay "$work/off.json" --out "$work/bad5"
check "... and nothing is written (plan)" bash -c "! ls '$work' | grep -q bad"

# scripts/score_all.sh: a folder of traces with GNU parallel.
mkdir -p "$work/folder/sub"
cp "$scenarios/traces/pad-straight.csv" "$work/folder/a.csv"
cp "$scenarios/traces/pad-s-curve.csv" "$work/folder/b.csv"
cp "$scenarios/traces/pad-straight.csv" "$work/folder/sub/c.csv"
check "score_all.sh scores a folder in parallel" env INCISE="$incise" "$root/scripts/score_all.sh" "$work/folder" "$scenarios/pad-straight.json" --batch 2 --jobs 2
check "... a line per trace in sorted order, then the summary" python3 -c "
import json; lines = [json.loads(l) for l in open('$work/folder/scores.jsonl')]
assert [l['trace'].split('/')[-1] for l in lines[:3]] == ['a.csv', 'b.csv', 'c.csv'], lines
assert lines[3]['summary']['traces'] == 3 and len(lines) == 4"
check "... the same figures as incise score on one trace" bash -c "diff <(head -1 '$work/folder/scores.jsonl' | sed 's/^{\"trace\":\"[^\"]*\",//') <(head -1 '$work/pad-straight.jsonl' | sed 's/^{\"trace\":\"[^\"]*\",//')"
check "... and the same summary as incise score over the same traces" bash -c "diff <(tail -1 '$work/folder/scores.jsonl') <('$incise' score '$scenarios/pad-straight.json' '$work/folder/a.csv' '$work/folder/b.csv' '$work/folder/sub/c.csv' | tail -1)"
cp "$work/empty.csv" "$work/folder/d.csv"
check "score_all.sh stops on a bad trace, exit 2, writes nothing" bash -c "rm '$work/folder/scores.jsonl'; INCISE='$incise' '$root/scripts/score_all.sh' '$work/folder' '$scenarios/pad-straight.json' 2> /dev/null; [ \$? -ne 0 ] && [ ! -e '$work/folder/scores.jsonl' ]"
finish "score"

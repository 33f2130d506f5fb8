#!/usr/bin/env bash
# The incise HID commands end to end, without hardware: the shipped recordings decode and replay, a tablet's
# recording swapped into a pen scenario replays, the live commands record and calibrate from the replay
# transport (a recording played as if plugged in), a recorder killed with SIGKILL leaves a file that reads
# back, and bad input gives a clear message, exit 2 and no output.
#   hid_cli_test.sh INCISE_BINARY SCENARIOS_DIR
set -u
incise=$1
scenarios=$2
source "$(dirname "$0")/harness.sh"
wacom=$scenarios/hid/bunny-pen-wacom.hid

# hid list: on a machine without devices it says so and where to look; through the replay transport it
# lists the recording's device and the profile its descriptor calls for.
check "hid list runs without devices" bash -c "'$incise' hid list > '$work/list' && grep -q 'HID' '$work/list'"
check "hid list through the replay transport names the pen profile" bash -c \
  "'$incise' hid list --transport replay:'$wacom' | grep -q 'profile pen: input report 16'"

# hid decode: text like hid-decode, and one JSON object per report.
check "hid decode prints the fields by name" bash -c "'$incise' hid decode '$wacom' | grep -q 'Tip Pressure [0-9]*, X Tilt'"
check "hid decode --json: one object per report, named fields, a pose" python3 -c "
import json, subprocess, sys
out = subprocess.run(['$incise', 'hid', 'decode', '$wacom', '--json', '--scenario', '$scenarios/bunny-pen-wacom.json'],
                     capture_output=True, text=True, check=True).stdout.splitlines()
reports = [line for line in open('$wacom') if line.startswith('E:')]
objs = [json.loads(line) for line in out]
names = {f['name'] for f in objs[40]['fields']}
ok = len(objs) == len(reports) and {'X', 'Y', 'Tip Pressure', 'X Tilt', 'Twist'} <= names and objs[40]['pose'] is not None
x = next(f for f in objs[40]['fields'] if f['name'] == 'X')
ok = ok and x['unit'] == 'cm' and x['usage_page'] == 0xff0d and abs(x['physical'] - x['logical'] * 22400 / 44800 * 1e-3) < 1e-9
sys.exit(0 if ok else 1)"
check "hid decode of a bare descriptor lists its reports" bash -c \
  "'$incise' hid decode '$scenarios/hid/descriptors/3dconnexion_spacenavigator_046d_c626.txt' | grep -q 'Input report 2: 7 bytes'"

# The shipped recordings: the generator makes them again byte for byte, and each replays to a closed cut.
for name in bunny-pen-wacom bunny-pen-xppen bunny-spacenavigator; do
  check "hid synth remakes $name.hid byte for byte" bash -c \
    "'$incise' hid synth '$scenarios/$name.json' --out '$work/$name.hid' > /dev/null && cmp -s '$work/$name.hid' '$scenarios/hid/$name.hid'"
  check "replay of $name cuts a closed two-manifold groove" bash -c \
    "'$incise' replay '$scenarios/$name.json' --fast --out '$work/r-$name' | grep -q 'closed two-manifold: yes'"
done
check "... the pen groove as long as the stroke's within 5%" python3 -c "
import json, sys
f = json.load(open('$work/r-bunny-pen-wacom/report.json'))['incision_figures']
sys.exit(0 if len(f) == 1 and f[0]['groove_length_m'] > 0.95 * f[0]['stroke_length_m'] > 0.05 else 1)"

# A tablet from outside the three the scenarios were made with, as a user tries it: a stroke recorded from a
# Huion Kamvas Pro 19 (synthesised through its descriptor) in place of pad-pen-wacom's recording, nothing else
# changed, cuts the groove the Wacom recording cuts, within 5%. (Scenario copies in $work name files by
# absolute paths.)
scenarios=$(cd "$scenarios" && pwd)
python3 -c "
import json, os
s = json.load(open('$scenarios/pad-pen-wacom.json'))
synth = s['pose_source']['synthesis']
synth.update(descriptor='$scenarios/hid/descriptors/huion_kamvas_pro_19_256c_006b.txt', vid='256c', pid='006b',
             name='HUION Huion Tablet_GT1902', **{'from': '$scenarios/' + synth['from']})
s['pose_source']['path'] = '$work/huion.hid'
json.dump(s, open('$work/huion-synth.json', 'w'))
s = json.load(open('$scenarios/pad-pen-wacom.json'))
del s['pose_source']['synthesis']
s['pose_source']['path'] = '$work/huion.hid'
json.dump(s, open('$work/pad-pen-huion.json', 'w'))"
check "hid synth through the Huion Kamvas Pro 19's descriptor (a Stylus application nested in a Pen one)" bash -c \
  "'$incise' hid synth '$work/huion-synth.json' > /dev/null && '$incise' hid list --transport replay:'$work/huion.hid' | grep -q 'profile pen: input report 10 (Pen > Stylus'"
check "... swapped into pad-pen-wacom, it replays to the Wacom recording's groove within 5%" bash -c \
  "'$incise' replay '$work/pad-pen-huion.json' --fast --out '$work/r-huion' > /dev/null && '$incise' replay '$scenarios/pad-pen-wacom.json' --fast --out '$work/r-pad-wacom' > /dev/null && python3 -c \"
import json, sys
a = json.load(open('$work/r-huion/report.json'))['incision_figures']
b = json.load(open('$work/r-pad-wacom/report.json'))['incision_figures']
sys.exit(0 if len(a) == 1 and len(b) == 1 and abs(a[0]['groove_length_m'] - b[0]['groove_length_m']) <= 0.05 * b[0]['groove_length_m'] > 0 else 1)\""

# hid calibrate through the replay transport: the shipped calibration recording (three presses synthesised from
# scenarios/hid/calibrate/presses.json through the Wacom's descriptor) gives a pen block that lays the pressed
# corners onto the scenario's rectangle, measures dead band and curve, and loads when pasted in.
calib=$scenarios/hid/calibrate/pen-wacom.hid
check "hid synth remakes calibrate/pen-wacom.hid byte for byte" bash -c \
  "'$incise' hid synth '$scenarios/hid/calibrate/pen-wacom.json' --out '$work/calib.hid' > /dev/null && cmp -s '$work/calib.hid' '$calib'"
check "hid calibrate prints a pen block" bash -c \
  "'$incise' hid calibrate --device 056a:0357 --transport replay:'$calib' --scenario '$scenarios/pad-pen-wacom.json' > '$work/pen.json' 2> '$work/calibrate.log'"
check "... the pressed corners go onto the scenario's rectangle; dead band and curve measured" python3 -c "
import json, re, sys
pen = json.load(open('$work/pen.json'))['pen']
target = json.load(open('$scenarios/pad-pen-wacom.json'))['pose_source']['pen']
presses = [tuple(map(float, m)) for m in re.findall(r'pressed at X ([0-9.]+), Y ([0-9.]+)', open('$work/calibrate.log').read())]
def at(f): return [pen['origin_m'][i] + f[0] * pen['x_edge_m'][i] + f[1] * pen['y_edge_m'][i] for i in range(3)]
far = [target['origin_m'][i] + target['x_edge_m'][i] + target['y_edge_m'][i] for i in range(3)]
ok = len(presses) == 3 and abs(presses[0][0] - 0.21) < 0.005 and abs(presses[1][1] - 0.7) < 0.005
ok = ok and max(abs(a - b) for a, b in zip(at(presses[0]), target['origin_m'])) < 2e-4
ok = ok and max(abs(a - b) for a, b in zip(at(presses[1]), far)) < 2e-4
ok = ok and 0 < pen['dead_band'] < 0.2 and 0.1 <= pen['curve'] <= 10 and pen['max_depth_m'] == target['max_depth_m']
sys.exit(0 if ok else 1)"
python3 -c "
import json
s = json.load(open('$scenarios/pad-pen-wacom.json'))
del s['pose_source']['synthesis']
s['pose_source']['path'] = '$scenarios/hid/pad-pen-wacom.hid'
s['pose_source']['pen'] = json.load(open('$work/pen.json'))['pen']
json.dump(s, open('$work/calibrated.json', 'w'))"
check "... pasted into the scenario, the block loads and makes poses" bash -c \
  "'$incise' hid decode '$scenarios/hid/pad-pen-wacom.hid' --scenario '$work/calibrated.json' | grep -q 'pose: tip'"
check "hid calibrate of a device that is not a pen: exit 2, what it is" expect_exit 2 "is not a pen: no pen: no Stylus" -- \
  "$incise" hid calibrate --device 046d:c626 --transport replay:"$scenarios/hid/bunny-spacenavigator.hid"
check "hid calibrate without the presses in time: exit 2 (no input), nothing on stdout" bash -c \
  "'$incise' hid calibrate --device 056a:0357 --transport replay:'$calib' --timeout 0.2 > '$work/none.json' 2> '$work/none.log'; [ \$? -eq 2 ] && [ ! -s '$work/none.json' ] && grep -q '0 of 3 presses' '$work/none.log'"

# hid record through the replay transport: the reports read back as they were sent.
check "hid record records the replayed device" "$incise" hid record --device 056a:0357 --transport replay:"$wacom" --duration 2 --out "$work/rec.hid"
check "... every report, bytes as in the recording" python3 -c "
import sys
a = [l.split()[2:] for l in open('$wacom') if l.startswith('E:')]
b = [l.split()[2:] for l in open('$work/rec.hid') if l.startswith('E:')]
sys.exit(0 if a == b else 1)"
check "... and it decodes" bash -c "'$incise' hid decode '$work/rec.hid' > /dev/null"
# SIGKILL mid-recording: what was flushed reads back.
"$incise" hid record --device 056a:0357 --transport replay:"$wacom" --out "$work/killed.hid" > /dev/null 2>&1 &
pid=$!
sleep 0.8
kill -9 $pid 2> /dev/null
wait $pid 2> /dev/null
check "a hid recorder killed with SIGKILL leaves a file that decodes" bash -c \
  "'$incise' hid decode '$work/killed.hid' > '$work/killed.txt' && [ \$(grep -c '^E:' '$work/killed.txt') -ge 50 ]"

# record --device: poses from a live device through its profile, to a CSV trace that replays.
check "record --device writes a trace" "$incise" record "$scenarios/bunny-pen-wacom.json" --device 056a:0357 --transport replay:"$wacom" --duration 1.8 --out "$work/live.csv"
check "... a pose per report, cutting in the middle" python3 -c "
import sys
rows = [l.split(',') for l in open('$work/live.csv') if l[0].isdigit()]
sys.exit(0 if len(rows) >= 200 and sum(1 for r in rows if r[8] == '1') > 100 else 1)"

# Bad input: exit 2, the place, nothing written.
check "no such device: exit 2, nothing written" expect_exit 2 "no device 056a:0358" -- "$incise" hid record --device 056a:0358 --out "$work/none.hid"
check "... nothing written (no device)" test ! -e "$work/none.hid"
check "a bad --device names the value" expect_exit 2 "--device 'pen': expected VID:PID" -- "$incise" hid record --device pen --out "$work/bad.hid"
check "a bad --transport names the value" expect_exit 2 "--transport 'usb'" -- "$incise" hid list --transport usb
check "record --device without a device: exit 2, nothing written" expect_exit 2 "no pose" -- "$incise" record --device 1234:5678 --duration 0.3 --out "$work/none.csv"
check "... nothing written (record)" test ! -e "$work/none.csv"
awk '/^E:/ { n++; if (n == 7) $3 = "26" } { print }' "$wacom" > "$work/badlen.hid"
check "a recording whose length disagrees with its bytes: file:line" expect_exit 2 "badlen.hid:[0-9]*:" -- "$incise" hid decode "$work/badlen.hid"
awk 'BEGIN { n = 0 } /^E:/ { n++; if (n == 10) { $3 = "3"; NF = 6 } } { print }' "$wacom" > "$work/short.hid"
check "a report shorter than its layout: printed, counted, exit 2 with file:line" expect_exit 2 "short.hid:[0-9]*: 1 bad report" -- "$incise" hid decode "$work/short.hid"
awk '/^E:/ { n++; if (n == 20) $2 = "000000.000001" } { print }' "$wacom" > "$work/back.hid"
check "time going back: file:line" expect_exit 2 "back.hid:[0-9]*:.*back" -- "$incise" hid decode "$work/back.hid"
printf '05 01 09 02 a1 01 15 00 25 01 75 01 95 08 81 02\n' > "$work/open.txt"
check "a descriptor with an unclosed collection: the byte" expect_exit 2 "collection opened at byte 4" -- "$incise" hid decode "$work/open.txt"
printf 'D: 0\nR: 4 05 01 09\n' > "$work/shortdesc.hid"
check "an R: line shorter than its length: file:line" expect_exit 2 "shortdesc.hid:2:" -- "$incise" hid decode "$work/shortdesc.hid"

finish hid_cli

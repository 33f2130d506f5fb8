#!/usr/bin/env bash
# The incise HID commands end to end, without hardware: the shipped recordings decode and replay, the live
# commands record from the replay transport (a recording played as if plugged in), a recorder killed with
# SIGKILL leaves a file that reads back, and bad input gives a clear message, exit 2 and no output.
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

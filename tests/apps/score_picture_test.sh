#!/usr/bin/env bash
# incise score --picture (under xvfb-run, like the viewer's CLI test): the cut seen from above with the plan
# drawn over it: the plan's green line lies on the groove's dark pixels.
#   tests/apps/score_picture_test.sh INCISE SCENARIOS_DIR
set -u
incise=$1 scenarios=$(cd "$2" && pwd)
source "$(dirname "$0")/harness.sh"
check "score --picture writes the top-down picture" "$incise" score "$scenarios/pad-straight.json" \
  "$scenarios/traces/pad-straight.csv" --plots "$work/plots" --picture > /dev/null
check "... a PNG beside the plot" bash -c "head -c 8 '$work/plots/pad-straight-top.png' | od -An -c | grep -q 'P   N   G'"
check "... the plan's line is drawn (green pixels) and lies over the groove (dark red next to it)" python3 -c "
import struct, zlib
data = open('$work/plots/pad-straight-top.png', 'rb').read()
w, h = struct.unpack('>II', data[16:24])
chunks, i = b'', 8
while i < len(data):
    n = struct.unpack('>I', data[i:i + 4])[0]; kind = data[i + 4:i + 8]
    if kind == b'IDAT': chunks += data[i + 8:i + 8 + n]
    i += 12 + n
raw = zlib.decompress(chunks); stride = 3 * w + 1
rows, prev = [], bytearray(3 * w)
for y in range(h):  # undo the PNG row filters (None, Sub, Up, Average, Paeth)
    f, line = raw[y * stride], bytearray(raw[y * stride + 1:(y + 1) * stride])
    for k in range(len(line)):
        a = line[k - 3] if k >= 3 else 0; b = prev[k]; c = prev[k - 3] if k >= 3 else 0
        p = a + b - c; pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
        line[k] = (line[k] + [0, a, b, (a + b) // 2, a if pa <= pb and pa <= pc else b if pb <= pc else c][f]) & 255
    rows.append(bytes(line)); prev = line
px = lambda x, y: rows[y][3 * x:3 * x + 3]
green = [(x, y) for y in range(h) for x in range(0, w, 4) if px(x, y) == bytes([40, 190, 60])]
assert len(green) > 100, len(green)
near_dark = sum(1 for x, y in green[::10] if any(px(x, yy)[0] < 160 and px(x, yy)[1] < 60 for yy in range(max(0, y - 8), min(h, y + 9))))
assert near_dark >= 0.8 * len(green[::10]), (near_dark, len(green[::10]))"
finish "score picture"

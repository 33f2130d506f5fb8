#!/usr/bin/env bash
# Outputs that survive a kill: `incise replay`, `wrap`, `cut` and `record` are each run once to completion
# (the reference outputs and the run time), then SEEDS times more, killed with SIGKILL after a seeded random
# delay spread over 1.1 x that run time; every other seed first puts a "previous" complete file at each
# output path. After each kill every output path holds nothing, the previous bytes, or the new complete
# file (the reference bytes; for the JSON reports, whose latency figures change from run to run, a document
# that parses to the reference's shape); anything else in the folder is a leftover "<output>.tmp"
# (atomic_file.h: a kill leaves it; it is never at an output path and the next writer truncates it). A
# killed recording is a byte prefix of the reference whose complete lines the trace reader reads back (the
# trace replayed: as many poses as complete lines). A failure prints the command and the seed:
#   kill_test.sh INCISE_BINARY SCENARIOS_DIR [SEEDS] [COMMANDS]   (defaults 20, "replay wrap cut record record-live";
#   "replay-tets" adds the tet tissue's outputs, about 1.4 s a run: in the slow variant; "record-live" a live device,
#   a hid recording played as one for 1 s, whose time stamps come from the clock: compared without them)
set -u
incise=$1
scenarios=$2
seeds=${3:-20}
commands=${4:-replay wrap cut record record-live}
source "$(dirname "$0")/harness.sh"

check "SIGKILL at $seeds seeded moments of each of: $commands" python3 - "$incise" "$scenarios" "$seeds" "$work" $commands <<'PY'
import json, os, random, shutil, signal, subprocess, sys, time

incise, scenarios, seeds, work = sys.argv[1], os.path.abspath(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
names = sys.argv[5:]
COMMANDS = {
    'replay': lambda out: [incise, 'replay', scenarios + '/bunny-straight.json', '--fast', '--out', out],
    'replay-tets': lambda out: [incise, 'replay', scenarios + '/bunny-tets.json', '--fast', '--out', out],
    'wrap': lambda out: [incise, 'wrap', scenarios + '/wrap/sphere-cylinder.json', '--out', out],
    'cut': lambda out: [incise, 'cut', '--format', 'both', '--out', out],
    'record': lambda out: [incise, 'record', scenarios + '/generate/bunny-straight.json', '--out', out + '/trace.csv'],
    # A live device (a hid recording played as one, in real time): 1 s of poses, flushed every 50.
    'record-live': lambda out: [incise, 'record', scenarios + '/bunny-pen-wacom.json', '--device', '056a:0357',
                                '--transport', 'replay:' + scenarios + '/hid/bunny-pen-wacom.hid', '--duration', '1',
                                '--out', out + '/trace.csv'],
}


def poses(data):  # a trace's complete lines, the samples without their (live clock) time_s
    return [l if l.startswith(b'#') or l.startswith(b'time_s') else l.split(b',', 1)[1]
            for l in data.split(b'\n')[:-1]]


def live_prefix(data, ref):  # the poses of the shorter recording a prefix of the longer's, but for the
    a, b = poses(data), poses(ref)  # last: a finished run's last sample is the device's state at its end
    n = min(len(a), len(b)) - 1
    return len(a) > 0 and a[:n] == b[:n]


def files(folder):
    return {os.path.relpath(os.path.join(d, f), folder): open(os.path.join(d, f), 'rb').read()
            for d, _, fs in os.walk(folder) for f in fs}


def run(name, out):  # the run time and when its first file (an output or its .tmp) appeared, in s
    os.makedirs(out, exist_ok=True)
    start, first_s = time.monotonic(), None
    process = subprocess.Popen(COMMANDS[name](out), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    while process.poll() is None:
        if first_s is None and any(fs for _, _, fs in os.walk(out)):
            first_s = time.monotonic() - start
        time.sleep(0.0005)
    assert process.returncode == 0, '%s exited with %d' % (name, process.returncode)
    run_s = time.monotonic() - start
    return run_s, first_s if first_s is not None else run_s


def shape(value):  # a JSON value's structure: keys, list lengths, types
    if isinstance(value, dict):
        return {k: shape(v) for k, v in value.items()}
    if isinstance(value, list):
        return [shape(v) for v in value]
    return type(value).__name__


def json_shape(data, jsonl):
    try:
        text = data.decode()
        if jsonl:
            return [shape(json.loads(line)) for line in text.splitlines()] if text.endswith('\n') else None
        return shape(json.loads(text))
    except ValueError:
        return None


def complete(path, data, ref, exact):
    if exact:
        return data == ref
    return json_shape(data, path.endswith('.jsonl')) == json_shape(ref, path.endswith('.jsonl')) is not None


def trace_reads_back(data, folder):
    lines = data.split(b'\n')[:-1]  # complete lines; a cut last one is dropped by the reader
    samples = [l for l in lines[1:] if not l.startswith(b'#')]
    if not samples:
        return True
    os.makedirs(folder, exist_ok=True)
    trace = os.path.join(folder, 'prefix.csv')
    open(trace, 'wb').write(data)
    scenario = os.path.join(folder, 'prefix.json')
    json.dump({'tissue': {'mesh': os.path.join(scenarios, 'meshes', 'bunny.obj'), 'scale': 0.01},
               'pose_source': {'kind': 'trace', 'path': trace}}, open(scenario, 'w'))
    replay = subprocess.run([incise, 'replay', scenario, '--fast', '--out', os.path.join(folder, 'replayed')],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    # Exit 2 is the reader refusing the trace; 1 a check of the cut (a prefix can end a stroke too short to
    # open a groove), which is not the reader's concern; 0 a run, also one whose poses never touched the tissue.
    if replay.returncode not in (0, 1):
        return print('  the trace reader refused it (exit %d): %s' % (replay.returncode, replay.stderr.strip()))
    poses = json.load(open(os.path.join(folder, 'replayed', 'report.json')))['poses']
    return poses == len(samples) or print('  the trace reader read %d poses of %d lines' % (poses, len(samples)))


def check_outputs(name, folder, ref, exact, previous, finished, replays, tally):
    problems = []
    got = files(folder)
    for path, data in got.items():
        if path not in ref and not (path.endswith('.tmp') and path[:-4] in ref):
            problems.append('%s: not an output and not an output\'s .tmp' % path)
        tally['.tmp left'] += path not in ref
    for path in ref:
        data = got.get(path)
        if data is None:
            ok, kind = not finished and path not in previous, 'absent'
        elif previous.get(path) == data and not finished:
            ok, kind = True, 'previous'
        elif name == 'record-live':
            ok, kind = live_prefix(data, ref[path]), 'new' if finished else 'prefix'
            ok = ok and (replays[0] <= 0 or trace_reads_back(data, folder + '-read'))
            replays[0] -= 1
        elif name == 'record' and not finished and ref[path] != data:
            ok, kind = ref[path].startswith(data), 'prefix'
            ok = ok and (replays[0] <= 0 or trace_reads_back(data, folder + '-read'))
            replays[0] -= 1
        else:
            ok, kind = complete(path, data, ref[path], exact[path]), 'new'
        tally[kind] += 1
        if not ok:
            problems.append('%s: %s' % (path, 'missing' if data is None else 'torn or wrong (%d bytes)' % len(data)))
    return problems


failures = 0
for name in names:
    ref_dir, again = os.path.join(work, 'ref-' + name), os.path.join(work, 'again-' + name)
    run_s, writing_s = run(name, ref_dir)
    run(name, again)
    ref, second = files(ref_dir), files(again)
    exact = {p: ref[p] == second.get(p) for p in ref}
    outcomes, replays = {}, [5]
    tally = dict.fromkeys(['absent', 'previous', 'new', 'prefix', '.tmp left'], 0)
    for seed in range(seeds):
        rng = random.Random('%s:%d' % (name, seed))
        folder = os.path.join(work, '%s-%d' % (name, seed))
        os.makedirs(folder)
        previous = {}
        if seed % 2 == 1:
            for path in ref:
                previous[path] = b'{"previous": %d}\n' % seed if path.endswith('.json') else b'previous %d\n' % seed
                os.makedirs(os.path.dirname(os.path.join(folder, path)), exist_ok=True)
                open(os.path.join(folder, path), 'wb').write(previous[path])
        # Half the kills anywhere in the run, half while it writes (from its first file on).
        delay_s = rng.uniform(0, 1.1 * run_s) if seed % 4 < 2 else rng.uniform(writing_s, run_s)
        process = subprocess.Popen(COMMANDS[name](folder), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        time.sleep(delay_s)
        process.send_signal(signal.SIGKILL)
        code = process.wait()
        finished = code == 0
        problems = check_outputs(name, folder, ref, exact, previous, finished, replays, tally)
        state = 'finished' if finished else 'killed'
        outcomes[state] = outcomes.get(state, 0) + 1
        if problems:
            failures += 1
            print('FAIL %s seed %d (killed after %.3f s of %.3f s; %s): %s' % (name, seed, delay_s, run_s, state,
                                                                                  '; '.join(problems)))
        else:
            shutil.rmtree(folder)
    print('  %s: %.2f s a run, writing from %.2f s, %d seeds: %s; outputs found: %s' % (
        name, run_s, writing_s, seeds, outcomes, tally))
sys.exit(1 if failures else 0)
PY
finish kill

#!/usr/bin/env python3
"""Recall, false clicks and timing of the onset detector on synthetic recordings, beside the
detector it replaced; and its memory on a long recording.

The recordings come from test/calibration/click_recordings.py (a generator sharing no code with
the detector): bouncing-ball sequences with e = 0.9 whose flights shrink from 300 ms to 5 ms
(40 impacts), click shapes of one to three damped sinusoids with decays 0.5-20 ms, room noise, a
spurious weak click, clipping in a third of them (the first clicks at 2 x full scale).  For each
level of ``--snr`` (the quietest impact's peak over the white noise's rms) it prints, over
``--seeds`` recordings, the recall (true clicks with an onset within 2 ms), false clicks per true
click, the spurious click taken, and the timing error (median, 99th percentile, max).  The old
detector is the one of commit ``--old`` (read with ``git show``, run as it was).

``--minutes M`` also writes an M-minute 48 kHz 16-bit WAV (the recordings end to end) and runs
``bounce_times_from_audio`` on it in a fresh process, printing its peak memory (VmHWM) and
wall time (``--seeds 0``: the memory only).

    python bench/bench_onsets.py [--seeds 40] [--snr 10 20 30 100] [--old 97c0e7a] [--minutes 10]
"""
import argparse
import importlib.util
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / 'test' / 'calibration'))
import click_recordings as cr  # noqa: E402

from contact_sim.calibration import audio  # noqa: E402


def old_detector(commit):
    source = subprocess.run(['git', 'show', f'{commit}:contact_sim/calibration/audio.py'],
                            cwd=ROOT, capture_output=True, text=True, check=True).stdout
    path = Path(tempfile.mkdtemp()) / 'old_audio.py'
    path.write_text(source)
    spec = importlib.util.spec_from_file_location('old_audio', path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.detect_onsets


def run(detect, seeds, snr):
    recall, false, spur, errors, clicks = [], [], 0, [], 0
    t0 = time.perf_counter()
    for seed in range(seeds):
        rec = cr.make_recording(seed=seed, loudness=(0.6, 2.0, 0.15)[seed % 3], quietest_snr=snr)
        found = detect(rec.samples, rec.rate).times
        r, f, err = cr.score(found, rec.times)
        recall.append(r * rec.times.size)
        false.append(f * rec.times.size)
        clicks += rec.times.size
        spur += bool(np.any(np.abs(found - rec.spurious) < 2e-3))
        errors.append(err)
    err = np.concatenate(errors) * 1e3
    return (sum(recall) / clicks, sum(false) / clicks, spur, np.median(err),
            np.percentile(err, 99), err.max(), time.perf_counter() - t0, clicks)


def memory(minutes):
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / 'long.wav'
        parts, total = [], 0
        seed = 0
        while total < minutes * 60 * 48000:
            x = cr.make_recording(seed=seed, quietest_snr=30).samples
            parts.append(np.round(x * 32767).astype(np.int16))
            total += x.size
            seed += 1
        audio.write_wav(path, np.concatenate(parts) / 32767.0, 48000, 16)
        del parts
        # VmHWM: the peak resident memory of this process image (ru_maxrss would carry the
        # parent's peak over the fork)
        code = ('import sys, time\n'
                'from contact_sim.calibration import bounce_times_from_audio\n'
                'def hwm():\n'
                '    s = open("/proc/self/status").read()\n'
                '    return int(s.split("VmHWM:")[1].split()[0]) // 1024\n'
                'base = hwm()\n'
                't = time.perf_counter(); o = bounce_times_from_audio(sys.argv[1])\n'
                'print(o.times.size, round(time.perf_counter() - t, 1), hwm(), base)\n')
        out = subprocess.run([sys.executable, '-c', code, str(path)], capture_output=True,
                             text=True, check=True).stdout.split()
        size = os.path.getsize(path) / 2**20
    print(f'{minutes} min of 48 kHz 16-bit mono ({size:.0f} MB, {seed} recordings): {out[0]} '
          f'onsets in {out[1]} s, peak memory {out[2]} MB (VmHWM of the process; {out[3]} MB '
          'after importing contact_sim)')


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--seeds', type=int, default=40)
    parser.add_argument('--snr', type=float, nargs='+', default=[10.0, 20.0, 30.0, 100.0])
    parser.add_argument('--old', default='97c0e7a')
    parser.add_argument('--minutes', type=float, default=0.0)
    args = parser.parse_args()
    detectors = [('new', audio.detect_onsets), (f'old ({args.old})', old_detector(args.old))]
    print(f'{args.seeds} recordings per line, 40 impacts each')
    print(f'{"detector":>16} {"snr":>5} {"recall":>8} {"false":>7} {"spurious":>9} '
          f'{"median ms":>10} {"p99 ms":>7} {"max ms":>7} {"time s":>7}')
    for snr in args.snr if args.seeds > 0 else ():
        for name, detect in detectors:
            r, f, sp, med, p99, mx, wall, _ = run(detect, args.seeds, snr)
            print(f'{name:>16} {snr:5.0f} {100 * r:7.2f}% {100 * f:6.2f}% {sp:5d}/{args.seeds:<3d}'
                  f' {med:10.3f} {p99:7.3f} {mx:7.3f} {wall:7.1f}')
    if args.minutes > 0:
        memory(args.minutes)


if __name__ == '__main__':
    main()

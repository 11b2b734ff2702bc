#!/usr/bin/env python3
"""`contact-sim bounces` over the real recordings of the development set, one line each.

The development set (issue 32) is ``../shared/reference/recordings`` beside the repository (or
``--data DIR``): phyphox workbooks of table-tennis (``pingpong/*.xlsx``) and tennis
(``tennis/*.xls``) drops and a table-tennis WAV (``audio/*.wav``, its hand-checked impacts in
``*_impacts.csv``).  When it is not there the bench says so and exits 0 (a fresh clone has none).

Each recording is run as a user would, in its own process (``contact-sim bounces FILE`` with the ball's mass and radius from the recordings' README, a contact stiffness guessed
for a hollow ball, and ``--holdout 0.3``), and one line printed:

* onsets: the clicks found in the recording (the workbook's events, or the onsets the audio
  detector heard) / kept (the audio detector's impacts) / fitted (after the glitches and the
  micro-bounce cut) / true (for a WAV with a hand-checked list: its impacts matched within
  3 ms in their span, the extra onsets there, and the largest error of those matched);
* the law ranked first, its fit status and the model-adequacy verdict, as printed;
* the hold-out rms of that law on the held-out clicks ("too few": ``--holdout 0.3`` was
  refused for too few clicks, and the command run without it), and the rms e residual the
  adequacy verdict was judged on against the recording's own scatter of e;
* the exit status and the wall time of the command.

    python bench/bench_recordings.py [--data DIR] [--only pingpong|tennis|audio] [--limit N]
"""
import argparse
import re
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / 'bench'))
from _table import run  # noqa: E402

# the balls, from the recordings' README (m, R1); k a guess for a hollow ball's shell
BALLS = {'pingpong': ['--mass', '0.0027', '--radius', '0.02', '--stiffness', '5e4'],
         'tennis': ['--mass', '0.056', '--radius', '0.0335', '--stiffness', '2e4'],
         'audio': ['--mass', '0.0027', '--radius', '0.02', '--stiffness', '5e4']}
PATTERNS = {'pingpong': '*.xlsx', 'tennis': '*.xls', 'audio': '*.wav'}
TOLERANCE = 3e-3     # s: an impact is matched by an onset this close
CLI = 'import sys; from contact_sim.cli import main; sys.exit(main(sys.argv[1:]))'


def _default_data():
    return ROOT.parent / 'shared' / 'reference' / 'recordings'


def _first(pattern, text, group=1):
    m = re.search(pattern, text, re.MULTILINE)
    return m.group(group) if m else None


def _true(path):
    """'matched/listed +extra' for a WAV with a hand-checked list beside it, else '-'."""
    listed = path.with_name(path.stem + '_impacts.csv')
    if not listed.exists():
        return '-'
    from contact_sim.calibration import bounce_times_from_audio
    true = np.loadtxt(listed, delimiter=',', skiprows=1, usecols=-1, ndmin=1)
    times = bounce_times_from_audio(path).times
    lo, hi = true.min() - TOLERANCE, true.max() + TOLERANCE
    inside = times[(times > lo) & (times < hi)]
    used = np.zeros(inside.size, bool)
    errors = []
    for t in true:
        free = np.where(used, np.inf, np.abs(inside - t))
        if free.size and free.min() <= TOLERANCE:
            used[int(np.argmin(free))] = True
            errors.append(free.min())
    worst = f' ({max(errors) * 1e3:.2f} ms)' if errors else ''
    return f'{len(errors)}/{true.size} +{int((~used).sum())}{worst}'


def summary(out):
    """The figures of one ``contact-sim bounces`` report (its stdout), as the table's texts:
    found, kept, fitted, law, status, verdict (``adequate (hold-out)``), held (the first law's
    hold-out rms, ms) and e (its rms e residual / the recording's own scatter of e)."""
    clicks = sum(int(n) for n in re.findall(r'^# sequence \d+: .*, (\d+) clicks', out, re.M))
    heard = _first(r'^# audio .*: (\d+) onset\(s\) found, (\d+) kept', out)
    kept = _first(r'^# audio .*: (\d+) onset\(s\) found, (\d+) kept', out, 2)
    left = len(re.findall(r': (?:spurious|doubled) click at .*\(left out\)', out))
    left += sum(int(n) for n in re.findall(r'the last (\d+) click\(s\) left out', out))
    law = _first(r'^# laws ranked.*\n(\w+): ', out) or '-'
    verdict, on = (_first(r'^model adequacy \(([^)]+)\): ([^:]+):', out, g) for g in (2, 1))
    held = _first(r'^hold-out rms \(%s\): ([\d.]+) ms' % re.escape(law), out) \
        if law != '-' else None
    misfit = _first(r"rms e residual of (\S+) against the recording's own scatter", out)
    scatter = _first(r"rms e residual of \S+ against the recording's own scatter (\S+) ", out)
    return {'found': heard or (str(clicks) if clicks else '-'),
            'kept': kept or (str(clicks) if clicks else '-'),
            'fitted': str(clicks - left) if clicks else '-', 'law': law,
            'status': _first(r'^# laws ranked.*\n\w+: .*\n(?:  drag.*\n)?\s+fit: ([\w-]+)',
                             out) or '-',
            'verdict': f'{verdict} ({on})' if verdict and on != 'none' else (verdict or '-'),
            'held': held or '-', 'e': f'{misfit} / {scatter}' if misfit and scatter else '-'}


def _row(kind, path):
    command = [sys.executable, '-c', CLI, 'bounces', str(path), *BALLS[kind], '--holdout', '0.3']
    start = time.perf_counter()
    done = subprocess.run(command, capture_output=True, text=True, cwd=ROOT)
    refused = done.returncode == 2 and 'holdout' in done.stderr
    if refused:          # too few clicks to hold some out: the fit alone
        done = subprocess.run(command[:-2], capture_output=True, text=True, cwd=ROOT)
    wall = time.perf_counter() - start
    got = summary(done.stdout)
    holdout = 'too few' if refused else got['held']
    true = _true(path) if kind == 'audio' else '-'
    error = '' if done.returncode in (0, 3) else \
        (done.stderr.strip().splitlines() or ['?'])[-1][:60]
    return (f'{kind + "/" + path.name:<32} {got["found"]:>6} {got["kept"]:>5} '
            f'{got["fitted"]:>6} {true:>18} {got["law"]:<18} {got["status"]:<14} '
            f'{got["verdict"]:<20} {holdout:>8} {got["e"]:>16} {done.returncode:>4} '
            f'{wall:6.1f} {error}')


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--data', type=Path, default=_default_data(),
                        help='the development set (default ../shared/reference/recordings)')
    parser.add_argument('--only', choices=sorted(PATTERNS), action='append')
    parser.add_argument('--limit', type=int, default=0, help='at most N files per folder')
    args = parser.parse_args()
    if not args.data.is_dir():
        print(f'no development set at {args.data}: nothing to run (give --data DIR)')
        return 0
    print(f'contact-sim bounces over {args.data}; per folder: {BALLS}, --holdout 0.3')
    print('onsets: found / kept (the audio detector\'s impacts) / fitted (after glitches and the '
          'micro-bounce cut) / true (matched within 3 ms of the hand-checked list, +extra, '
          'largest error)')
    print('adequacy: the verdict (on the fit, or on the held-out flights); hold-out: the first '
          'law\'s rms on the held-out clicks (ms); e: its rms e residual / the recording\'s own '
          'scatter of e, on what the verdict was judged')
    print(f'{"recording":<32} {"found":>6} {"kept":>5} {"fitted":>6} {"true":>18} '
          f'{"law ranked first":<18} {"fit":<14} {"adequacy":<20} {"hold-out":>8} '
          f'{"e resid/scatter":>16} '
          f'{"exit":>4} {"wall s":>6}')
    for kind in args.only or ('audio', 'pingpong', 'tennis'):
        files = sorted((args.data / kind).glob(PATTERNS[kind]))
        for path in files[:args.limit or None]:
            print(_row(kind, path), flush=True)
    return 0


if __name__ == '__main__':
    sys.exit(run(main))

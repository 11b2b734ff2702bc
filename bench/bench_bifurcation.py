#!/usr/bin/env python3
"""Wall time of a bifurcation diagram with full contact dynamics: 200 values of Γ x 300 bounces
(after 100 transient bounces) of the Azad-Featherstone sphere of ``examples/bifurcation.py`` on a
10 Hz table, swept on local processes (``sweep``).  Every bounce is a full contact phase (compiled
engine) and an exact flight; no impact map.  Every bounce goes through the drop engine's modes
and transition table (issue 36: one engine, no compiled bounce loop); beside this run's figures,
the last ones published with the compiled bounce loop it replaced (``PUBLISHED``).  Target: the
diagram (200 values x 400 bounces) within 3 s on this machine's 2 cores.

    python bench/bench_bifurcation.py [--points 200] [--bounces 300] [--workers 2] [--law ...]
"""
import argparse
import os
import resource
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'examples'))
from bifurcation import tables  # noqa: E402

from contact_sim.drop.sweeps import bifurcation_diagram  # noqa: E402

TARGET_WALL = 3.0     # s, the default diagram on 2 workers (issue 36)
# the default diagram with the compiled bounce loop (mode_train, removed by issue 36), as
# docs/bench_results/bench_bifurcation.md published it on 2026-12-04 14:11 UTC (load 0.7)
PUBLISHED = {'wall': 1.5, 'cpu': 2.9}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument('--points', type=int, default=200)
    ap.add_argument('--bounces', type=int, default=300)
    ap.add_argument('--transient', type=int, default=100)
    ap.add_argument('--workers', type=int, default=2)
    ap.add_argument('--law', default='azad_featherstone', choices=('azad_featherstone', 'linear'))
    ap.add_argument('--gamma', type=float, nargs=2, default=(0.3, 4.0))
    args = ap.parse_args()
    table = tables(args.bounces, args.transient)[args.law]
    gammas = np.linspace(*args.gamma, args.points)
    load = os.getloadavg()[0]
    start = time.perf_counter()
    x, phases = bifurcation_diagram(table, gammas, max_workers=args.workers)
    wall = time.perf_counter() - start
    # the workers' CPU time (the pool is shut down and waited for): on the shared machine the
    # wall time also counts the other engineers' load, the CPU time far less
    cpu = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = cpu.ru_utime + cpu.ru_stime
    print(f'{args.law}: {args.points} values of Gamma in [{args.gamma[0]:g}, {args.gamma[1]:g}] '
          f'x {args.bounces} bounces (+{args.transient} transient), {args.workers} worker '
          f'processes: {wall:.1f} s wall, {cpu:.1f} s CPU of the workers '
          f'({cpu / args.workers:.1f} s each), {len(phases)} points; load average '
          f'{load:.2f} before, {os.getloadavg()[0]:.2f} after; target <= {TARGET_WALL:g} s wall '
          f'({"met" if wall <= TARGET_WALL else "NOT met"})')
    print(f'published with the compiled bounce loop: {PUBLISHED["wall"]:.1f} s wall, '
          f'{PUBLISHED["cpu"]:.1f} s CPU of the workers; this run: {cpu / PUBLISHED["cpu"]:.2f}x '
          f'the CPU time, {cpu / (args.points * (args.bounces + args.transient)) * 1e6:.0f} us '
          f'of CPU a bounce')


if __name__ == '__main__':
    from _table import run   # --markdown OUT: the table for the docs (bench/_table.py)
    run(main)

#!/usr/bin/env python3
"""The bifurcation diagram of ``bench_bifurcation.py`` on ``concurrent.futures`` and on a local
Dask cluster, with the overhead per task of each.

The same ``bifurcation_diagram`` (200 values of Γ x 300 bounces after 100 transient ones, one task
per Γ) runs through ``sweep(..., executor=...)`` on a ``ProcessPoolExecutor(2)`` and on
``distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True)`` through
``Client.get_executor()``; both must give identical bounce data (the same code on the same
machine).  Both executors are started and warmed first (every worker imports the engine and
loads its compiled kernels), so the diagram's time is the sweep's alone (the start is printed
apart), then run in turn, ``--repeat`` times, so that both see the same load (the idle one
waits: Dask's cluster keeps its heartbeats).
The overhead per task is measured on the same warm executor with no-op tasks: ``--noop`` of them
submitted at once through ``sweep`` (what a sweep pays per task, both workers busy) and 200 one
at a time (one task's round trip).  CPU time is read from /proc for every worker process and for
this process (the pool's feeder thread, or Dask's client and scheduler, which LocalCluster runs
here).  Best of the runs for each figure.  Without Dask installed the futures part runs and the bench
says so and exits 0.

    python bench/bench_cluster.py [--points 200] [--bounces 300] [--repeat 5] [--noop 2000]
"""
import argparse
import contextlib
import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'examples'))
from bifurcation import tables  # noqa: E402

from contact_sim.drop.sweeps import bifurcation_diagram, sweep  # noqa: E402
from contact_sim.model import LINEAR  # noqa: E402

ROUND_TRIPS = 200
WORKERS = 2
_TICK = os.sysconf('SC_CLK_TCK')


def _noop(value):
    return value


def _warm(_=None):
    """Import the engine and load its compiled kernels in this worker; its pid."""
    from contact_sim.drop.table import VibratingTable
    from contact_sim.model.contact import Contact
    VibratingTable(Contact(LINEAR, 1e7, 10.0), 0.066, 10.0, bounces=1, transient=1)(1.2)
    return os.getpid()


def cpu_seconds(pid):
    """User + system CPU time of process ``pid`` in s (Linux: /proc/<pid>/stat)."""
    with open(f'/proc/{pid}/stat') as f:
        fields = f.read().rsplit(')', 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / _TICK


class Measured:
    """One warm executor (its worker pids), its best figures so far and its diagram's points."""

    def __init__(self, name, executor, pids, started):
        self.name, self.executor, self.pids = name, executor, pids
        self.best, self.points, self.walls = {'start': started}, None, []

    def cpu(self):
        return sum(cpu_seconds(p) for p in self.pids), cpu_seconds(os.getpid())

    def once(self, table, gammas, noop):
        """One run of the diagram and of the no-op batches; keeps each figure's best."""
        best, executor = self.best, self.executor
        workers0, here0 = self.cpu()
        start = time.perf_counter()
        result = bifurcation_diagram(table, gammas, executor=executor)
        wall = time.perf_counter() - start
        workers1, here1 = self.cpu()
        self.walls.append(wall)
        if self.points is None:
            self.points = result
        elif not all(np.array_equal(a, b) for a, b in zip(self.points, result)):
            raise SystemExit(f'{self.name} gave different bounce data on a second run')
        if wall < best.get('wall', np.inf):
            best.update(wall=wall, workers_cpu=workers1 - workers0, here_cpu=here1 - here0)
        start = time.perf_counter()
        assert sweep(_noop, range(noop), executor=executor) == list(range(noop))
        best['per_task'] = min(best.get('per_task', np.inf), (time.perf_counter() - start) / noop)
        start = time.perf_counter()
        for i in range(ROUND_TRIPS):
            assert executor.submit(_noop, i).result() == i
        best['round_trip'] = min(best.get('round_trip', np.inf),
                                 (time.perf_counter() - start) / ROUND_TRIPS)


def start_futures(stack):
    start = time.perf_counter()
    pool = stack.enter_context(ProcessPoolExecutor(WORKERS, initializer=_warm))
    list(pool.map(_warm, range(WORKERS)))   # starts the workers (each warmed at its start)
    return Measured(f'concurrent.futures.ProcessPoolExecutor({WORKERS})', pool,
                    sorted(pool._processes), time.perf_counter() - start)


def start_dask(stack, distributed):
    import logging
    start = time.perf_counter()
    cluster = stack.enter_context(distributed.LocalCluster(
        n_workers=WORKERS, threads_per_worker=1, processes=True, dashboard_address=None,
        silence_logs=logging.ERROR))
    client = stack.enter_context(distributed.Client(cluster))
    pids = sorted(client.run(_warm).values())
    return Measured(f'distributed {distributed.__version__} LocalCluster({WORKERS} workers x 1 '
                    'thread, processes), Client.get_executor()', client.get_executor(), pids,
                    time.perf_counter() - start)


def row(name, figures, tasks):
    task = figures['wall'] * WORKERS / tasks      # the mean task's wall time on a worker
    return (f'| {name} | {figures["start"]:.2f} | {figures["wall"]:.1f} | '
            f'{figures["workers_cpu"]:.1f} | {figures["here_cpu"]:.2f} | {tasks} | '
            f'{task * 1e3:.0f} | {figures["per_task"] * 1e6:.0f} | '
            f'{figures["round_trip"] * 1e3:.2f} | {figures["per_task"] / task * 100:.2f} % |')


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument('--points', type=int, default=200)
    ap.add_argument('--bounces', type=int, default=300)
    ap.add_argument('--transient', type=int, default=100)
    ap.add_argument('--law', default='azad_featherstone', choices=('azad_featherstone', 'linear'))
    ap.add_argument('--gamma', type=float, nargs=2, default=(0.3, 4.0))
    ap.add_argument('--repeat', type=int, default=5, help='best of this many runs')
    ap.add_argument('--noop', type=int, default=2000, help='no-op tasks for the overhead')
    args = ap.parse_args()
    table = tables(args.bounces, args.transient)[args.law]
    gammas = np.linspace(*args.gamma, args.points)
    loads = [os.getloadavg()]
    print(f'{args.law}: {args.points} values of Gamma in [{args.gamma[0]:g}, {args.gamma[1]:g}] '
          f'x {args.bounces} bounces (+{args.transient} transient), one task per Gamma, '
          f'{WORKERS} workers; best of {args.repeat}; overhead from {args.noop} no-op tasks '
          f'submitted at once and {ROUND_TRIPS} one at a time')
    try:
        import distributed
    except ImportError:
        distributed = None
    with contextlib.ExitStack() as stack:
        runs = [start_futures(stack)]
        if distributed is not None:
            runs.append(start_dask(stack, distributed))
        for _ in range(args.repeat):    # the executors in turn, so both see the same load
            for measured in runs:
                measured.once(table, gammas, args.noop)
                loads.append(os.getloadavg())
    print('\n| executor | start + warm s | diagram wall s | workers CPU s | this process CPU s '
          '| tasks | mean task ms (wall x 2 / tasks) | overhead per task µs (no-ops at once) '
          '| round trip ms (one no-op) | overhead / mean task |')
    print('|---|---|---|---|---|---|---|---|---|---|')
    for measured in runs:
        print(row(measured.name, measured.best, args.points))
    print()
    for measured in runs:
        print(f'{measured.name}: diagram wall s of each run ' +
              ', '.join(f'{w:.1f}' for w in measured.walls))
    print(f'\n{len(runs[0].points[1])} points each; 1-minute load average from '
          f'{min(la[0] for la in loads):.2f} to {max(la[0] for la in loads):.2f} (at the start '
          f'and after each run: ' + ', '.join('%.2f' % la[0] for la in loads) + ')')
    if distributed is None:
        print('Dask is not installed (pip install ".[dask]"): only concurrent.futures measured')
        return 0
    same = all(np.array_equal(a, b) for a, b in zip(runs[0].points, runs[1].points))
    print('bounce data identical on both executors: ' + ('yes' if same else 'NO'))
    return 0 if same else 1


if __name__ == '__main__':
    from _table import run   # --markdown OUT: the table for the docs (bench/_table.py)
    sys.exit(run(main))

#!/usr/bin/env python3
"""The compiled contact engine against the issue-10 targets, and the peers' drop problem.

Prints, each timed ``--repeat`` times (best and median: the machine is shared, so the median is
noisy and the best is the figure to compare):

* the peers' problem: a steel ball (R = 12.7 mm, steel density) on a flat cast-iron plate, Hertz
  stiffness, Hunt-Crossley damping tuned to e(1 m/s) = 0.8, dropped from 1 m under 9.81 m/s²,
  5 s simulated: wall time, integrator steps and bounces, beside the peers' figures quoted in
  issue 10 (measured there, not re-run here); target <= 0.37 s with 378 bounces;
* the paper's Sec. II-C drop (5 s): milliseconds per simulated second; target <= 5 ms;
* ``simulate_impact``: microseconds per impact; target <= 100 us;
* with ``--reference``, the same three on the scipy reference engine (slow: about 10 s);
* with ``--compile-time``, the kernels' compile time (empty cache) and the load time from the
  cache, each in a fresh process;
* with ``--stiff`` (alone), heavily damped drops (the paper's contact, larger λ): the compiled DOP853
  forced on every phase against the scipy engine (Radau above ζ = 30): the measurement behind
  ``phase.COMPILED_STIFF_DAMPING``.

    python bench/bench_peers.py [--repeat 10] [--reference] [--compile-time] [--stiff]
"""
import argparse
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time

import contact_sim as cs
from contact_sim import drop, phase

# quoted from issue 10 (wall s for 5 s, steps), measured there on this machine
PEERS = [('Drake continuous RK3, accuracy 1e-6', 1.84, 28192),
         ('OpenSim RKMerson, accuracy 1e-7', 2.85, 12386),
         ('contact_sim before issue 10 (scipy)', 4.43, 10192)]
TARGET_PEERS_S, TARGET_BOUNCES, TARGET_PAPER_MS, TARGET_IMPACT_US = 0.37, 378, 5.0, 100.0


def peers_contact():
    radius = 0.0127
    mass = cs.sphere_mass(cs.get_material('steel').density, radius)
    hertz = cs.Contact.from_materials(cs.HUNT_CROSSLEY, 'steel', 'cast_iron', radius)
    lam = cs.damping_for_restitution(cs.HUNT_CROSSLEY, hertz.stiffness, mass, 0.8, 1.0)
    return cs.Contact(cs.HUNT_CROSSLEY, hertz.stiffness, lam), mass


def timed(func, repeat):
    """(best s, median s, last result) of ``repeat`` calls."""
    walls = []
    out = None
    for _ in range(repeat):
        start = time.perf_counter()
        out = func()
        walls.append(time.perf_counter() - start)
    return min(walls), statistics.median(walls), out


def impact_cases():
    paper = cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 1e5)
    steel_iron = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron', 0.0127,
                                           damping_factor=8.87e5)
    hc, mass = peers_contact()
    return [('azad_featherstone paper, 1 m/s', paper, 0.066, 1.0, 0.0),
            ('azad_featherstone paper, 4.47 m/s, g', paper, 0.066, 4.47, 10.0),
            ('azad_featherstone steel/iron, 0.1 m/s', steel_iron, 0.06735, 0.1, 0.0),
            ('hunt_crossley peers, 4.43 m/s, g', hc, mass, 4.43, 9.81),
            ('linear, zeta 0.5', cs.Contact(cs.LINEAR, 1e6, 0.5 * math.sqrt(1e6)), 1.0, 1.0, 0.0)]


def run_engine(engine, repeat):
    contact, mass = peers_contact()
    paper = cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 1e5)
    with phase.use_engine(engine):
        best, median, res = timed(
            lambda: cs.simulate_drop(contact, mass, 1.0, gravity=9.81, duration=5.0), repeat)
        bounces = len(res.apex_heights)
        print(f'\n[{engine}] peers\' problem (Hunt-Crossley, e(1 m/s) = 0.8, 1 m, 5 s)')
        print(f'  wall best {best:.4f} s, median {median:.4f} s; {res.steps} steps, '
              f'{bounces} bounces; {1e6 * best / res.steps:.1f} us per step (best)')
        print(f'  target <= {TARGET_PEERS_S} s with {TARGET_BOUNCES} bounces: '
              f'{"met" if best <= TARGET_PEERS_S and bounces == TARGET_BOUNCES else "NOT met"}; '
              f'{PEERS[0][1] / best:.1f}x faster than the faithful Drake setting (best)')
        best, median, res = timed(
            lambda: cs.simulate_drop(paper, 0.066, 1.0, gravity=10.0, duration=5.0), repeat)
        print(f'[{engine}] paper drop (Sec. II-C, 5 s): {1e3 * best / 5.0:.2f} ms per simulated '
              f'second best, {1e3 * median / 5.0:.2f} median; {res.steps} steps, '
              f'{len(res.apex_heights)} bounces; target <= {TARGET_PAPER_MS} ms: '
              f'{"met" if 1e3 * best / 5.0 <= TARGET_PAPER_MS else "NOT met"}')
        wall, flight = flight_share(paper)
        print(f'[{engine}] paper drop, one more run: {1e3 * wall:.1f} ms, of which '
              f'{1e3 * flight:.1f} ms in the flights\' search for the next contact '
              f'(plate.flights.touch_time, Python)')
        print(f'[{engine}] simulate_impact (us per impact, best / median of {repeat} x n calls)')
        worst = 0.0
        for name, c, m, v, g in impact_cases():
            n = 200 if engine == 'compiled' else 5
            best, median, r = timed(lambda: [cs.simulate_impact(c, m, v, gravity=g)
                                             for _ in range(n)], repeat)
            worst = max(worst, 1e6 * best / n)
            print(f'  {name:<40} {1e6 * best / n:9.1f} {1e6 * median / n:9.1f}   '
                  f'{r[0].steps:4d} steps  e = {r[0].restitution:.10f}')
        print(f'  target <= {TARGET_IMPACT_US} us per impact: '
              f'{"met" if worst <= TARGET_IMPACT_US else "NOT met"} (slowest case, best)')


def flight_share(contact):
    """(wall s, s spent in the fixed plate's touch-time search, plate.flights.touch_time) of one
    paper drop."""
    flights = drop.plate.flights
    original = flights.touch_time
    spent = [0.0]

    def timed_search(z, zdot, gravity, contact):
        start = time.perf_counter()
        try:
            return original(z, zdot, gravity, contact)
        finally:
            spent[0] += time.perf_counter() - start

    flights.touch_time = timed_search
    try:
        start = time.perf_counter()
        cs.simulate_drop(contact, 0.066, 1.0, gravity=10.0, duration=5.0)
        return time.perf_counter() - start, spent[0]
    finally:
        flights.touch_time = original


def compile_times():
    """Seconds to import contact_sim.phase.compiled with an empty cache and with the cache written."""
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        out = []
        for _ in range(2):
            start = time.perf_counter()
            subprocess.run([sys.executable, '-c', 'import contact_sim.phase.compiled'], env=env,
                           check=True)
            out.append(time.perf_counter() - start)
    return out


def stiff_drops():
    """Heavily damped drops: compiled DOP853 on every phase against the scipy engine's Radau."""
    print('heavily damped drops (paper contact, 66 g, 1 m, g = 10, 5 s), one run each:')
    print(f'{"lambda":>8} {"zeta":>7} {"DOP853 compiled":>24} {"scipy engine (Radau)":>24}')
    saved = phase.COMPILED_STIFF_DAMPING
    for lam in (1e7, 2.5e7, 5e7, 1e8, 1e9):
        contact = cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, lam)
        zeta = phase.phase_scales(contact, 0.066, 10.0, 0.0, math.sqrt(20.0)).zeta
        cells = []
        for engine in phase.ENGINES:
            phase.COMPILED_STIFF_DAMPING = math.inf
            try:
                with phase.use_engine(engine):
                    start = time.perf_counter()
                    res = cs.simulate_drop(contact, 0.066, 1.0, gravity=10.0, duration=5.0)
                    wall = time.perf_counter() - start
            finally:
                phase.COMPILED_STIFF_DAMPING = saved
            cells.append(f'{res.steps:7d} steps {1e3 * wall:8.1f} ms')
        print(f'{lam:8.1e} {zeta:7.1f} {cells[0]:>24} {cells[1]:>24}')


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--repeat', type=int, default=10)
    parser.add_argument('--reference', action='store_true',
                        help='also time the scipy reference engine (slow)')
    parser.add_argument('--compile-time', action='store_true',
                        help='time the kernels\' compilation and their load from the cache')
    parser.add_argument('--stiff', action='store_true',
                        help='heavily damped drops: compiled DOP853 against scipy\'s Radau')
    args = parser.parse_args()
    if args.stiff:
        stiff_drops()
        return
    print('Peers\' figures, quoted from issue 10 (measured there, not re-run here):')
    for name, wall, steps in PEERS:
        print(f'  {name:<38} {wall:5.2f} s  {steps:6d} steps  {1e6 * wall / steps:4.0f} us/step')
    print(f'machine: {os.cpu_count()} cores, shared (figures are noisy; compare the best)')
    run_engine('compiled', args.repeat)
    if args.reference:
        run_engine('scipy', max(1, min(args.repeat, 2)))
    if args.compile_time:
        cold, warm = compile_times()
        print(f'\na new process running "import contact_sim.phase.compiled" (Python, numpy, scipy, '
              f'numba and the kernels): {cold:.1f} s with an empty numba cache (compiling), '
              f'{warm:.2f} s with the cache written (loading)')


if __name__ == '__main__':
    from _table import run   # --markdown OUT: the table for the docs (bench/_table.py)
    run(main)

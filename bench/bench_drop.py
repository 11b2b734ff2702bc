#!/usr/bin/env python3
"""The Sec. II-C drop (66 g, 1 m, g = 10, k = 1e10, λ = 1e5, 5 s): our engine against what a
user would write, a ``scipy.integrate.solve_ivp(method="Radau", events=...)`` loop restarted at
every contact event, on the same clamped force law (eq. 11).  Prints integrator steps, wall time,
bounce counts and the error of the first restitution against the exact value, for our compiled
engine (the default) and for our scipy reference engine (``phase.use_engine("scipy")``).

    python bench/bench_drop.py [--rtols 1e-6 1e-8 1e-10] [--repeat 3]
"""
import argparse
import math
import time

import numpy as np
from scipy.integrate import solve_ivp

import contact_sim as cs
from contact_sim import phase

M, H, G, K, LAM, T_END = 0.066, 1.0, 10.0, 1e10, 1e5, 5.0


def baseline(rtol, atol):
    """Radau with terminal events where the clamped force switches on or off, restarted."""
    def rhs(t, y):
        z, v = y
        force = math.sqrt(z) * max(K * z + LAM * v, 0.0) if z > 0.0 else 0.0
        return [v, G - force / M]

    def force_on(t, y):            # > 0 exactly when the clamped force is positive
        return min(y[0], K * y[0] + LAM * y[1])

    t, y, in_contact = 0.0, np.array([-H, 0.0]), False
    steps, impacts, apexes = 0, [], []
    while t < T_END and len(impacts) < 10_000:
        force_on.terminal, force_on.direction = True, (-1 if in_contact else 1)
        sol = solve_ivp(rhs, (t, T_END), y, method='Radau', events=force_on, rtol=rtol,
                        atol=atol, max_step=0.01)
        steps += len(sol.t) - 1
        if sol.status != 1:
            break
        t, y = float(sol.t_events[0][0]), sol.y_events[0][0].copy()
        if in_contact:
            impacts[-1]['rebound'] = -y[1]
            if y[1] < 0:
                apexes.append(-(y[0] - y[1] ** 2 / (2 * G)))
        else:
            impacts.append({'time': t, 'speed': y[1]})
        in_contact = not in_contact
    return steps, impacts, apexes


def ours(rtol, engine='compiled'):
    with phase.use_engine(engine):
        result = cs.simulate_drop(cs.Contact(cs.AZAD_FEATHERSTONE, K, LAM), M, H, gravity=G,
                                  duration=T_END, rtol=rtol)
    impacts = [{'time': i.time, 'speed': i.impact_speed, 'rebound': i.rebound_speed}
               for i in result.impacts]
    return result.steps, impacts, list(result.apex_heights)


def micro_bounces(apexes):
    apexes = np.asarray(apexes)
    below = np.flatnonzero(apexes < 1e-3)
    return int(apexes.size - below[0]) if below.size else 0


def timed(func, repeat):
    best = math.inf
    for _ in range(repeat):
        start = time.perf_counter()
        out = func()
        best = min(best, time.perf_counter() - start)
    return best, out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--rtols', type=float, nargs='+', default=[1e-6, 1e-8, 1e-10],
                        help='relative tolerances, each used by both engines')
    parser.add_argument('--repeat', type=int, default=3)
    args = parser.parse_args()
    exact_first = cs.simulate_impact(cs.Contact(cs.AZAD_FEATHERSTONE, K, LAM), M,
                                     math.sqrt(2 * G * H), gravity=G).restitution
    print(f'Sec. II-C drop, 5 s simulated; wall time is the best of {args.repeat} runs')
    print(f'{"rtol":>6} {"engine":<26} {"steps":>7} {"wall (s)":>9} {"bounces":>8} '
          f'{"micro":>6} {"|e1 - exact|":>13}')
    for rtol in args.rtols:
        rows = []
        for name, func in (('contact_sim', lambda: ours(rtol)),
                           ('solve_ivp Radau + events', lambda: baseline(rtol, [1e-14, 1e-10])),
                           ('contact_sim, scipy engine', lambda: ours(rtol, 'scipy'))):
            wall, (steps, impacts, apexes) = timed(func, args.repeat)
            first = impacts[0]['rebound'] / impacts[0]['speed']
            rows.append((steps, wall))
            print(f'{rtol:6.0e} {name:<26} {steps:7d} {wall:9.4f} {len(apexes):8d} '
                  f'{micro_bounces(apexes):6d} {abs(first - exact_first):13.2e}')
        (s_ours, w_ours), (s_base, w_base), (_, w_ref) = rows
        print(f'{"":6} steps ratio ours/baseline = {s_ours / s_base:.3f}, '
              f'wall-time speed-up = {w_base / w_ours:.1f}x, '
              f'{1e3 * w_ours / T_END:.2f} ms per simulated second '
              f'({w_ref / w_ours:.0f}x faster than the scipy engine)')


if __name__ == '__main__':
    from _table import run   # --markdown OUT: the table for the docs (bench/_table.py)
    run(main)

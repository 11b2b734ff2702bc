#!/usr/bin/env python3
"""What one bounce costs, and what its physics costs: the issue-21 figures, on the one drop engine
(issue 36: every bounce through the modes and the transition table, no compiled bounce loop).

Prints, each the best of ``--repeat`` runs of CPU time (the machine is shared: the best CPU time
is the figure to compare; the load average is printed beside it):

* the kernel: one contact phase's integrator steps in ``phase.compiled.run`` alone (state and
  parameters built beforehand), µs per step and per phase;
* one ``simulate_impact`` of the same contact (µs), and its ratio to the kernel time of its
  steps (target <= 3);
* a bounce in a drop on the fixed plate (``simulate_drop``, 20 s of the contact of
  ``examples/bifurcation.py``), µs per bounce and its ratio to one ``simulate_impact`` at the
  drop's mean impact speed (target <= 1.5);
* the same for the peers' problem of ``bench_peers.py`` (a Hunt-Crossley steel ball dropped from
  1 m, 5 s);
* a bounce on a vibrating table (``VibratingTable.run`` at Γ = 2, 400 impacts), µs per bounce and
  its ratio to ``simulate_impact``; and the same orbit (40 s) with its flights planned in
  compiled code beside the Python reference search (``flights.gap_flight``);
* the same 40 s on a commanded plate following the table as set-points (its (p, ṗ) sampled 20
  times a period, ``CommandedPlate``'s C¹ piecewise quadratic between them; the plate built
  before the clock starts), with compiled flights and with the reference flights; and one
  flight's plan over it alone (``mode_flight.Flight``, 400 flights from random states above the
  plate).

Beside each figure: the last one published with the compiled bounce loop that issue 36 removed
(``PUBLISHED``, docs/bench_results/bench_bounce.md of 2026-12-04 14:11 UTC, load 0.6), and the
ratio of this run's to it (a second machine was to be kept only if the one engine could not come
within 1.5x of it).  A loaded machine inflates this run's figures, not the published ones.

    python bench/bench_bounce.py [--repeat 5]
"""
import argparse
import math
from dataclasses import dataclass
import os
import sys
import time

import numpy as np

import contact_sim as cs
from contact_sim import phase
from contact_sim.drop.engine import DropSimulation
from contact_sim.drop.mode_flight import Flight
from contact_sim.drop.plate import CommandedPlate, PlateMotion, SinusoidalPlate
from contact_sim.drop.table import VibratingTable, period_one_threshold
from contact_sim.phase import compiled

sys.path.insert(0, os.path.dirname(__file__))
from bench_peers import peers_contact  # noqa: E402

MASS, STIFFNESS, E_1MS, FREQUENCY = 0.066, 1e10, 0.7, 10.0
TARGET_IMPACT_OVER_KERNEL, TARGET_BOUNCE_OVER_IMPACT = 3.0, 1.5
TARGET_OVER_TRAINS = 1.5
# the last figures published with the compiled bounce loop (mode_train, removed by issue 36):
# docs/bench_results/bench_bounce.md, 2026-12-04 14:11 UTC, load 0.6; µs a bounce, ms a drop
PUBLISHED = {'fixed': 42.5, 'peers': 27.6, 'table': 37.7, 'commanded': 48.0,
             'fixed drop ms': 1.401, 'fixed drop ms, Python modes': 2.008,
             'peers drop ms': 10.417, 'peers drop ms, Python modes': 18.403,
             'table 40 s': 42.8, 'commanded 40 s, Python modes': 70.3}


@dataclass(frozen=True)
class ReferenceTable(SinusoidalPlate):
    """The table with its flights planned by the Python reference (``flights.gap_flight``)."""

    def plan_flight(self, flight, z, zdot, contact, drag_rates, after_lift_off):
        return PlateMotion.plan_flight(self, flight, z, zdot, contact, drag_rates,
                                       after_lift_off)


@dataclass(frozen=True)
class ReferenceCommandedPlate(CommandedPlate):
    """A commanded plate with its flights planned by the Python path (``flights.gap_flight``)."""

    def plan_flight(self, flight, z, zdot, contact, drag_rates, after_lift_off):
        return PlateMotion.plan_flight(self, flight, z, zdot, contact, drag_rates,
                                       after_lift_off)


def sampled_table(amplitude, frequency, phase, duration, per_period=20):
    """The set-points (times s, positions m, velocities m/s) of the table a sin(2π f t + ϕ)
    sampled ``per_period`` times a period over [0, duration]."""
    w = 2.0 * math.pi * frequency
    t = np.arange(int(duration * frequency * per_period) + 1) / (frequency * per_period)
    return (tuple(t), tuple(amplitude * np.sin(w * t + phase)),
            tuple(amplitude * w * np.cos(w * t + phase)))


def best_of(func, repeat):
    """(best s, last result) of ``repeat`` calls: CPU time of this process
    (``time.process_time``), which another engineer's load on the shared cores inflates far
    less than the wall time (both are single-threaded here)."""
    best, out = math.inf, None
    for _ in range(repeat):
        start = time.process_time()
        out = func()
        best = min(best, time.process_time() - start)
    return best, out


def the_contact():
    lam = cs.damping_for_restitution(cs.AZAD_FEATHERSTONE, STIFFNESS, MASS, E_1MS, 1.0)
    return cs.Contact(cs.AZAD_FEATHERSTONE, STIFFNESS, lam)


def kernel_time(contact, mass, speed, gravity, repeat):
    """(s per phase, steps) of ``compiled.run`` alone on a prepared phase, to lift-off."""
    ph = phase.contact_phase(contact, mass, gravity, 0.0, 0.0, speed, keep_points=False)
    state0 = ph._st.copy()
    st, k, f, par, buf = ph._st, ph._k, ph._f, ph._par, ph._buffer
    loops = 200

    def many():
        for _ in range(loops):
            st[:] = state0
            compiled.run(st, k, f, par, buf, math.inf, compiled.MAX_STEPS, -math.inf)
        return int(st[compiled.S_STEPS])

    wall, steps = best_of(many, repeat)
    return wall / loops, steps


def impact_time(contact, mass, speed, gravity, repeat):
    loops = 200

    def many():
        for _ in range(loops):
            out = cs.simulate_impact(contact, mass, speed, gravity=gravity)
        return out

    wall, out = best_of(many, repeat)
    return wall / loops, out.steps


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--repeat', type=int, default=5)
    args = parser.parse_args()
    contact = the_contact()
    g = 9.81
    print(f'load average at start: {" ".join(f"{x:.2f}" for x in os.getloadavg())}; '
          f'best of {args.repeat} runs')

    # a drop on the fixed plate: 20 s, bounces until rest
    wall_drop, drop = best_of(lambda: cs.simulate_drop(contact, MASS, 0.2, gravity=g,
                                                      duration=20.0), args.repeat)
    n_drop = len(drop.impacts)
    speed_drop = float(np.mean([i.impact_speed for i in drop.impacts]))
    # the peers' problem of bench_peers.py (Hunt-Crossley steel ball, 1 m, 5 s, ~378 bounces)
    hc, hc_mass = peers_contact()
    wall_hc, hc_drop = best_of(lambda: cs.simulate_drop(hc, hc_mass, 1.0, gravity=g,
                                                       duration=5.0), args.repeat)
    n_hc = len(hc_drop.impacts)
    speed_hc = float(np.mean([i.impact_speed for i in hc_drop.impacts]))
    # a vibrating table at Γ = 2 (period-1), 400 impacts
    table = VibratingTable(contact, MASS, FREQUENCY, bounces=300, transient=100,
                           restitution_guess=E_1MS)
    wall_table, (times, _, speeds) = best_of(lambda: table.run(2.0), args.repeat)
    n_table = times.size
    speed_table = float(np.mean(speeds))
    # the same orbit with every flight planned by the Python reference (flights.gap_flight)
    w = 2.0 * math.pi * FREQUENCY
    g1 = period_one_threshold(E_1MS)
    table_args = (2.0 * g / w ** 2, FREQUENCY, math.acos(g1 / 2.0))

    def table_drop(plate):
        sim = DropSimulation(contact, MASS, 0.0, velocity=-math.pi * g / w, gravity=g,
                             plate=plate)
        sim.advance(40.0)
        return sim.impacts

    wall_fast, n_fast = best_of(lambda: len(table_drop(SinusoidalPlate(*table_args))),
                                args.repeat)
    wall_ref, n_ref = best_of(lambda: len(table_drop(ReferenceTable(*table_args))), args.repeat)
    points = sampled_table(*table_args, duration=41.0)     # the plates built once, untimed
    commanded, commanded_ref = CommandedPlate(*points), ReferenceCommandedPlate(*points)
    wall_cmd, cmd_impacts = best_of(lambda: table_drop(commanded), args.repeat)
    n_cmd = len(cmd_impacts)
    speed_cmd = float(np.mean([i.impact_speed for i in cmd_impacts]))
    wall_cmd_ref, n_cmd_ref = best_of(lambda: len(table_drop(commanded_ref)), args.repeat)
    rng = np.random.default_rng(0)
    starts = list(zip(rng.uniform(0.0, 40.0, 400), -rng.uniform(1e-4, 1e-2, 400),
                      rng.uniform(-1.0, 0.5, 400)))

    def plans(plate):
        return [Flight(plate, g, t0, z, zdot, contact, None, True).contact_time
                for t0, z, zdot in starts]

    wall_plan, touch = best_of(lambda: plans(commanded), args.repeat)
    wall_plan_ref, touch_ref = best_of(lambda: plans(commanded_ref), args.repeat)
    worst = max(abs(a - b) / abs(b) for a, b in zip(touch, touch_ref))

    ratios, bounce_ratios, published_ratios = [], [], []
    print(f'{"case":<34} {"speed (m/s)":>11} {"steps":>6} {"kernel (us)":>12} '
          f'{"impact (us)":>12} {"impact/kernel":>14} {"bounce (us)":>12} {"bounce/impact":>14} '
          f'{"published (us)":>15} {"bounce/published":>17}')
    for name, key, c, mass, speed, wall, count in (
            (f'fixed plate, drop 0.2 m ({n_drop} bnc)', 'fixed', contact, MASS, speed_drop,
             wall_drop, n_drop),
            (f'fixed, peers\' HC 1 m ({n_hc} bnc)', 'peers', hc, hc_mass, speed_hc, wall_hc,
             n_hc),
            (f'table 10 Hz, G = 2 ({n_table} bnc)', 'table', contact, MASS, speed_table,
             wall_table, n_table),
            (f'commanded, table as pts ({n_cmd} bnc)', 'commanded', contact, MASS, speed_cmd,
             wall_cmd, n_cmd)):
        kernel, steps = kernel_time(c, mass, speed, g, args.repeat)
        impact, _ = impact_time(c, mass, speed, g, args.repeat)
        bounce = wall / count
        ratios.append(impact / kernel)
        bounce_ratios.append(bounce / impact)
        published_ratios.append(bounce * 1e6 / PUBLISHED[key])
        print(f'{name:<34} {speed:11.4g} {steps:6d} {kernel * 1e6:12.2f} {impact * 1e6:12.2f} '
              f'{impact / kernel:14.1f} {bounce * 1e6:12.1f} {bounce / impact:14.1f} '
              f'{PUBLISHED[key]:15.1f} {published_ratios[-1]:17.2f}')
    print(f'fixed plate, drop 0.2 m, 20 s: {wall_drop * 1e3:.3f} ms ({n_drop} bounces); '
          f'published: {PUBLISHED["fixed drop ms"]:.3f} ms with the compiled bounces, '
          f'{PUBLISHED["fixed drop ms, Python modes"]:.3f} ms with the Python modes')
    print(f"peers' Hunt-Crossley drop, 1 m, 5 s: {wall_hc * 1e3:.3f} ms ({n_hc} bounces); "
          f'published: {PUBLISHED["peers drop ms"]:.3f} ms with the compiled bounces, '
          f'{PUBLISHED["peers drop ms, Python modes"]:.3f} ms with the Python modes')
    print(f'table G = 2, 40 s: {wall_fast / n_fast * 1e6:.1f} us a bounce ({n_fast} bounces), '
          f'{wall_ref / n_ref * 1e6:.1f} us ({n_ref}) with the reference flights '
          f'(flights.gap_flight); published with the compiled bounces: '
          f'{PUBLISHED["table 40 s"]:.1f} us')
    print(f'commanded plate (the table as {len(points[0])} set-points), 40 s: '
          f'{wall_cmd / n_cmd * 1e6:.1f} us a bounce ({n_cmd} bounces), '
          f'{wall_cmd_ref / n_cmd_ref * 1e6:.1f} us ({n_cmd_ref}) with the reference flights '
          f'(flights.gap_flight); published: {PUBLISHED["commanded"]:.1f} us with the compiled '
          f'bounces, {PUBLISHED["commanded 40 s, Python modes"]:.1f} us with the Python modes')
    print(f'one flight planned over it: {wall_plan / len(starts) * 1e6:.1f} us compiled, '
          f'{wall_plan_ref / len(starts) * 1e6:.1f} us Python ({len(starts)} flights, touch '
          f'times within {worst:.1e} relative)')
    kernel, steps = kernel_time(contact, MASS, 1.0, 0.0, args.repeat)
    print(f'per kernel step (1 m/s, no gravity): {kernel / steps * 1e6:.3f} us '
          f'({steps} steps a phase)')
    for what, values, target in (('impact/kernel', ratios, TARGET_IMPACT_OVER_KERNEL),
                                 ('bounce/impact', bounce_ratios, TARGET_BOUNCE_OVER_IMPACT),
                                 ('bounce/published', published_ratios, TARGET_OVER_TRAINS)):
        print(f'target {what} <= {target:g} on every row: worst {max(values):.1f} '
              f'({"met" if max(values) <= target else "NOT met"})')
    print(f'targets: impact/kernel <= {TARGET_IMPACT_OVER_KERNEL:g}, bounce/impact <= '
          f'{TARGET_BOUNCE_OVER_IMPACT:g}, bounce/published <= {TARGET_OVER_TRAINS:g}; '
          f'load average at end: '
          f'{" ".join(f"{x:.2f}" for x in os.getloadavg())}')


if __name__ == '__main__':
    from _table import run   # --markdown OUT: the table for the docs (bench/_table.py)
    run(main)

#!/usr/bin/env python3
"""Speed of ``fit_bounces``: 30 recorded sequences of 10 bounces, fitted for all four laws.

The recordings are made by the drop engine (a golf-like ball, Azad-Featherstone contact, air
drag; five release heights), with 50 µs timing jitter, 1/48000 s quantisation and a random
experiment start.  Prints the wall time of one fit of all laws (best of ``--repeat``), the time
per law, the model evaluations' share, and the recovered λ against the true one.

    python bench/bench_bounces.py [--sequences 30] [--bounces 10] [--repeat 3]
"""
import argparse
import time

import numpy as np

import contact_sim as cs
from contact_sim.calibration import ImpactTimes, fit_bounces
from contact_sim.flight import AirDrag


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--sequences', type=int, default=30)
    parser.add_argument('--bounces', type=int, default=10)
    parser.add_argument('--repeat', type=int, default=3)
    args = parser.parse_args()
    mass, k, drag = 0.046, 2e8, AirDrag(1.204, 0.3, 0.0214)
    lam = cs.damping_for_restitution(cs.AZAD_FEATHERSTONE, k, mass, 0.8, 3.0)
    contact = cs.Contact(cs.AZAD_FEATHERSTONE, k, lam)
    heights = (0.4, 0.6, 0.8, 1.0, 1.2)
    truth = {}
    for h in heights:
        result = cs.simulate_drop(contact, mass, h, duration=12.0 * (2 * h / 9.81) ** 0.5,
                                  drag=drag)
        truth[h] = np.array([imp.time for imp in result.impacts])[:args.bounces]
    rng = np.random.default_rng(0)
    recordings = []
    for i in range(args.sequences):
        h = heights[i % len(heights)]
        t = truth[h] + rng.normal(0.0, 50e-6, truth[h].size) + rng.uniform(0.5, 3.0)
        recordings.append(ImpactTimes(np.round(t * 48000.0) / 48000.0, h + rng.normal(0, 0.01)))
    fit_bounces(k, mass, recordings[:1], drag=drag)          # load the tables once
    best = float('inf')
    for _ in range(args.repeat):
        start = time.perf_counter()
        fit = fit_bounces(k, mass, recordings, drag=drag)
        best = min(best, time.perf_counter() - start)
    clicks = sum(r.times.size for r in recordings)
    print(f'{args.sequences} sequences x {args.bounces} bounces ({clicks} clicks), '
          f'{len(fit.fits)} laws: {best:.3f} s wall time (best of {args.repeat}), '
          f'{best / len(fit.fits):.3f} s per law')
    for f in fit.fits:
        low, high = f.damping_interval
        print(f'  {f.law.name:<18} lambda = {f.damping:.6e} [{low:.6e}, {high:.6e}], '
              f'rms {f.rms * 1e6:8.2f} us, {f.parameters} parameters')
    print(f'  true lambda = {lam:.6e} (azad_featherstone); speed-dependent restitution '
          f'supported: {fit.speed_dependent} (delta AIC {fit.delta_aic:.1f})')


if __name__ == '__main__':
    from _table import run   # --markdown OUT: the table for the docs (bench/_table.py)
    run(main)

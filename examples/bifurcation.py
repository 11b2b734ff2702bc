#!/usr/bin/env python3
"""Bifurcation diagram of a sphere on a vibrating table: Azad-Featherstone against constant e.

Both contacts give e = 0.7 at 1 m/s (``fitting.damping_for_restitution``, as Fig. 3 of the paper:
66 g, k = 1e10 N/m^1.5 for the new law, 1e7 N/m for the linear law, whose e does not depend on the
speed).  The table vibrates at 10 Hz; for each Γ the full engine runs ``--transient`` bounces and
plots the table phase of the next ``--bounces`` impacts.  The dashed lines are the constant-e
thresholds Γ₁(0.7) and Γ₂(0.7) (``table``).  The sweep runs on local processes, or on a Dask
cluster with ``--dask SCHEDULER_ADDRESS`` (``distributed.Client(address).get_executor()``).

    python examples/bifurcation.py [--points 200] [--bounces 300] [--out bifurcation.png]
"""
import argparse
import math
import time

import numpy as np

from contact_sim.model import LINEAR, AZAD_FEATHERSTONE
from contact_sim.model.contact import Contact
from contact_sim.impact.damping_fit import damping_for_restitution
from contact_sim.drop.sweeps import bifurcation_diagram
from contact_sim.drop.table import VibratingTable, period_doubling_threshold, period_one_threshold

MASS, STIFFNESS, LINEAR_STIFFNESS, E_1MS, FREQUENCY = 0.066, 1e10, 1e7, 0.7, 10.0


def tables(bounces=300, transient=100):
    """The two ``VibratingTable`` s: {'azad_featherstone': ..., 'linear': ...}."""
    out = {}
    for law, k in ((AZAD_FEATHERSTONE, STIFFNESS), (LINEAR, LINEAR_STIFFNESS)):
        lam = damping_for_restitution(law, k, MASS, E_1MS, 1.0)
        out[law.name] = VibratingTable(Contact(law, k, lam), MASS, FREQUENCY, bounces=bounces,
                                       transient=transient, restitution_guess=E_1MS)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument('--points', type=int, default=200, help='number of Γ values')
    ap.add_argument('--gamma', type=float, nargs=2, default=(0.3, 4.0), help='Γ range')
    ap.add_argument('--bounces', type=int, default=300)
    ap.add_argument('--transient', type=int, default=100)
    ap.add_argument('--workers', type=int, default=None)
    ap.add_argument('--dask', default=None, help='a Dask scheduler address (optional extra)')
    ap.add_argument('--out', default='bifurcation.png')
    args = ap.parse_args(argv)
    if args.dask and args.workers is not None:
        ap.error('--workers sizes the local process pool: with --dask the cluster has its own '
                 'workers (allowed one of --workers, --dask)')
    gammas = np.linspace(*args.gamma, args.points)
    executor = None
    if args.dask:
        from distributed import Client
        executor = Client(args.dask).get_executor()
    results = {}
    for law, table in tables(args.bounces, args.transient).items():
        start = time.perf_counter()
        results[law] = bifurcation_diagram(table, gammas, executor=executor,
                                           max_workers=args.workers)
        print(f'{law:18s} {args.points} values of Gamma x {args.bounces} bounces: '
              f'{time.perf_counter() - start:.1f} s')
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(2, 1, figsize=(8, 7), sharex=True)
    g1, g2 = period_one_threshold(E_1MS), period_doubling_threshold(E_1MS)
    for ax, (law, (x, phase)) in zip(axes, results.items()):
        ax.plot(x, phase / (2 * math.pi), ',k', alpha=0.5)
        for g in (g1, g2):
            ax.axvline(g, ls='--', lw=0.8, color='tab:red')
        ax.set_ylabel('impact phase / 2π')
        ax.set_title(f'{law}: e(1 m/s) = {E_1MS}, 66 g, table at {FREQUENCY:g} Hz')
    axes[-1].set_xlabel('Γ = a ω² / g   (dashed: constant-e Γ₁, Γ₂ at e = 0.7)')
    fig.tight_layout()
    fig.savefig(args.out, dpi=120)
    print(f'plot written to {args.out}')


if __name__ == '__main__':
    main()

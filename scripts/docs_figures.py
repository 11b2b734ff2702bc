#!/usr/bin/env python3
"""The docs' pictures that no `contact-sim --plot` draws (those come with scripts/transcripts.py).

    python scripts/docs_figures.py [OUT_DIR]     # default docs/_generated/figures

- ``fig3.png``, ``fig4.png``: the paper's Figs. 3 and 4, by ``examples/restitution_curves.py``;
- ``bifurcation.png``: the vibrating table's bifurcation diagram, by ``examples/bifurcation.py``'s
  two tables (Azad-Featherstone and constant e = 0.7 at 1 m/s, 66 g, 10 Hz), made small for the
  docs build (``POINTS`` values of Γ, ``TRANSIENT`` + ``BOUNCES`` bounces each, in this process);
  ``python examples/bifurcation.py`` draws the full one (200 x 300 bounces, about a minute).

matplotlib with the Agg backend; the docs build (docs/_ext/contact_sim_docs.py) runs it.
"""
import importlib.util
import math
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
DEFAULT_OUT = ROOT / 'docs' / '_generated' / 'figures'
POINTS, TRANSIENT, BOUNCES = 40, 30, 40
NAMES = ('fig3.png', 'fig4.png', 'bifurcation.png')


def _example(name):
    spec = importlib.util.spec_from_file_location(name, ROOT / 'examples' / f'{name}.py')
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def missing(out_dir):
    """True when a picture is absent from ``out_dir``."""
    return any(not (Path(out_dir) / name).exists() for name in NAMES)


def restitution_figures(out_dir):
    curves = _example('restitution_curves')
    curves._plot(curves.fig3(), curves.fig4(), [out_dir / 'fig3.png', out_dir / 'fig4.png'])


def bifurcation_figure(out_dir):
    import matplotlib.pyplot as plt

    from contact_sim.drop.sweeps import bifurcation_diagram
    from contact_sim.drop.table import period_doubling_threshold, period_one_threshold
    example = _example('bifurcation')
    gammas = np.linspace(0.3, 4.0, POINTS)
    fig, axes = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    g1, g2 = period_one_threshold(example.E_1MS), period_doubling_threshold(example.E_1MS)
    with ThreadPoolExecutor(max_workers=1) as executor:
        for ax, (law, table) in zip(axes, example.tables(BOUNCES, TRANSIENT).items()):
            x, phase = bifurcation_diagram(table, gammas, executor=executor)
            ax.plot(x, phase / (2 * math.pi), '.k', markersize=1.5, alpha=0.6)
            for g in (g1, g2):
                ax.axvline(g, ls='--', lw=0.8, color='tab:red')
            ax.set_ylabel('impact phase / 2π')
            ax.set_title(f'{law}: e(1 m/s) = {example.E_1MS}, 66 g, table at '
                         f'{example.FREQUENCY:g} Hz ({POINTS} Γ x {BOUNCES} bounces)')
    axes[-1].set_xlabel('Γ = a ω² / g   (dashed: constant-e Γ₁, Γ₂ at e = 0.7)')
    fig.tight_layout()
    fig.savefig(out_dir / 'bifurcation.png', dpi=100)
    plt.close(fig)


def write_all(out_dir=DEFAULT_OUT):
    """Draw every picture of ``NAMES`` into ``out_dir``."""
    import matplotlib
    matplotlib.use('Agg')
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    restitution_figures(out_dir)
    bifurcation_figure(out_dir)
    return [out_dir / name for name in NAMES]


if __name__ == '__main__':
    started = time.perf_counter()
    written = write_all(sys.argv[1] if len(sys.argv) > 1 else DEFAULT_OUT)
    print(f'{len(written)} pictures in {time.perf_counter() - started:.1f} s')

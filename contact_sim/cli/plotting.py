"""PNG figures for the `contact-sim` command line: matplotlib (the optional extra ``plot``), Agg.

matplotlib is imported only by ``load_pyplot``, so the rest of the package never needs it.
Every function takes ready-computed arrays; none of them does any physics.
"""
import math
from pathlib import Path

import numpy as np


class MissingMatplotlib(RuntimeError):
    """--plot was given but matplotlib cannot be imported."""


def load_pyplot():
    """Import matplotlib with the non-interactive Agg backend and return ``pyplot``."""
    try:
        import matplotlib
        matplotlib.use('Agg')
        from matplotlib import pyplot
    except ImportError as error:
        raise MissingMatplotlib(
            f'--plot needs matplotlib, which cannot be imported ({error}): install the optional '
            "extra with  pip install 'contact_sim[plot]'  (or  pip install matplotlib)") from None
    return pyplot


def check_output(path):
    """Fail early, before any simulation, if ``path`` cannot be written."""
    parent = Path(path).expanduser().resolve().parent
    if not parent.is_dir():
        raise ValueError(f'--plot = {str(path)!r} cannot be written: directory {str(parent)!r} '
                         'does not exist')


def save_figure(fig, path):
    """Write ``fig`` as a PNG to ``path`` (exactly that name) and close it."""
    pyplot = load_pyplot()
    try:
        fig.savefig(path, dpi=150, format='png')   # the file named, not name + '.png'
    except OSError as error:
        raise ValueError(f'--plot = {str(path)!r} cannot be written: {error.strerror}') from None
    finally:
        pyplot.close(fig)


def _new_figure(rows=1, height=4.8):
    pyplot = load_pyplot()
    fig, axes = pyplot.subplots(rows, 1, figsize=(8.0, height), sharex=True, squeeze=False,
                                layout='constrained')
    return fig, [ax for (ax,) in axes]


def _style(ax):
    ax.grid(True, which='major', alpha=0.5)
    ax.grid(True, which='minor', alpha=0.15)


def restitution_figure(path, curves, points, title, subtitle, log_speed):
    """e vs impact speed: ``curves`` and ``points`` map a label to (speeds m/s, e)."""
    fig, (ax,) = _new_figure()
    for label, (speeds, e) in curves.items():
        line, = ax.plot(speeds, e, label=label, linewidth=1.8)
        if label in points:
            ax.plot(*points[label], 'o', color=line.get_color(), markersize=4)
    if log_speed:
        ax.set_xscale('log')
    ax.set_xlabel('impact speed v (m/s)' + (', log scale' if log_speed else ''))
    ax.set_ylabel('coefficient of restitution e (-)')
    ax.set_ylim(*restitution_limits([e for _, e in curves.values()]))
    ax.set_title(f'{title}\n{subtitle}', fontsize=10)
    ax.legend(title='force law')
    _style(ax)
    save_figure(fig, path)


def restitution_limits(values):
    """y limits that show every curve inside the frame, also when all e are within 1e-9 of 1
    (near-elastic: the axis then zooms in) or exactly equal (elastic)."""
    finite = np.concatenate([np.ravel(v) for v in values]) if len(values) else np.empty(0)
    finite = finite[np.isfinite(finite)]
    if finite.size == 0:
        return 0.0, 1.05
    low, high = float(finite.min()), float(finite.max())
    span = high - low
    if span <= 1e-12 * max(abs(high), 1.0):
        span = max(0.05 * abs(high), 1e-3)
        return low - span, high + span
    return low - 0.08 * span, high + 0.08 * span


def drop_figure(path, time, height, force, impacts, title, subtitle):
    """Height of the sphere's lowest point (m) and contact force (N) vs time (s).

    ``impacts`` is a sequence of (time s, peak force N) marking each contact's peak.
    """
    fig, (top, bottom) = _new_figure(rows=2, height=6.4)
    top.plot(time, height, color='tab:blue', linewidth=1.2)
    top.axhline(0.0, color='0.3', linewidth=0.8)
    top.set_ylabel('height of lowest point (m)\n(< 0: penetration)')
    top.set_title(f'{title}\n{subtitle}', fontsize=10)
    bottom.plot(time, force, color='tab:red', linewidth=1.0, label='contact force F')
    if len(impacts):
        t, peak = np.asarray(impacts, dtype=float).T
        bottom.plot(t, peak, 'v', color='black', markersize=4, label='peak force of a contact')
        bottom.legend()
    bottom.set_xlabel('time t (s)')
    bottom.set_ylabel('contact force F (N)')
    for ax in (top, bottom):
        _style(ax)
    save_figure(fig, path)


def fit_figure(path, data, curves, title, subtitle):
    """Measured points ``data`` = (speeds m/s, e) against fitted curves {label: (speeds, e)}."""
    fig, (ax,) = _new_figure()
    speeds, e = data
    ax.plot(speeds, e, 'ko', markersize=5, label='data', zorder=3)
    for label, (v, ev) in curves.items():
        ax.plot(v, ev, linewidth=1.8, label=label)
    ax.set_xscale('log')
    ax.set_xlabel('impact speed v (m/s), log scale')
    ax.set_ylabel('coefficient of restitution e (-)')
    ax.set_title(f'{title}\n{subtitle}', fontsize=10)
    ax.legend(title='least-squares fit', fontsize=8)
    _style(ax)
    save_figure(fig, path)


def dense_speeds(speeds, log_speed, count=200):
    """An evenly spaced (geometric when ``log_speed``) grid spanning ``speeds``, for curves."""
    lo, hi = float(np.min(speeds)), float(np.max(speeds))
    if not hi > lo:
        return np.asarray([lo])
    if log_speed and lo > 0.0 and math.isfinite(hi):
        return np.geomspace(lo, hi, count)
    return np.linspace(lo, hi, count)


ERROR_BAR_CLIP = 0.1        # e: error bars longer than this are drawn clipped, with a note
OUTLIER_MADS = 5.0          # a point this many robust spreads off the best curve is marked
LEGEND_RUNS = 12            # more runs than this: a colour bar instead of a legend


def bounce_figure(path, table, curves, runs, residuals, law_name, title):
    """The bounce calibration's figure.

    ``table`` = (run j, speeds m/s, e, σ_e) arrays of the corrected restitutions (may be empty:
    then there is no e(v) panel); ``curves`` = {label: (speeds, e)} of the fitted laws, the
    best first; ``runs`` = [(name, times from the first click s)] and ``residuals`` = the best
    law's predicted - measured times (s) of each run.  e > 1 and outliers (more than
    ``OUTLIER_MADS`` robust spreads off the best curve) are marked; error bars longer than
    ``ERROR_BAR_CLIP`` are clipped, with a note; every run has its label or colour bar.
    """
    pyplot = load_pyplot()
    has_e = len(table[1]) > 0
    fig, axes = pyplot.subplots(2 if has_e else 1, 1, figsize=(8.0, 7.0 if has_e else 4.2),
                                layout='constrained', squeeze=False)
    axes = axes[:, 0]
    colours = pyplot.get_cmap('viridis' if len(runs) > 10 else 'tab10')

    def colour(j):
        return colours(j / max(len(runs) - 1, 1) if len(runs) > 10 else j % 10)

    if has_e:
        _restitution_panel(axes[0], table, curves, colour)
    else:
        fig.text(0.01, 0.005, 'no e(v) panel: no two consecutive single flights to read e from',
                 fontsize=8, color='0.3')
    ax_r = axes[-1]
    for j, ((name, t), r) in enumerate(zip(runs, residuals)):
        ax_r.plot(t, np.asarray(r) * 1e3, 'o-', ms=3, color=colour(j),
                  label=f'{j + 1}: {name}' if len(runs) <= LEGEND_RUNS else None)
    ax_r.axhline(0.0, color='k', lw=0.8)
    ax_r.set_xlabel('time since the first click (s)')
    ax_r.set_ylabel(f'predicted - measured (ms), {law_name}')
    ax_r.grid(True, alpha=0.4)
    if len(runs) <= LEGEND_RUNS:
        ax_r.legend(fontsize=7, title='run', title_fontsize=7)
    else:
        from matplotlib.cm import ScalarMappable
        from matplotlib.colors import Normalize
        bar = fig.colorbar(ScalarMappable(Normalize(1, len(runs)), colours), ax=list(axes))
        bar.set_label(f'run (1 to {len(runs)}, in the order read)')
    fig.suptitle(title, fontsize=10)
    save_figure(fig, path)
    return fig


def _restitution_panel(ax, table, curves, colour):
    runs, v, e, se = (np.asarray(c, dtype=float) for c in table)
    best_v, best_e = next(iter(curves.values()))
    off = e - np.interp(v, best_v, best_e)
    spread = 1.4826 * float(np.median(np.abs(off - np.median(off)))) or 1e-12
    outlier = np.abs(off) > OUTLIER_MADS * spread
    above = e > 1.0
    clipped = se > ERROR_BAR_CLIP
    bars = np.minimum(se, ERROR_BAR_CLIP)
    normal = ~outlier & ~above
    for j in np.unique(runs[normal]).astype(int):
        sel = normal & (runs == j)
        ax.errorbar(v[sel], e[sel], yerr=bars[sel], fmt='o', ms=4, color=colour(j),
                    elinewidth=0.8, label='measured (corrected)' if j == runs[normal].min()
                    else None)
    if np.any(outlier & ~above):
        sel = outlier & ~above
        ax.errorbar(v[sel], e[sel], yerr=bars[sel], fmt='s', ms=6, mfc='none', color='tab:orange',
                    label=f'outlier (> {OUTLIER_MADS:g} robust spreads off the best law)')
    if np.any(above):
        ax.errorbar(v[above], e[above], yerr=bars[above], fmt='x', ms=7, color='tab:red',
                    label='e > 1: a mis-numbered click?')
        ax.axhline(1.0, color='tab:red', lw=0.6, ls=':')
    for label, (cv, ce) in curves.items():
        ax.plot(cv, ce, label=label)
    if np.any(clipped):
        ax.text(0.01, 0.02, f'{int(clipped.sum())} error bar(s) clipped at ±{ERROR_BAR_CLIP:g}'
                f' (largest ±{float(se.max()):.2g})', transform=ax.transAxes, fontsize=8,
                color='0.3')
    kept = e[normal] if np.any(normal) else e
    lo = min(float(kept.min()), min(float(np.min(c[1])) for c in curves.values()))
    hi = max(float(kept.max()), max(float(np.max(c[1])) for c in curves.values()))
    if np.any(above):
        hi = max(hi, float(e[above].max()))
    pad = 0.1 * max(hi - lo, 0.02) + ERROR_BAR_CLIP * float(np.any(clipped))
    ax.set_ylim(lo - pad, hi + pad)
    ax.set_xlabel('impact speed (m/s)')
    ax.set_ylabel('coefficient of restitution e')
    ax.legend(fontsize=7)
    ax.grid(True, alpha=0.4)

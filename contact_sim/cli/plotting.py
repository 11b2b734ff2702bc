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
        raise ValueError(f'plot = {str(path)!r} cannot be written: directory {str(parent)!r} '
                         'does not exist')


def save_figure(fig, path):
    """Write ``fig`` as a PNG to ``path`` (exactly that name) and close it."""
    pyplot = load_pyplot()
    try:
        fig.savefig(path, dpi=150, format='png')   # the file named, not name + '.png'
    except OSError as error:
        raise ValueError(f'plot = {str(path)!r} cannot be written: {error.strerror}') from None
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

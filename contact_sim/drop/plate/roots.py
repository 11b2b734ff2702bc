"""Roots of a flight's functions of time, none skipped: the first root of the gap between the
sphere and a moving plate (rigorously bracketed), and the first upward crossing of a sampled
function (the force's return inside the plate's undeformed surface)."""
import math

import numpy as np
from scipy.optimize import brentq

EPS = np.finfo(float).eps


def power(x, e):
    """x ** e for x >= 0 as numpy's ``array ** e`` computes it (its exact cases 0, 1/2, 1, 2):
    the force's powers in the functions whose roots are searched (``flights``, and compiled in
    ``compiled_flight``)."""
    if e == 1.0:
        return x
    if e == 0.5:
        return math.sqrt(x)
    if e == 0.0:
        return 1.0
    if e == 2.0:
        return x * x
    return x ** e


def quadratic_positive(g, dg, curvature, h):
    """True if g + dg s + ½ curvature s² > 0 for every s in [0, h] (plain Python, compiled in
    ``compiled_flight``)."""
    if g + dg * h + 0.5 * curvature * h * h <= 0.0:
        return False
    if curvature > 0.0 and dg < 0.0 and -dg / curvature < h:
        return g - 0.5 * dg * dg / curvature > 0.0      # the vertex inside
    return True


def first_gap_root(gap, t0, curvature_bound, t_max=math.inf, max_steps=100000,
                   local_curvature=None):
    """First t in [t0, t_max] where the gap G(t) reaches <= ~0, with no root skipped.

    ``gap(t)`` returns (G, G', scale): the gap (m), its rate (m/s) and a length scale of the
    operands (for the rounding tolerance).  With |G''| <= M = ``curvature_bound`` on the whole
    interval, G(t + s) >= G + G' s - ½ M s² > 0 for 0 <= s < h = (G' + √(G'² + 2 M G)) / M:
    each step to t + h is safe (no root inside), and converges quadratically to a transversal
    root, geometrically to a tangent one.  ``local_curvature(t, h)``, a lower bound of G'' on
    [t, t + h], allows longer safe steps (twice the last one, tried once while the steps are not
    shrinking; the global step is the fallback): where G'' >= 0 nearby, e.g. just after a release,
    where G grows like s³.
    Returns (t, G, G') at the first point where G <= tolerance (16 eps × scale), or ``None`` past
    ``t_max``.
    """
    t = t0
    M = max(curvature_bound, 1e-300)
    trial = 0.0
    for _ in range(max_steps):
        G, dG, scale = gap(t)
        if G <= 16.0 * EPS * max(scale, 1e-9):
            return t, G, dG
        disc = math.sqrt(dG * dG + 2.0 * M * G)
        h = (dG + disc) / M if dG >= 0.0 else 2.0 * G / (disc - dG)
        if local_curvature is not None and h >= 0.5 * trial:
            # the steps are not shrinking (no root ahead yet): try twice the last one, once
            trial = 2.0 * max(trial, h)
            if quadratic_positive(G, dG, local_curvature(t, trial), trial):
                h = trial
        trial = h
        t_next = t + h
        if t_next == t:
            return t, G, dG
        if t_next > t_max:
            return None
        t = t_next


def first_upward_root(func, t_max, samples=64, func_many=None):
    """First t in (0, t_max] (s) where ``func`` goes from <= 0 to > 0, looked for on ``samples``
    equal stretches and refined by Brent's method; ``None`` if none is seen.

    ``func_many`` (optional) is ``func`` over an array of times, the same numbers elementwise:
    the samples are then evaluated in one call, and ``func`` only refines the bracket.
    """
    ts = np.arange(samples + 1.0) * (t_max / samples)    # np.linspace's numbers, cheaper
    ts[-1] = t_max
    if func_many is not None:
        values = np.asarray(func_many(ts), dtype=float)
        up = np.flatnonzero((values[1:] > 0.0) & (values[:-1] <= 0.0))
        if up.size == 0:
            return None
        i = int(up[0])
        return brentq(func, ts[i], ts[i + 1], xtol=1e-18, rtol=1e-15)
    prev_t, prev_v = ts[0], func(ts[0])
    for t in ts[1:]:
        v = func(t)
        if v > 0.0 and prev_v <= 0.0:
            return brentq(func, prev_t, t, xtol=1e-18, rtol=1e-15)
        prev_t, prev_v = t, v
    return None

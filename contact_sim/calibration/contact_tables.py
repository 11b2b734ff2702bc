"""Per-law tables of the bounce model (``bounces``): what a unit impact does besides its
restitution and duration, as functions of the damping group ζ.

x_l = z_lift / Z is the depth at which the force vanished (> 0 for the Azad-Featherstone, Lee-Wang
and linear laws: the last part of the way up to the surface is flight), and a(ζ), b(ζ) are the
first-order gravity coefficients of the crossing speed and time (``bounces`` module doc).  They are
tabulated per law on 97 points uniform in ln ζ (from 1e-5 to the ζ of e = 0.02) by exact contact
integration (``phase.PhaseIntegrator``; ``scripts/build_bounce_tables.py`` writes
``data/bounce_tables.npz``, about 20 s; the law answers its shipped table,
``ContactLaw.bounce_table``, and a law without one is tabulated once per process) and
interpolated by cubic splines.  ``law_tables`` holds them with the master curve's
e and τc (``impact.master_curve``) as piecewise cubics on uniform grids (the bounce loop's hot
path).
Laws are ``ContactLaw`` objects.
"""
import math
from dataclasses import dataclass
from functools import cache

import numpy as np
from scipy.interpolate import CubicSpline

from contact_sim.impact import dimensionless, group_for_restitution, master_curve
from contact_sim.model import Contact
from contact_sim.phase import PhaseIntegrator

TABLE_POINTS = 97           # table grid, uniform in ln ζ from 1e-5 to the ζ of e = 0.02
LOWEST_RESTITUTION = 0.02    # below it (ζ beyond the table) the end values are held
_G_STEP = 1e-4                                            # dimensionless gravity for a, b


def _unit_contact(law, zeta, gravity):
    """(τ_lift, x_lift, u_lift, τ_cross, u_cross) of the unit impact k = m = v = 1, damping ζ."""
    phase = PhaseIntegrator(Contact(law, 1.0, zeta), 1.0, gravity, 0.0, 0.0, 1.0,
                            rtol=1e-12, atol=1e-14)
    while not phase.lifted_off:
        phase.step()
        if phase.steps > 100000:
            raise RuntimeError(f'unit impact of law {law.name} at zeta = {zeta:g} did not end')
    t, x, u = phase.end
    u = -u   # upward speed at lift-off
    if x <= 0.0:
        return t, 0.0, u, t, u
    # flight from the lift-off depth to the surface under the (dimensionless) gravity
    u_cross = math.sqrt(max(u * u - 2.0 * gravity * x, 0.0))
    return t, x, u, t + 2.0 * x / (u + u_cross), u_cross


def build_contact_table(law, points=TABLE_POINTS):
    """(ln ζ grid, x_l, a, b) of ``law`` by exact integration (module doc); a few seconds.

    a = -∂e_cross/∂G and b = ∂τ_cross/∂G by Richardson extrapolation of steps G and 2G.
    """
    grid = np.linspace(math.log(1e-5), math.log(group_for_restitution(law, LOWEST_RESTITUTION)),
                       points)
    x_l, a, b = (np.empty(grid.size) for _ in range(3))
    for i, s in enumerate(grid):
        zeta = math.exp(s)
        _, x0, _, tau0, u0 = _unit_contact(law, zeta, 0.0)
        _, _, _, tau1, u1 = _unit_contact(law, zeta, _G_STEP)
        _, _, _, tau2, u2 = _unit_contact(law, zeta, 2.0 * _G_STEP)
        x_l[i] = x0
        a[i] = -(4.0 * u1 - u2 - 3.0 * u0) / (2.0 * _G_STEP)
        b[i] = (4.0 * tau1 - tau2 - 3.0 * tau0) / (2.0 * _G_STEP)
    return grid, x_l, a, b


@cache
def contact_table(law):
    """Per law: cubic splines in ln ζ of x_l, a and b (module doc), from the law's shipped
    table (``ContactLaw.bounce_table``) or, for a law without one, computed once per process."""
    shipped = law.bounce_table
    grid, *values = (build_contact_table(law) if shipped is None else
                     (shipped.log_zeta, shipped.x_lift, shipped.a, shipped.b))
    return (float(grid[0]), float(grid[-1])), tuple(CubicSpline(grid, v) for v in values)


@dataclass(frozen=True)
class LawTables:
    """Piecewise-cubic coefficients on uniform grids in s = ln ζ: (e, τc) from the master curve
    and (x_l, a, b) from ``contact_table``, evaluated together (the bounce loop's hot path)."""

    s0: float
    h: float
    master: np.ndarray        # (4, N, 2): e, τc
    t0: float
    th: float
    corrections: np.ndarray   # (4, M, 3): x_l, a, b


@cache
def law_tables(law):
    """The ``LawTables`` of ``law``, or ``None`` for a law without a master curve."""
    curve = master_curve(law)
    if curve is None:
        return None
    master = np.stack([curve.coefficients['restitution'], curve.coefficients['duration']],
                      axis=-1)
    (lo, hi), splines = contact_table(law)
    corrections = np.stack([sp.c for sp in splines], axis=-1)
    return LawTables(curve.s0, curve.h, master, lo, (hi - lo) / corrections.shape[1], corrections)


def tabulated_restitution(law):
    """(ln ζ at the master curve's nodes, e there, decreasing) of ``law``, or ``None`` for a law
    without a master curve."""
    tables = law_tables(law)
    if tables is None:
        return None
    nodes = tables.master[3, :, 0]
    return tables.s0 + tables.h * np.arange(nodes.size), nodes


def _piecewise(coefficients, s0, h, s):
    n = coefficients.shape[1]
    x = np.clip((s - s0) / h, 0.0, n)
    i = np.minimum(x.astype(int), n - 1)
    ds = ((x - i) * h)[:, None]
    c = coefficients[:, i]
    return ((c[0] * ds + c[1]) * ds + c[2]) * ds + c[3]


def contact_values(law, zeta):
    """(e, τc, x_l, a, b) at the groups ``zeta`` (1-d array), from the shipped tables when the
    law has them: below the master curve's ζ range (e > 0.99998) e and τc are continued
    linearly in ζ (error O(ζ²) < 1e-9), above it (e < 1e-3, no bounce worth timing) the end
    values are held, so an optimiser's trial values never fall back on exact integration."""
    tables = law_tables(law)
    if tables is None:
        (lo, hi), splines = contact_table(law)
        s = np.clip(np.log(zeta), lo, hi)
        return (dimensionless('restitution', law, zeta), dimensionless('duration', law, zeta),
                *(f(s) for f in splines))
    s = np.log(np.maximum(zeta, 1e-300))
    master = _piecewise(tables.master, tables.s0, tables.h, s)
    below = s < tables.s0
    if np.any(below):     # d/dζ = (d/ds) / ζ at the first node
        lo = math.exp(tables.s0)
        c = tables.master[:, 0]
        master = np.where(below[:, None], c[3] + (zeta - lo)[:, None] * c[2] / lo, master)
    corr = _piecewise(tables.corrections, tables.t0, tables.th, s)
    return master[:, 0], master[:, 1], corr[:, 0], corr[:, 1], corr[:, 2]


@cache
def scalar_rows(law):
    """The tables of ``law_tables`` as Python tuples, for the one-sequence loop."""
    tables = law_tables(law)
    master = [tuple(tables.master[:, i, :].ravel().tolist())
              for i in range(tables.master.shape[1])]
    corr = [tuple(tables.corrections[:, i, :].ravel().tolist())
            for i in range(tables.corrections.shape[1])]
    return tables, master, corr

"""A bounce sequence in O(1) per bounce: the touch times of a sphere bouncing on a plate.

Between two touches of the plate (the clicks a microphone hears) the sphere

1. is in contact: the restitution fast path (``restitution``) gives the rebound speed e(v) v and
   the contact duration τc(v) of an impact at speed v *without gravity*;
2. flies, in closed form with air drag (``flight``), from the plate back to the plate.

Gravity during the contact is what the fast path leaves out.  Its effect is first order in the
dimensionless gravity G = g T / v (T = Z / v the impact's time scale, see ``restitution``):
the sphere leaves the plate (crosses z = 0 going up) at

    u = v (e(ζ) - G a(ζ)),   a time   τ = T (τc(ζ) + x_l(ζ) / e(ζ) + G b(ζ))   after the touch,

where x_l = z_lift / Z is the depth at which the force vanished and a(ζ), b(ζ) are the
first-order gravity coefficients, tabulated per law (``contact_tables``).  Drag acts on the
short flight from the lift-off depth to the surface (to first order); during the contact it is
neglected, as in the engine (``flight.contact_drag_impulse_ratio``).  The remainder is O(G²): the
touch times agree with ``simulate_drop`` to about 1 µs per bounce while G < 2e-3
(test/calibration/test_bounces.py), and the model stops being valid in the final micro-bounces,
where the flight is no longer long against the contact (G -> 1: errors of 0.1-2 ms per bounce at
G ~ 0.3-0.9) and the sphere ends in permanent contact; ``BounceSequence.gravity_group`` reports G
for each bounce, and the prediction stops at the first bounce whose rebound speed is not
positive.  ``glitches`` leaves out clicks past G = 0.01.
Laws are ``ContactLaw`` objects (the front ends resolve names).
Units: SI; times in s from the first touch unless an offset is given.
"""
import math
from dataclasses import dataclass

import numpy as np

from contact_sim.calibration.contact_tables import contact_values, law_tables, scalar_rows
from contact_sim.flight import AirDrag, fall_time, flight_to_plate
from contact_sim.impact import checked_scales, damping_group_of, impact_scales
from contact_sim.model import require_contact
from contact_sim.validation import (GRAVITY_MAX, HEIGHT_MAX, InputError, require_instance,
                                    require_int, require_mass, require_positive, require_range,
                                    require_real)

VALID_GRAVITY_GROUP = 2e-3    # above this G the first-order gravity correction is not trusted
MAX_BOUNCES = 1_000_000       # impacts one predict_bounces call computes at most


def contact_map(law, stiffness, damping, mass, gravity, speed, kappa=0.0, beta=0.0):
    """Rebound speed u (m/s) at the surface and time τ (s) from touch to that crossing, for
    impacts at ``speed`` (array, m/s); also the gravity group G.  Vectorised; see module doc.

    Drag (κ, β) acts on the short flight from the lift-off depth z_l up to the surface, to first
    order: u is lowered by (κ u + β) z_l."""
    v = np.atleast_1d(np.asarray(speed, dtype=float))
    length, time = impact_scales(law, stiffness, mass, v)
    zeta = np.broadcast_to(damping_group_of(law, damping, mass, length, v), v.shape)
    e0, tau0, xl, aa, bb = contact_values(law, np.ascontiguousarray(zeta))
    g_group = gravity * time / v
    u = v * (e0 - g_group * aa)
    u = u - (kappa * u + beta) * xl * length
    tau = time * (tau0 + xl / np.maximum(e0, 1e-300) + g_group * bb)
    if np.ndim(speed) == 0:
        return float(u[0]), float(tau[0]), float(g_group[0])
    return u, tau, g_group


def _sequence_scalar(law, stiffness, damping, mass, gravity, v, count, kappa):
    """``impact_sequence`` for one sequence in plain Python floats (β = 0, tabulated law):
    the same formulas, about 5 µs per bounce."""
    tables, master, corr = scalar_rows(law)
    n1, p1, q2 = 1.0 / (law.n + 1.0), law.p + 1.0, law.q - 2.0
    s0, h, t0, th = tables.s0, tables.h, tables.t0, tables.th
    nm, nc = len(master), len(corr)
    lo = math.exp(s0)
    vt = math.sqrt(gravity / kappa) if kappa > 0.0 else math.inf
    nan = math.nan
    times, speeds, rebounds, groups = [0.0], [v], [], []
    t = 0.0
    for i in range(count):
        if not v > 0.0:
            break
        length = (mass * v * v / stiffness) ** n1
        time = length / v
        zeta = damping * length ** p1 * v ** q2 / mass
        s = math.log(zeta) if zeta > 0.0 else -745.0
        x = min(max((s - s0) / h, 0.0), nm)
        j = min(int(x), nm - 1)
        ds = (x - j) * h
        a0, a1, b0, b1, c0, c1, d0, d1 = master[j]
        if s < s0:
            e0 = d0 + (zeta - lo) * c0 / lo
            tau0 = d1 + (zeta - lo) * c1 / lo
        else:
            e0 = ((a0 * ds + b0) * ds + c0) * ds + d0
            tau0 = ((a1 * ds + b1) * ds + c1) * ds + d1
        x = min(max((s - t0) / th, 0.0), nc)
        j = min(int(x), nc - 1)
        ds = (x - j) * th
        r = corr[j]
        xl = ((r[0] * ds + r[3]) * ds + r[6]) * ds + r[9]
        aa = ((r[1] * ds + r[4]) * ds + r[7]) * ds + r[10]
        bb = ((r[2] * ds + r[5]) * ds + r[8]) * ds + r[11]
        g_group = gravity * time / v
        u = v * (e0 - g_group * aa)
        u -= kappa * u * xl * length
        if not u > 0.0:
            rebounds.append(nan)
            groups.append(nan)
            break
        rebounds.append(u)
        groups.append(g_group)
        if i + 1 == count:
            break
        tau = time * (tau0 + xl / max(e0, 1e-300) + g_group * bb)
        if kappa > 0.0:     # (atan w + asinh w) vt / g, arrival u / √(1 + w²): flight.py
            w = u / vt
            flight = (math.atan(w) + math.asinh(w)) * vt / gravity
            v = u / math.sqrt(1.0 + w * w)
        else:
            flight, v = 2.0 * u / gravity, u
        t += tau + flight
        times.append(t)
        speeds.append(v)
    out = []
    for values in (times, speeds, rebounds, groups):
        row = np.full(count, np.nan)
        row[:len(values)] = values
        out.append(row[None, :])
    return tuple(out)


def impact_sequence(law, stiffness, damping, mass, gravity, first_speed, count, kappa=0.0,
                    beta=0.0):
    """Touch times (from the first touch), impact speeds, rebound speeds and gravity groups of
    ``count`` impacts starting at ``first_speed`` (array of S sequences): arrays of shape (S,
    count), NaN after the sphere stops bouncing.  O(1) work per bounce, vectorised over S
    (``damping`` may be an array of S values too); a few sequences go through a plain-float
    loop with the same formulas (numpy's per-call overhead dominates for small arrays)."""
    v = np.atleast_1d(np.asarray(first_speed, dtype=float))
    lam = np.broadcast_to(np.asarray(damping, dtype=float), v.shape)
    if v.size <= 8 and beta == 0.0 and law_tables(law) is not None:
        rows = [_sequence_scalar(law, stiffness, float(lam[i]), mass, gravity, float(v[i]),
                                 count, kappa) for i in range(v.size)]
        return tuple(np.concatenate([r[q] for r in rows]) for q in range(4))
    damping = lam
    shape = (v.size, count)
    times, speeds, rebounds, groups = (np.full(shape, np.nan) for _ in range(4))
    times[:, 0], speeds[:, 0] = 0.0, v
    t = np.zeros(v.size)
    for i in range(count):
        ok = np.isfinite(v) & (v > 0.0)
        vv = np.where(ok, v, 1.0)
        u, tau, g_group = contact_map(law, stiffness, damping, mass, gravity, vv, kappa, beta)
        ok &= u > 0.0
        u = np.where(ok, u, np.nan)
        rebounds[:, i], groups[:, i] = u, np.where(ok, g_group, np.nan)
        if i + 1 == count:
            break
        flight, v_next = flight_to_plate(np.where(ok, u, 1.0), gravity, kappa, beta)
        t = t + tau + flight
        v = np.where(ok, v_next, np.nan)
        times[:, i + 1] = np.where(ok, t, np.nan)
        speeds[:, i + 1] = v
    return times, speeds, rebounds, groups


def release_speed(height, gravity, kappa=0.0, beta=0.0):
    """Speed (m/s) at the plate after a release from rest at ``height`` (m), with drag."""
    return fall_time(np.asarray(height, dtype=float), 0.0, gravity, kappa, beta)[1]


def release_height(speed, gravity, kappa=0.0, beta=0.0):
    """Height (m) of a release from rest that reaches the plate at ``speed``: the inverse of
    ``release_speed`` in closed form (inf at or beyond the terminal speed)."""
    s = np.asarray(speed, dtype=float)
    with np.errstate(divide='ignore', invalid='ignore'):
        if kappa > 0.0:
            r = math.sqrt(beta * beta + 4.0 * kappa * gravity)
            s_plus = 2.0 * gravity / (beta + r)
            s_minus = s_plus + beta / kappa
            h = (s_plus * np.log1p(s / (s_plus - s)) - s_minus * np.log1p(s / s_minus)) / r
            return np.where(s < s_plus, h, np.inf)
        if beta > 0.0:
            x = beta * s / gravity
            h = -(s / beta) - gravity / beta ** 2 * np.log1p(-x)
            return np.where(x < 1.0, h, np.inf)
    return s * s / (2.0 * gravity)


@dataclass(frozen=True)
class BounceSequence:
    """Predicted bounces: per impact its touch time (s), impact and rebound speeds (m/s), the
    restitution u / v at the surface (gravity during contact included to first order), and the
    gravity group G (the model is trusted while G < ``VALID_GRAVITY_GROUP``)."""

    times: np.ndarray
    impact_speeds: np.ndarray
    rebound_speeds: np.ndarray
    gravity_group: np.ndarray

    @property
    def restitutions(self):
        """Per impact, rebound / impact speed (dimensionless)."""
        return self.rebound_speeds / self.impact_speeds

    @property
    def valid(self):
        """Per impact, True while the gravity group is below ``VALID_GRAVITY_GROUP``."""
        return self.gravity_group < VALID_GRAVITY_GROUP


def predict_bounces(contact, mass, height=None, first_flight=None, count=10, gravity=9.81,
                    drag=None, start_time=0.0):
    """Predict the touch times and speeds of a bouncing sphere, in closed form per bounce.

    The sphere (``mass`` kg, ``Contact``) is released from rest at ``height`` (m) above the
    plate, or, with ``first_flight`` (s), its first bounce flight lasts that long (touch to
    touch): ``count`` impacts, the first at ``start_time`` (s; for a release, the release is at
    ``start_time`` and the first touch after the fall). The sequence ends early, with a
    rebound speed 0, at the impact after which the sphere stays in contact (fewer than
    ``count`` impacts).

    Parameters
    ----------
    contact : Contact
        The contact (law, k, λ).
    mass : float
        The sphere's mass, kg, > 0.
    height : float, optional
        Release height from rest, m, > 0; give it or ``first_flight``.
    first_flight : float, optional
        Duration of the first bounce, touch to touch, s, > 0; give it or ``height``.
    count : int, optional
        Impacts predicted, 1 to 1e6 (default 10).
    gravity : float, optional
        Gravity g, m/s², > 0 (default 9.81).
    drag : AirDrag, optional
        Air drag in flight; ``None`` (default): vacuum.
    start_time : float, optional
        Time of the release (or of the first impact with ``first_flight``), s (default 0).

    Returns
    -------
    BounceSequence
        Per impact: touch time (s), impact and rebound speeds (m/s), restitution, gravity group.

    Raises
    ------
    InputError
        Keyed ``mass``, ``gravity``, ``count``, ``start_time``, ``height`` or ``first_flight``:
        out of range.
    ValueError
        Both or neither of ``height`` and ``first_flight``, or a ``first_flight`` no bounce of
        this contact lasts.

    See Also
    --------
    fit_bounces : The inverse, λ from recorded touch times.

    Examples
    --------
    >>> import contact_sim as cs
    >>> contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron',
    ...                                     radius=0.0127, damping_factor=8.87e5)
    >>> mass = cs.build_mass(sphere='steel', radius=0.0127)
    >>> bounces = cs.predict_bounces(contact, mass, height=0.1, count=4)
    >>> print(*(f"{t:.4f}" for t in bounces.times))
    0.1428 0.3495 0.5020 0.6163
    >>> print(*(f"{e:.4f}" for e in bounces.restitutions))
    0.7235 0.7374 0.7499 0.7613
    """
    contact = require_contact(contact)
    mass = require_mass(mass)
    gravity = require_range('gravity', gravity, 0.0, GRAVITY_MAX, low_open=True, unit='m/s^2')
    count = require_int('count', count, 1, MAX_BOUNCES)
    start = require_real('start_time', start_time)
    drag = require_instance('drag', drag, (AirDrag, type(None)),
                            'None or an AirDrag(air_density, drag_coefficient, radius)')
    kappa, beta = drag.rates(mass, gravity) if drag is not None else (0.0, 0.0)
    law, k, lam = contact.law, contact.stiffness, contact.damping
    if (height is None) == (first_flight is None):
        raise InputError('height', height, 'release is %s: give exactly one of {n[height]} (m) '
                         'and {n[first_flight]} (s)'
                         % ('missing' if height is None else 'given twice'))
    if height is not None:
        h = require_range('height', height, 0.0, HEIGHT_MAX, low_open=True, unit='m')
        v1 = float(release_speed(h, gravity, kappa, beta))
        try:
            checked_scales(contact, mass, v1)
        except InputError as error:
            if error.field != 'speeds':
                raise
            raise InputError('height', h, '{n[height]} = {value} m is out of range: its impact '
                             'speed %g m/s has impact scales that are not finite doubles; '
                             'allowed a larger {n[height]}' % v1) from None
        start += float(fall_time(h, 0.0, gravity, kappa, beta)[0])
    else:
        v1 = first_speed_for_flight(law, k, lam, mass, gravity,
                                    require_positive('first_flight', first_flight), kappa, beta)
    times, speeds, rebounds, groups = impact_sequence(law, k, lam, mass, gravity, v1, count,
                                                      kappa, beta)
    n = int(np.argmin(np.isfinite(times[0]))) if not np.all(np.isfinite(times[0])) else count
    v = speeds[0, :n]
    rebound = np.where(np.isfinite(rebounds[0, :n]), rebounds[0, :n], 0.0)
    group = np.where(np.isfinite(groups[0, :n]), groups[0, :n],
                     gravity * impact_scales(law, k, mass, v)[1] / v)
    return BounceSequence(times[0, :n] + start, v, rebound, group)


def first_speed_for_flight(law, stiffness, damping, mass, gravity, flight, kappa=0.0, beta=0.0):
    """Impact speed v (m/s) whose bounce (contact + flight, touch to touch) lasts ``flight`` s."""
    from scipy.optimize import brentq

    def interval(v):
        t = impact_sequence(law, stiffness, damping, mass, gravity, v, 2, kappa, beta)[0]
        return float(t[0, 1]) if np.isfinite(t[0, 1]) else 0.0

    # the rebound speed is at least g T / 2 (drag only shortens the flight) and v >= u
    lo, hi = 0.25 * gravity * flight, gravity * flight
    while interval(hi) < flight:
        lo, hi = hi, 2.0 * hi
        if hi > 1e6:
            raise ValueError(f'first_flight = {float(flight)!r} is out of range: no bounce of this '
                             'contact lasts that long')
    return brentq(lambda v: interval(v) - flight, lo, hi, xtol=1e-14, rtol=1e-14)


__all__ = ['BounceSequence', 'VALID_GRAVITY_GROUP', 'contact_map', 'first_speed_for_flight', 'impact_sequence', 'predict_bounces', 'release_height',
           'release_speed']

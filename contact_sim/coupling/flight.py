"""A coupled contact's flight inside one host step, in closed form: the clamped force is zero and
the rest of the system gives the gap a constant acceleration over the step.

z > 0 is penetration, ż > 0 approach, a the acceleration along +z (m/s², any sign): the flight
is the parabola z(t) = z₀ + ż₀ t + ½ a t².  The force switches on again where it crosses z = 0
on the way in, or, inside the undeformed surface with zero force after a lift-off at z > 0 (a law
with n > p), where φ = k z^(n-p) + λ ż|ż|^(q-1) turns positive (it must once ż reaches 0 there):
the same rule as the drop's fixed-plate flights, with any sign of a.  Units: SI.
"""
import math

import numpy as np
from scipy.optimize import brentq

# samples of φ on the search interval before Brent's method refines a sign change (as the drop's
# fixed-plate flights look for the force's return)
SAMPLES = 64
# brentq's smallest relative tolerance (4 eps): below it scipy raises ValueError
_RTOL = 4.0 * float(np.finfo(float).eps)


def parabola(z, zdot, acceleration, t):
    """(z, ż) (m, m/s) a time t (s) after (z, ż) under the constant acceleration (m/s²)."""
    return z + zdot * t + 0.5 * acceleration * t * t, zdot + acceleration * t


def _surface_root(z, zdot, a):
    """The first t > 0 (s) at which the parabola from z < 0 (or z = 0 leaving) reaches z = 0
    on the way in (inf: never)."""
    if a == 0.0:
        return -z / zdot if zdot > 0.0 else math.inf
    disc = zdot * zdot - 2.0 * a * z
    if disc < 0.0:
        return math.inf
    root = math.sqrt(disc)
    if zdot >= 0.0 and z < 0.0:     # approaching: the first root, without cancellation
        return 2.0 * -z / (zdot + root) if zdot + root > 0.0 else math.inf
    if zdot > 0.0 or (zdot == 0.0 and a > 0.0):     # at the surface, moving or pressed in
        return 0.0
    # leaving (ż < 0): the way back in needs a > 0; the later root
    return (-zdot + root) / a if a > 0.0 else math.inf


def _exit_time(z, zdot, a):
    """The time (s) at which the parabola from z > 0 reaches the surface z = 0 (inf: never)."""
    disc = zdot * zdot - 2.0 * a * z
    if disc < 0.0:
        return math.inf
    root = math.sqrt(disc)
    if zdot < 0.0:
        return 2.0 * z / (-zdot + root)
    return (zdot + root) / -a if a < 0.0 else math.inf


def touch_time(contact, z, zdot, acceleration, horizon, leaving=False):
    """The flight time (s) from (z, ż) until the clamped force of ``contact`` switches on again,
    if it does within ``horizon`` (s); inf otherwise.

    Parameters
    ----------
    contact : Contact
        The contact (its law, k and λ decide the force's return inside the surface).
    z, zdot : float
        Penetration (m) and penetration rate (m/s) at the start, with the force zero there.
    acceleration : float
        The constant acceleration of z over the flight, m/s² (any sign).
    horizon : float
        The longest flight time asked about, s, >= 0.
    leaving : bool, optional
        The flight starts at a lift-off, where φ = 0: its sign there is round-off and does
        not count.

    Returns
    -------
    float
        The touch time in s (0 <= t <= horizon), or inf.

    Examples
    --------
    >>> import contact_sim as cs
    >>> from contact_sim.coupling import touch_time
    >>> contact = cs.Contact(cs.AZAD_FEATHERSTONE, 1.0952e10, 9.996e4)
    >>> print(f"{touch_time(contact, -0.01, 1.0, 9.81, 1.0):.6f}")
    0.009552
    >>> touch_time(contact, -0.01, 1.0, 9.81, 0.005)
    inf
    """
    a = acceleration
    if z > 0.0:
        t_out = _exit_time(z, zdot, a)
        # ż reaches 0 inside the surface: the spring pushes again by then
        t_turn = -zdot / a if zdot < 0.0 < a else (0.0 if zdot >= 0.0 else math.inf)
        t_search = min(t_out, t_turn, horizon)
        root = _force_return(contact, z, zdot, a, t_search, leaving)
        if root is not None:
            return root
        if t_turn <= t_out:
            return t_turn if t_turn <= horizon else math.inf
        if t_out > horizon:
            return math.inf
        t = t_out + _surface_root(0.0, zdot + a * t_out, a)
    else:
        t = _surface_root(z, zdot, a)
    return t if t <= horizon else math.inf


def _force_return(contact, z, zdot, a, t_search, leaving):
    """The first t in [0, t_search] (s) at which φ turns positive on the parabola inside the
    surface (``None``: none found on ``SAMPLES`` samples and the ends); ``leaving``: φ(0) does
    not count."""
    law, k, lam = contact.law, contact.stiffness, contact.damping

    def phi(t):
        zt, vt = parabola(z, zdot, a, t)
        rate = math.copysign(abs(vt) ** law.q, vt) if vt != 0.0 else 0.0
        return k * max(zt, 0.0) ** (law.n - law.p) + lam * rate

    if not leaving and phi(0.0) > 0.0:
        return 0.0
    if not t_search > 0.0 or not math.isfinite(t_search):
        return None
    previous, negative = 0.0, not leaving
    for t in np.linspace(0.0, t_search, SAMPLES + 1)[1:].tolist():
        if phi(t) > 0.0:
            if not negative:
                return t
            return brentq(phi, previous, t, xtol=1e-15 * max(t, 1e-30), rtol=_RTOL)
        previous, negative = t, True
    return None

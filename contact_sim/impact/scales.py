"""The scales of one impact: the depth Z, the time T and the damping group ζ (SI units).

With Z = (m v² / k)^(1/(n+1)) (the depth at which the spring would hold all the kinetic energy)
and T = Z / v, an impact without gravity reduces to one problem in the group
ζ = λ Z^(p+1) v^(q-2) / m (see ``outcomes``).  These functions work on numpy arrays.
"""
import math

import numpy as np

from contact_sim.validation import InputError, require_real_array

# the largest damping group of any path: beyond it the exact integration is not attempted, and a
# drop's contact is a creep into the plate far slower than any drop.  e there (``dimensionless``):
# 1e-8 Hunt-Crossley, 1.2e-10 Lee-Wang, 6.1e-14 Azad-Featherstone, 1e-16 linear
ZETA_MAX = 1e8
# below this damping group a damped contact is elastic to every digit (1 - e ~ ζ), and a
# drop's lift-off quantities (∝ k z / λ) overflow the doubles: a drop wants λ = 0 instead
ZETA_MIN = 1e-100
# the shortest contact time scale T = Z / v of any path (impacts, drops): a shorter contact is
# stiffer than any material (steel on steel at 10 m/s: T ~ 2e-5 s)
CONTACT_TIME_MIN = 1e-12   # s
# the deepest contact length scale Z: a sphere sinking deeper than 1 km is no contact of these laws
CONTACT_LENGTH_MAX = 1e3   # m


def impact_scales(law, stiffness, mass, speed):
    """Z (m) and T (s) of an impact at ``speed``; works on numpy arrays."""
    length = (mass * np.asarray(speed, dtype=float) ** 2 / stiffness) ** (1.0 / (law.n + 1.0))
    return length, length / speed


def require_speeds(speed, name='speeds'):
    """``speed`` as a float array of finite real speeds > 0 (m/s), else ``InputError`` on
    ``name`` (strings, complex numbers, dates, masked arrays refused: ``require_real_array``)."""
    v = require_real_array(name, speed, finite=False)
    if v.size and not (np.all(np.isfinite(v)) and np.all(v > 0.0)):
        bad = float(v[~(np.isfinite(v) & (v > 0.0))].flat[0])
        raise InputError(name, bad, '{n[%s]} = {value} is out of range: allowed 0 < {n[%s]} < inf '
                         '(m/s)' % (name, name))
    return v


def damping_group_of(law, damping, mass, length, speed):
    """ζ = λ Z^(p+1) v^(q-2) / m of damping λ and mass m (kg) at the impact length scale Z (m)
    and speed v (m/s): arrays or floats."""
    return damping * length ** (law.p + 1.0) * speed ** (law.q - 2.0) / mass


def _scales_accepted(length, time, zeta, zeta_max, zeta_min, elastic=True):
    """(finite, ok) of impact scales, arrays or floats: Z and T finite positive doubles; and
    also T >= ``CONTACT_TIME_MIN``, Z <= ``CONTACT_LENGTH_MAX``, ζ <= ``zeta_max`` and ζ = 0 or
    ζ >= ``zeta_min`` (the rule ``checked_scales`` and ``checked_scales_at`` both apply).  ζ = 0
    counts as elastic only for an ``elastic`` contact (λ = 0): a λ > 0 whose ζ underflows to 0
    (λ = 5e-324) is below ``zeta_min``."""
    finite = (length > 0.0) & (length < math.inf) & (time > 0.0) & (time < math.inf)  # NaN: no
    zero_ok = (zeta == 0.0) & (elastic or zeta_min <= 0.0)
    ok = finite & (time >= CONTACT_TIME_MIN) & (length <= CONTACT_LENGTH_MAX) & (zeta <= zeta_max) \
        & (zero_ok | (zeta >= zeta_min) & (zeta > 0.0))
    return finite, ok


def checked_scales_at(contact, mass, speed, name='speed', zeta_max=ZETA_MAX, zeta_min=0.0):
    """``checked_scales`` at one speed, as floats: (Z in m, T in s, ζ).

    The same tests in plain float arithmetic (about 1 µs, against 20 µs for numpy on a 0-d
    array), for the callers of one impact (``simulate_impact``, the scalar ``restitution``).
    Anything the float path cannot decide (not a finite float > 0, an overflow, a test that
    fails) goes to ``checked_scales``, which raises the same ``InputError`` as for an array.
    """
    if type(speed) is float and 0.0 < speed < math.inf and type(mass) is float:
        law = contact.law
        try:
            length = (mass * (speed * speed) / contact.stiffness) ** (1.0 / (law.n + 1.0))  # as v**2
            time = length / speed
            zeta = damping_group_of(law, contact.damping, mass, length, speed)
        except (OverflowError, ZeroDivisionError):
            pass
        else:
            if _scales_accepted(length, time, zeta, zeta_max, zeta_min,
                                contact.damping == 0.0)[1]:
                return length, time, zeta
    length, time, zeta = checked_scales(contact, mass, speed, name, zeta_max, zeta_min)
    return float(length), float(time), float(zeta)


def checked_scales(contact, mass, speed, name='speeds', zeta_max=ZETA_MAX, zeta_min=0.0):
    """The scales of impacts of one contact at the given speeds.

    Parameters
    ----------
    contact : Contact
        The law with its stiffness k (N/m^n) and damping λ (N·s^q/m^(p+q)).
    mass : float
        The (reduced) mass in kg.
    speed : float or array_like
        Impact speeds in m/s.
    name : str, optional
        The field an ``InputError`` names.
    zeta_max : float, optional
        The largest damping group accepted (``ZETA_MAX``; ``check_drop`` passes inf and
        applies its own bound, at the impact and at rest).
    zeta_min : float, optional
        The smallest non-zero damping group accepted: 0 (every λ; ``restitution`` answers
        e = 1 - 2ζ/3... down to ζ = 1e-300), ``ZETA_MIN`` for a drop (whose lift-off quantities
        overflow below it).

    Returns
    -------
    tuple of ndarray
        (Z in m, T in s, ζ dimensionless), of the shape of ``speed``.

    Raises
    ------
    InputError
        On ``name``: a speed not finite and positive, or whose Z or T is not a finite positive
        number; on ``stiffness``: T below ``CONTACT_TIME_MIN`` or Z above
        ``CONTACT_LENGTH_MAX``; on ``damping``: ζ above ``zeta_max``, or 0 < ζ < ``zeta_min``.
    """
    law = contact.law
    v = require_speeds(speed, name)
    with np.errstate(all='ignore'):
        length, time = impact_scales(law, contact.stiffness, mass, v)
        zeta = damping_group_of(law, contact.damping, mass, length, v)
    finite, ok = _scales_accepted(length, time, zeta, zeta_max, zeta_min, contact.damping == 0.0)
    if not np.all(ok):
        i = np.flatnonzero(~np.broadcast_to(ok, np.shape(v)).ravel())[0]
        bad = float(np.ravel(v)[i])
        if not np.ravel(finite)[i]:
            raise InputError(name, bad, '{n[%s]} = {value} is out of range for {n[mass]} = %g kg '
                             'and {n[stiffness]} = %g: its impact depth Z and time T are not '
                             'finite positive doubles; allowed speeds whose Z and T are '
                             'finite positive doubles'
                             % (name, float(mass), contact.stiffness))
        k, n = contact.stiffness, law.n
        t = float(np.ravel(time)[i])
        if t < CONTACT_TIME_MIN:   # T ∝ k^(-1/(n+1)) at one speed
            k_max = k * (t / CONTACT_TIME_MIN) ** (n + 1.0)
            raise InputError('stiffness', k, '{n[stiffness]} = {value} N/m^%g is too large for '
                             'a %g kg sphere at %g m/s: its contact would last ~%.3g s; allowed '
                             '{n[stiffness]} <= %.4g N/m^%g (contact time scale >= %g s)'
                             % (n, float(mass), bad, t, k_max, n, CONTACT_TIME_MIN),
                             value='%g' % k)
        depth = float(np.ravel(length)[i])
        if depth > CONTACT_LENGTH_MAX:   # Z ∝ k^(-1/(n+1))
            k_min = k * (depth / CONTACT_LENGTH_MAX) ** (n + 1.0)
            raise InputError('stiffness', k, '{n[stiffness]} = {value} N/m^%g is too small for '
                             'a %g kg sphere at %g m/s: it would sink ~%.3g m into the plate; '
                             'allowed {n[stiffness]} >= %.4g N/m^%g (contact length scale <= %g '
                             'm)' % (n, float(mass), bad, depth, k_min, n, CONTACT_LENGTH_MAX),
                             value='%g' % k)
        z = float(np.ravel(zeta)[i])
        if z < zeta_min:
            raise InputError('damping', contact.damping, '{n[damping]} = {value} is too small to '
                             'damp a %g kg sphere at %g m/s: the damping group would be zeta = '
                             '%.3g, elastic to every digit; allowed {n[damping]} = 0 (elastic) or '
                             '{n[damping]} >= %.4g (zeta >= %g)'
                             % (float(mass), bad, z,
                                zeta_min / damping_group_of(law, 1.0, float(mass), depth, bad),
                                zeta_min),
                             value='%g' % contact.damping)
        lam_max = contact.damping * (zeta_max / z)
        raise InputError('damping', contact.damping, '{n[damping]} = {value} is too large for a '
                         '%g kg sphere at %g m/s: the damping group would be zeta = %.3g; '
                         'allowed {n[damping]} <= %.4g (zeta <= %g)'
                         % (float(mass), bad, z, lam_max, zeta_max), value='%g' % contact.damping)
    return length, time, zeta

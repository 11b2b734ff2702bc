"""The scales of one impact: the depth Z, the time T and the damping group ζ (SI units).

With Z = (m v² / k)^(1/(n+1)) (the depth at which the spring would hold all the kinetic energy)
and T = Z / v, an impact without gravity reduces to one problem in the group
ζ = λ Z^(p+1) v^(q-2) / m (see ``restitution``).  These functions work on numpy arrays.
"""
import numpy as np

from contact_sim.validation import InputError

ZETA_MAX = 1e8   # beyond this damping group (e < 1e-10) the exact integration is not attempted


def impact_scales(law, stiffness, mass, speed):
    """Z (m) and T (s) of an impact at ``speed``; works on numpy arrays."""
    length = (mass * np.asarray(speed, dtype=float) ** 2 / stiffness) ** (1.0 / (law.n + 1.0))
    return length, length / speed


def require_speeds(speed, name='speed'):
    """``speed`` as a float array of finite speeds > 0 (m/s), else ``InputError``."""
    v = np.asarray(speed, dtype=float)
    if v.size and not (np.all(np.isfinite(v)) and np.all(v > 0.0)):
        bad = float(v[~(np.isfinite(v) & (v > 0.0))].flat[0])
        raise InputError(name, bad, '{n[%s]} = {value} is out of range: allowed 0 < {n[%s]} < inf '
                         '(m/s)' % (name, name))
    return v


def damping_group_of(law, length, speed, damping, mass):
    """ζ = λ Z^(p+1) v^(q-2) / m at the impact length scale Z (m) and speed v (m/s): arrays or
    floats."""
    return damping * length ** (law.p + 1.0) * speed ** (law.q - 2.0) / mass


def checked_scales(contact, mass, speed, name='speed'):
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

    Returns
    -------
    tuple of ndarray
        (Z in m, T in s, ζ dimensionless), of the shape of ``speed``.

    Raises
    ------
    InputError
        On ``name``: a speed not finite and positive, or whose Z or T is not a finite positive
        number, or whose ζ exceeds ``ZETA_MAX``.
    """
    law = contact.law
    v = require_speeds(speed, name)
    with np.errstate(all='ignore'):
        length, time = impact_scales(law, contact.stiffness, mass, v)
        zeta = damping_group_of(law, length, v, contact.damping, mass)
    ok = (length > 0.0) & np.isfinite(length) & (time > 0.0) & np.isfinite(time) \
        & (zeta <= ZETA_MAX)
    if not np.all(ok):
        bad = float(np.broadcast_to(v, ok.shape)[~ok].flat[0])
        raise InputError(name, bad, '{n[%s]} = {value} is out of range for mass = %r kg and this '
                         'contact: allowed speeds whose impact scales Z, T are finite and whose '
                         'damping group is at most zeta = %g' % (name, float(mass), ZETA_MAX))
    return length, time, zeta

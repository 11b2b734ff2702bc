"""Coefficient of restitution, fast: exact reductions instead of repeated integration.

Without gravity, an impact at speed v obeys m z̈ = -k zⁿ - λ zᵖ ż|ż|^(q-1), z(0) = 0, ż(0) = v.
With Z = (m v² / k)^(1/(n+1)) (the depth at which the spring would hold all the kinetic energy),
T = Z / v, x = z / Z and τ = t / T it becomes

    x'' = -xⁿ - ζ xᵖ x'|x'|^(q-1),  x(0) = 0, x'(0) = 1,
    ζ = λ Z^(p+1) v^(q-2) / m = λ m^((p+1)/(n+1) - 1) v^(2(p+1)/(n+1) + q - 2) k^(-(p+1)/(n+1)),

so the restitution e, the dimensionless contact time τc, peak force F̂ = F / (k Zⁿ) and depth
x̂ = z / Z depend on the single group ζ.  For q = 1: Azad-Featherstone ζ = λ v^(1/5) /
(m^(2/5) k^(3/5)), Hunt-Crossley ζ = λ v / k, Lee-Wang ζ = λ v^(3/5) / (m^(1/5) k^(4/5)),
linear ζ = λ / √(m k) (velocity independent).  Two parameter sets with the same ζ give the same e.

* Hunt-Crossley and the linear law have closed forms (``model.closed_forms``: Lambert W and a
  first integral; the damped oscillator up to separation).
* Everything else comes from master curves tabulated by ``simulate_impact`` on a uniform grid in
  ln ζ (``scripts/build_master_curves.py``, ``model.master_curves``), interpolated by cubic
  splines.  Beyond the table e follows asymptotics joined to its ends (``tails``:
  1 - I ζ + c2 ζ² below, ζ^(-a) (A + B ζ^(-b)) above); the other quantities there come from
  the exact path.

The law says which of these it has (``ContactLaw.closed_form``, ``ContactLaw.master_curve``):
they are registered per law, never found by exponents, so a custom law is integrated, with a
warning the first time (``dimensionless_outcomes``).  This module holds the public dimensional
results and the group ζ with its inverse; ``scales`` the impact's scales,
``dimensionless_outcomes`` the choice of source.
"""
import math

import numpy as np

from contact_sim.impact.dimensionless_outcomes import dimensionless
from contact_sim.impact.scales import (checked_scales, checked_scales_at, damping_group_of,
                                      impact_scales, require_speeds)
from contact_sim.impact.tails import restitution_tails
from contact_sim.model import require_contact
from contact_sim.validation import (MASS_RANGE, InputError, range_text, require_mass,
                                    require_real_array)


def damping_group(contact, mass, speed):
    """The damping group ζ = λ Z^(p+1) v^(q-2) / m, the one group the restitution depends on.

    Z = (m v² / k)^(1/(n+1)) is the impact's length scale (see the module doc).

    Parameters
    ----------
    contact : Contact
        The contact: its law (exponents n, p, q), stiffness k and damping λ.
    mass : float or array_like of float
        The (reduced) mass, kg, > 0.
    speed : float or array_like of float
        Impact speeds, m/s, > 0.

    Returns
    -------
    float or numpy.ndarray
        Damping group ζ, dimensionless, of the broadcast shape of ``mass`` and ``speed``.

    Raises
    ------
    InputError
        Keyed ``contact`` (not a ``Contact``), ``mass`` (``MASS_RANGE``) or ``speed``: a speed
        that is not a finite real > 0, or a ζ that overflows.

    Examples
    --------
    >>> import contact_sim as cs
    >>> contact = cs.Contact(cs.AZAD_FEATHERSTONE, 1.0952e10, 9.996e4)
    >>> print(f"{float(cs.damping_group(contact, 0.06735, 1.0)):.4f}")
    0.2785
    """
    contact = require_contact(contact)
    m = _array_in('mass', mass, *MASS_RANGE)     # numbers or arrays
    v = require_speeds(speed, 'speed')
    law = contact.law
    with np.errstate(all='ignore'):
        length, _ = impact_scales(law, contact.stiffness, m, v)
        zeta = damping_group_of(law, contact.damping, m, length, v)
    if not np.all(np.isfinite(zeta)):
        raise InputError('speed', None, 'the damping group of these {n[speed]}, {n[stiffness]}, '
                         '{n[mass]} and {n[damping]} overflows: allowed values whose zeta is a '
                         'finite number')
    return zeta


def _array_in(name, values, low, high, low_open=False):
    """``values`` (a number or an array) as floats, each finite and in [low, high] (low
    excluded when ``low_open``), else ``InputError`` naming ``name`` and the range."""
    x = require_real_array(name, values)
    bad = (x <= low if low_open else x < low) | (x > high)
    if np.any(bad):
        worst = float(x[bad].flat[0])
        raise InputError(name, worst, '{n[%s]} = {value} is out of range: allowed %s'
                         % (name, range_text(name, low, high, low_open=low_open)),
                         value=repr(worst))
    return x if x.ndim else float(x)


def damping_from_group(law, stiffness, mass, speed, zeta):
    """λ that gives the group ``zeta`` at ``speed``: the inverse of ``damping_group``."""
    length, _ = impact_scales(law, stiffness, mass, speed)
    return zeta * mass / (length ** (law.p + 1.0) * np.asarray(speed, dtype=float) ** (law.q - 2.0))


def _dimensional(quantity, contact, mass, speeds):
    contact = require_contact(contact)
    law = contact.law
    mass = require_mass(mass)
    speeds = require_speeds(speeds, 'speeds')   # first: a ragged list has no ndim
    scalar = np.ndim(speeds) == 0
    k = contact.stiffness
    length, time, zeta = checked_scales(contact, mass, speeds)
    value = dimensionless(quantity, law, zeta)
    scale = {'restitution': 1.0, 'duration': time, 'peak_force': k * length ** law.n,
             'max_penetration': length}[quantity]
    result = value * scale
    return float(result) if scalar else result


def _scalar_restitution(contact, mass, speed):
    """One speed, fully in Python floats: the ≤ 20 µs path used by services."""
    contact = require_contact(contact)
    law = contact.law
    zeta = checked_scales_at(contact, mass, speed, 'speeds')[2]   # raises, naming the speed
    closed = law.closed_form
    if zeta > 0.0 and closed is not None and closed.scalar is not None:
        return closed.scalar(zeta)
    if zeta > 0.0:
        curve = law.master_curve
        if curve is not None:
            value = curve.evaluate_scalar('restitution', zeta)
            if value is not None:
                return min(value, 1.0)
            tails = restitution_tails(law)
            if tails is not None:
                return tails.small(zeta) if zeta < tails.zeta0 else tails.large(zeta)
    return float(dimensionless('restitution', law, np.array(zeta)))


def restitution(contact, mass, speeds):
    """Coefficient of restitution of impacts at ``speeds`` without gravity.

    Vectorised: a scalar gives a float, an array an array of the same shape.  Agrees with
    ``simulate_impact`` to 1e-8 or better.

    Parameters
    ----------
    contact : Contact
        The contact (law, k, λ).
    mass : float
        The (reduced) mass, kg, > 0.
    speeds : float or array_like of float
        Impact speeds, m/s, > 0.

    Returns
    -------
    float or numpy.ndarray
        Restitution e = rebound speed / impact speed, 0 <= e <= 1, of the shape of ``speeds``.

    Raises
    ------
    InputError
        Keyed ``contact``, ``mass`` or ``speed``: not a ``Contact``, or a value out of range
        (a speed whose damping group or scales leave what the model answers).

    See Also
    --------
    simulate_impact : The exact, slow reference path.
    damping_for_restitution : The inverse, λ for a target e.

    Examples
    --------
    >>> import contact_sim as cs
    >>> contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron',
    ...                                     radius=0.0127, damping_factor=8.87e5)
    >>> mass = cs.build_mass(sphere='steel', radius=0.0127)
    >>> print(f"{cs.restitution(contact, mass, 1.0):.4f}")
    0.7381
    >>> print(*(f"{e:.4f}" for e in cs.restitution(contact, mass, [0.5, 1.0, 2.0])))
    0.7660 0.7381 0.7078
    >>> cs.restitution(contact, mass, -1.0)
    Traceback (most recent call last):
        ...
    contact_sim.validation.InputError: speeds = -1.0 is out of range: allowed 0 < speeds < inf (m/s)
    """
    if isinstance(speeds, (int, float)) and not isinstance(speeds, bool) \
            and math.isfinite(speeds) and speeds > 0.0 \
            and type(mass) in (int, float) and MASS_RANGE[0] <= mass <= MASS_RANGE[1]:   # no bool
        return _scalar_restitution(contact, float(mass), float(speeds))
    return _dimensional('restitution', contact, mass, speeds)


def contact_duration(contact, mass, speeds):
    """Contact duration of impacts at ``speeds``, touch to lift-off, without gravity.

    Parameters
    ----------
    contact : Contact
        The contact (law, k, λ).
    mass : float
        The (reduced) mass, kg, > 0.
    speeds : float or array_like of float
        Impact speeds, m/s, > 0.

    Returns
    -------
    float or numpy.ndarray
        The durations in s, of the shape of ``speeds``.

    Raises
    ------
    InputError
        Keyed ``contact``, ``mass`` or ``speed``: not a ``Contact``, or a value out of range
        (a speed whose damping group or scales leave what the model answers).

    Examples
    --------
    >>> import contact_sim as cs
    >>> contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron',
    ...                                     radius=0.0127, damping_factor=8.87e5)
    >>> mass = cs.build_mass(sphere='steel', radius=0.0127)
    >>> print(f"{cs.contact_duration(contact, mass, 1.0) * 1e6:.2f} us")
    100.24 us
    """
    return _dimensional('duration', contact, mass, speeds)


def peak_force(contact, mass, speeds):
    """Peak contact force of impacts at ``speeds``, without gravity.

    Parameters
    ----------
    contact : Contact
        The contact (law, k, λ).
    mass : float
        The (reduced) mass, kg, > 0.
    speeds : float or array_like of float
        Impact speeds, m/s, > 0.

    Returns
    -------
    float or numpy.ndarray
        The peak forces in N, of the shape of ``speeds``.

    Raises
    ------
    InputError
        Keyed ``contact``, ``mass`` or ``speed``: not a ``Contact``, or a value out of range
        (a speed whose damping group or scales leave what the model answers).

    Examples
    --------
    >>> import contact_sim as cs
    >>> contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron',
    ...                                     radius=0.0127, damping_factor=8.87e5)
    >>> mass = cs.build_mass(sphere='steel', radius=0.0127)
    >>> print(*(f"{f:.1f}" for f in cs.peak_force(contact, mass, [0.5, 1.0, 2.0])))
    892.4 2019.2 4564.7
    """
    return _dimensional('peak_force', contact, mass, speeds)


def max_penetration(contact, mass, speeds):
    """Maximum penetration of impacts at ``speeds``, without gravity.

    Parameters
    ----------
    contact : Contact
        The contact (law, k, λ).
    mass : float
        The (reduced) mass, kg, > 0.
    speeds : float or array_like of float
        Impact speeds, m/s, > 0.

    Returns
    -------
    float or numpy.ndarray
        The deepest penetrations in m, of the shape of ``speeds``.

    Raises
    ------
    InputError
        Keyed ``contact``, ``mass`` or ``speed``: not a ``Contact``, or a value out of range
        (a speed whose damping group or scales leave what the model answers).

    Examples
    --------
    >>> import contact_sim as cs
    >>> contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron',
    ...                                     radius=0.0127, damping_factor=8.87e5)
    >>> mass = cs.build_mass(sphere='steel', radius=0.0127)
    >>> print(f"{cs.max_penetration(contact, mass, 1.0) * 1e6:.3f} um")
    31.851 um
    """
    return _dimensional('max_penetration', contact, mass, speeds)

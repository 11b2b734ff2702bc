"""Hertz contact geometry for spheres and plates (Azad & Featherstone 2014, eqs. 5, 6, 10).

Radii in m (a flat plate has infinite radius), moduli in Pa, masses in kg.
"""
import math

from contact_sim.model.materials import get_material
from contact_sim.validation import InputError, require_positive


def effective_modulus(a, b):
    """E* with 1/E* = (1 - ν1²)/E1 + (1 - ν2²)/E2 (eq. 6), for two ``Material`` values or
    library names (Pa)."""
    a, b = get_material(a), get_material(b)
    return 1.0 / ((1.0 - a.poisson_ratio ** 2) / a.youngs_modulus
                  + (1.0 - b.poisson_ratio ** 2) / b.youngs_modulus)


def equivalent_radius(r1, r2=math.inf):
    """R with 1/R = 1/R1 + 1/R2 (eq. 10); ``r2 = inf`` is a flat plate (m)."""
    r1 = require_positive('radius', r1, allow_inf=True)
    r2 = require_positive('plate_radius', r2, allow_inf=True)
    if math.isinf(r1) and math.isinf(r2):
        raise InputError('radius', r1, '{n[radius]} = inf and {n[plate_radius]} = inf: at least '
                         'one radius must be finite')
    return 1.0 / (1.0 / r1 + 1.0 / r2)


def hertz_stiffness(effective_modulus, radius):
    """k = (4/3) E* √R (eq. 5), in N/m^1.5, for the Hertz force F = k z^1.5."""
    e_star = require_positive('effective_modulus', effective_modulus)
    r = require_positive('radius', radius)
    return 4.0 / 3.0 * e_star * math.sqrt(r)


def reduced_mass(m1, m2=math.inf):
    """m = m1 m2 / (m1 + m2) in kg; ``m2 = inf`` is an immovable plate."""
    m1 = require_positive('mass', m1, allow_inf=True)
    m2 = require_positive('plate_mass', m2, allow_inf=True)
    if math.isinf(m1) and math.isinf(m2):
        raise ValueError('mass = inf and plate_mass = inf: at least one mass must be finite')
    if math.isinf(m2):
        return m1
    if math.isinf(m1):
        return m2
    return m1 * m2 / (m1 + m2)


def sphere_mass(density, radius):
    """Mass of a solid sphere, (4/3) π R³ ρ, in kg."""
    r = require_positive('radius', radius)
    rho = require_positive('density', density)
    try:
        mass = 4.0 / 3.0 * math.pi * r ** 3 * rho
    except OverflowError:
        mass = math.inf
    if not 0.0 < mass < math.inf:
        raise InputError('radius', r, '{n[radius]} = {value} m gives a sphere mass (4/3) pi R^3 '
                         'rho = %r kg: allowed radii whose mass is a positive finite number'
                         % mass)
    return mass

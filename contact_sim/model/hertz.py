"""Hertz contact geometry for spheres and plates (Azad & Featherstone 2014, eqs. 5, 6, 10).

Radii in m (a flat plate has infinite radius), moduli in Pa, masses in kg.
"""
import math

from contact_sim.model.materials import get_material
from contact_sim.validation import InputError, require_positive


def effective_modulus(a, b):
    """Effective modulus E* of two elastic bodies in contact (equation 6).

    1/E* = (1 - ν1²)/E1 + (1 - ν2²)/E2.

    Parameters
    ----------
    a, b : Material or str
        The two materials, as ``Material`` values or names in ``MATERIALS``.

    Returns
    -------
    float
        Effective modulus E*, Pa, > 0.

    Raises
    ------
    InputError
        Keyed ``material``: a name that is not in ``MATERIALS``.

    See Also
    --------
    hertz_stiffness : The Hertz k = (4/3) E* √R.

    Examples
    --------
    >>> import contact_sim as cs
    >>> print(f"{cs.effective_modulus('steel', 'cast_iron'):.4e}")
    7.2886e+10
    """
    a, b = get_material(a), get_material(b)
    return 1.0 / ((1.0 - a.poisson_ratio ** 2) / a.youngs_modulus
                  + (1.0 - b.poisson_ratio ** 2) / b.youngs_modulus)


RADIUS_MIN = 1e-300   # m: below ~5.6e-309, 1/R overflows and R underflows to 0


def equivalent_radius(radius, plate_radius=math.inf):
    """Equivalent radius R of two spheres in contact (equation 10): 1/R = 1/R1 + 1/R2.

    Parameters
    ----------
    radius : float
        Radius R1 of the first sphere, m, > 0 (``inf`` allowed if ``plate_radius`` is
        finite).
    plate_radius : float, optional
        Radius R2 of the second body, m, > 0; the default ``inf`` is a flat plate.

    Returns
    -------
    float
        Equivalent radius R, m, > 0.

    Raises
    ------
    InputError
        Keyed ``radius`` or ``plate_radius`` (the arguments' names): a radius that is not a
        number > 0.
    ValueError
        Both radii infinite.

    Examples
    --------
    >>> import contact_sim as cs
    >>> cs.equivalent_radius(0.0127)          # a sphere on a flat plate
    0.0127
    >>> print(f"{cs.equivalent_radius(0.015, 0.015):.4f}")   # two 15 mm spheres
    0.0075
    """
    r1 = require_positive('radius', radius, allow_inf=True)   # named as the caller wrote them
    r2 = require_positive('plate_radius', plate_radius, allow_inf=True)
    if math.isinf(r1) and math.isinf(r2):
        raise InputError('radius', r1, '{n[radius]} = inf and {n[plate_radius]} = inf: at least '
                         'one radius must be finite')
    for key, r in (('radius', r1), ('plate_radius', r2)):
        if r < RADIUS_MIN:   # 1/r overflows: R would be 0
            raise InputError(key, r, '{n[%s]} = {value} m is out of range: allowed %g <= '
                             '{n[%s]} (1/R = 1/R1 + 1/R2 a finite double)' % (key, RADIUS_MIN, key),
                             value=repr(r))
    return 1.0 / (1.0 / r1 + 1.0 / r2)


def hertz_stiffness(effective_modulus, radius):
    """Hertz stiffness k = (4/3) E* √R (equation 5) of the force F = k z^1.5.

    Parameters
    ----------
    effective_modulus : float
        Effective modulus E*, Pa, > 0 (``effective_modulus``).
    radius : float
        Equivalent radius R in m, > 0 (``equivalent_radius``).

    Returns
    -------
    float
        Stiffness k, N/m^1.5.

    Raises
    ------
    InputError
        Keyed ``effective_modulus`` or ``radius``: a value that is not a finite number > 0.

    Examples
    --------
    >>> import contact_sim as cs
    >>> e_star = cs.effective_modulus('steel', 'cast_iron')
    >>> print(f"{cs.hertz_stiffness(e_star, 0.0127):.4e}")
    1.0952e+10
    """
    e_star = require_positive('effective_modulus', effective_modulus)
    r = require_positive('radius', radius)
    return 4.0 / 3.0 * e_star * math.sqrt(r)


def reduced_mass(m1, m2=math.inf):
    """Reduced mass m = m1 m2 / (m1 + m2) of two bodies.

    Parameters
    ----------
    m1 : float
        Mass of the sphere, kg, > 0 (``inf`` allowed if ``m2`` is finite).
    m2 : float, optional
        Mass of the plate, kg, > 0; the default ``inf`` is an immovable plate.

    Returns
    -------
    float
        Reduced mass m, kg (``m1`` itself for an immovable plate).

    Raises
    ------
    InputError
        Keyed ``mass`` or ``plate_mass``: a mass that is not a number > 0.
    ValueError
        Both masses infinite.

    Examples
    --------
    >>> import contact_sim as cs
    >>> cs.reduced_mass(0.5)
    0.5
    >>> cs.reduced_mass(1.0, 3.0)
    0.75
    """
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
    """Mass of a solid sphere, (4/3) π R³ ρ.

    Parameters
    ----------
    density : float
        Density ρ, kg/m³, > 0.
    radius : float
        Equivalent radius R, m, > 0.

    Returns
    -------
    float
        The mass in kg, positive and finite.

    Raises
    ------
    InputError
        Keyed ``density`` or ``radius``: a value that is not a number > 0, or a radius whose
        mass overflows.

    Examples
    --------
    >>> import contact_sim as cs
    >>> print(f"{cs.sphere_mass(7850.0, 0.0127):.5f}")    # a 12.7 mm steel ball
    0.06735
    """
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

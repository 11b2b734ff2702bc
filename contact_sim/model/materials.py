"""Elastic materials: Young's modulus E (Pa), Poisson ratio ν (-), density ρ (kg/m³).

Every library value carries its source. Handbook values are typical room-temperature figures;
real batches vary by several per cent (cast iron and cork by much more), so calibrate damping
against measured restitution for the pair you simulate.
"""
from dataclasses import dataclass

from contact_sim.validation import InputError, require_range

_HANDBOOK = 'W. D. Callister, Materials Science and Engineering: An Introduction, Appendix B'


# The smallest modulus and density a Material takes: far below any solid's (gels have ~10 Pa),
# and above the subnormal values whose 1/E or R³ ρ underflow to an E* or a mass of 0.
MODULUS_MIN = 1.0      # Pa
DENSITY_MIN = 1e-3     # kg/m³


@dataclass(frozen=True)
class Material:
    """An isotropic linear-elastic material (SI units); frozen, checked when built.

    Attributes
    ----------
    name : str
        A non-empty name (the key in ``MATERIALS`` for a library material).
    youngs_modulus : float
        Young's modulus E, Pa, >= ``MODULUS_MIN`` (1 Pa).
    poisson_ratio : float
        Poisson ratio ν, dimensionless, -1 < ν < 0.5.
    density : float
        Density ρ, kg/m³, >= ``DENSITY_MIN`` (1e-3 kg/m³).
    source : str
        Where the values come from (default ``'user supplied'``).

    Raises
    ------
    InputError
        Keyed ``youngs_modulus``, ``poisson_ratio`` or ``density``: a value out of its range.
    ValueError
        An empty or non-string ``name``.

    See Also
    --------
    get_material : A library material by name.

    Examples
    --------
    >>> import contact_sim as cs
    >>> rubber = cs.Material('rubber', 0.01e9, 0.49, 1100.0)
    >>> rubber.youngs_modulus
    10000000.0
    >>> cs.Material('rubber', 0.01e9, 0.6, 1100.0)
    Traceback (most recent call last):
        ...
    contact_sim.validation.InputError: poisson_ratio = 0.6 is out of range: allowed -1 < poisson_ratio < 0.5
    """

    name: str
    youngs_modulus: float
    poisson_ratio: float
    density: float
    source: str = 'user supplied'

    def __post_init__(self):
        if not isinstance(self.name, str) or not self.name:
            raise ValueError(f'name = {self.name!r} is invalid: allowed a non-empty string')
        object.__setattr__(self, 'youngs_modulus',
                           require_range('youngs_modulus', self.youngs_modulus, MODULUS_MIN,
                                         unit='Pa'))
        object.__setattr__(self, 'poisson_ratio',
                           require_range('poisson_ratio', self.poisson_ratio, -1.0, 0.5,
                                         low_open=True, high_open=True))
        object.__setattr__(self, 'density', require_range('density', self.density, DENSITY_MIN,
                                                          unit='kg/m^3'))


#: The library materials, name -> ``Material`` (handbook values, each with its ``source``):
#: aluminium, brass, cast_iron, cork, glass, lead, nylon, steel.
MATERIALS = {m.name: m for m in (
    Material('steel', 207e9, 0.30, 7850.0, _HANDBOOK + ' (plain carbon steel 1020)'),
    Material('cast_iron', 100e9, 0.26, 7300.0,
             _HANDBOOK + ' (gray cast iron, E mid-range of the grades listed)'),
    Material('brass', 110e9, 0.35, 8530.0, _HANDBOOK + ' (cartridge brass 70Cu-30Zn)'),
    Material('lead', 13.5e9, 0.44, 11350.0, _HANDBOOK + ' (commercially pure lead)'),
    Material('aluminium', 69e9, 0.33, 2710.0, _HANDBOOK + ' (aluminium alloy 1100)'),
    Material('glass', 69e9, 0.23, 2500.0, _HANDBOOK + ' (soda-lime glass)'),
    Material('nylon', 2.8e9, 0.39, 1140.0, _HANDBOOK + ' (nylon 6,6, E mid-range)'),
    Material('cork', 20e6, 0.0, 170.0,
             'L. J. Gibson and M. F. Ashby, Cellular Solids, 2nd ed. (1997), ch. 12: cork, '
             'E about 13-50 MPa, near-zero Poisson ratio, density 120-240 kg/m3'),
)}


def get_material(name):
    """The library material of a name (a ``Material`` is returned as is).

    Parameters
    ----------
    name : str or Material
        A key of ``MATERIALS``, or a ``Material``.

    Returns
    -------
    Material
        The material.

    Raises
    ------
    InputError
        Keyed ``material`` (a ``ValueError``): an unknown name; the message lists the known ones.

    Examples
    --------
    >>> import contact_sim as cs
    >>> steel = cs.get_material('steel')
    >>> steel.youngs_modulus, steel.poisson_ratio, steel.density
    (207000000000.0, 0.3, 7850.0)
    >>> cs.get_material('unobtainium')
    Traceback (most recent call last):
        ...
    contact_sim.validation.InputError: material = 'unobtainium' is unknown: allowed one of aluminium, brass, cast_iron, cork, glass, lead, nylon, steel or a custom Material(name, youngs_modulus, poisson_ratio, density)
    """
    if isinstance(name, Material):
        return name
    try:
        return MATERIALS[name]
    except (KeyError, TypeError):
        raise InputError('material', name, '{n[material]} = {value} is unknown: allowed one of '
                         '%s or a custom Material(name, youngs_modulus, poisson_ratio, density)'
                         % ', '.join(sorted(MATERIALS)), value=repr(name)) from None

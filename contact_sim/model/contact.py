"""A contact: a force law with its stiffness k and damping λ (SI units, see ``laws``)."""
import math
from dataclasses import dataclass


from contact_sim.model.hertz import effective_modulus, equivalent_radius, hertz_stiffness, sphere_mass
from contact_sim.model.laws import ContactLaw, get_law, require_law
from contact_sim.model.materials import get_material
from contact_sim.validation import InputError, require_instance, require_nonnegative, require_positive


@dataclass(frozen=True)
class Contact:
    """A compliant contact F = k z^n + λ z^p ż|ż|^(q-1), clamped at zero (equation 11).

    Attributes
    ----------
    law : ContactLaw
        The force law (a name is refused: resolve it with ``get_law``, or use ``build_contact``).
    stiffness : float
        Stiffness k, N/m^n (N/m^1.5 for the Hertz laws), > 0.
    damping : float
        Damping λ, N·s^q/m^(p+q) (N·s/m^1.5 for Azad-Featherstone), >= 0.

    Raises
    ------
    InputError
        Keyed ``law``, ``stiffness`` or ``damping``: a law that is not a ``ContactLaw`` (a name
        among them) or a value out of range.

    See Also
    --------
    build_contact : The contact from materials or overrides.

    Examples
    --------
    >>> import contact_sim as cs
    >>> contact = cs.Contact(cs.AZAD_FEATHERSTONE, 1.095e10, 1e5)
    >>> contact.law is cs.AZAD_FEATHERSTONE
    True
    >>> cs.Contact(cs.LINEAR, -1.0, 0.0)
    Traceback (most recent call last):
        ...
    contact_sim.validation.InputError: stiffness = -1.0 is out of range: allowed 0 < stiffness
    """

    law: ContactLaw
    stiffness: float
    damping: float

    def __post_init__(self):
        require_law(self.law)
        object.__setattr__(self, 'stiffness', require_positive('stiffness', self.stiffness))
        object.__setattr__(self, 'damping', require_nonnegative('damping', self.damping))

    def force(self, z, zdot):
        """Clamped normal force at penetration z and penetration rate ż (equation 11).

        Parameters
        ----------
        z : float or array_like of float
            Penetration, m (z <= 0: no contact).
        zdot : float or array_like of float
            Penetration rate, m/s (> 0 is approach).

        Returns
        -------
        numpy.ndarray
            The force in N, >= 0, of the broadcast shape of ``z`` and ``zdot``.

        Examples
        --------
        >>> import contact_sim as cs
        >>> contact = cs.Contact(cs.AZAD_FEATHERSTONE, 1.095e10, 1e5)
        >>> print(*(f"{f:.3f}" for f in contact.force([1e-6, 2e-6], [0.5, -0.1])))
        60.950 16.829
        """
        return self.law.force(z, zdot, self.stiffness, self.damping)

    def force_at(self, z, zdot):
        """``force`` at one state, as a float.

        Parameters
        ----------
        z : float
            Penetration, m.
        zdot : float
            Penetration rate, m/s (> 0 is approach).

        Returns
        -------
        float
            The force in N, >= 0.

        Examples
        --------
        >>> import contact_sim as cs
        >>> print(f"{cs.Contact(cs.AZAD_FEATHERSTONE, 1.095e10, 1e5).force_at(1e-6, 0.5):.3f}")
        60.950
        """
        return self.law.force_at(float(z), float(zdot), self.stiffness, self.damping)

    def static_penetration(self, load):
        """Equilibrium depth z0 = (W / k)^(1/n) under a steady load W.

        Parameters
        ----------
        load : float
            Load W, N, >= 0 (m g for a resting sphere).

        Returns
        -------
        float
            Depth z0, m.

        Raises
        ------
        InputError
            Keyed ``load``: a negative or non-finite load.

        Examples
        --------
        >>> import contact_sim as cs
        >>> contact = cs.Contact(cs.AZAD_FEATHERSTONE, 1.095e10, 1e5)
        >>> print(f"{contact.static_penetration(0.066 * 9.81):.4e}")
        1.5177e-07
        """
        return (require_nonnegative('load', load) / self.stiffness) ** (1.0 / self.law.n)

    def rest_linearisation(self, load):
        """The linearised contact at static equilibrium under a load W.

        k' = dF/dz = n k z0^(n-1) and c' = dF/dż = λ z0^p (for q = 1), so that small motions
        about z0 obey m ÿ + c' ẏ + k' y = 0.

        Parameters
        ----------
        load : float
            Load W, N, >= 0.

        Returns
        -------
        tuple of float
            (z0 in m, k' in N/m, c' in N·s/m).

        Raises
        ------
        InputError
            Keyed ``load``: a negative or non-finite load.

        Examples
        --------
        >>> import contact_sim as cs
        >>> contact = cs.Contact(cs.AZAD_FEATHERSTONE, 1.095e10, 1e5)
        >>> z0, k1, c1 = contact.rest_linearisation(0.066 * 9.81)
        >>> print(f"{z0:.4e} {k1:.4e} {c1:.3f}")
        1.5177e-07 6.3989e+06 38.958
        """
        law = self.law
        z0 = self.static_penetration(load)
        return (z0, law.n * self.stiffness * z0 ** (law.n - 1.0), self.damping * z0 ** law.p)

    @classmethod
    def from_materials(cls, law, sphere, plate, radius, plate_radius=math.inf,
                       damping_factor=0.0):
        """Build k from Hertz theory (equations 5, 6, 10) and λ = λ* √R (equation 9).

        Parameters
        ----------
        law : ContactLaw
            A law with n = 1.5 (Hertz).
        sphere, plate : Material or str
            The materials, as ``Material`` values or names in ``MATERIALS``.
        radius : float
            The sphere's radius R1, m, > 0.
        plate_radius : float, optional
            The plate's radius of curvature R2, m, > 0; ``inf`` (default) is a flat plate.
        damping_factor : float, optional
            Damping factor λ*, N·s^q/m^(p+q+1/2) (N·s/m² for Azad-Featherstone), >= 0; the
            default 0 is a purely elastic contact.

        Returns
        -------
        Contact
            k = (4/3) E* √R in N/m^1.5 and λ = λ* √R.

        Raises
        ------
        InputError
            Keyed ``law`` (not a ``ContactLaw``), ``sphere``, ``plate`` (an unknown material),
            ``radius``, ``plate_radius`` or ``damping_factor`` (a value out of range), or
            ``stiffness``: a law without the Hertz exponent n = 1.5 (``build_contact``'s rule).

        See Also
        --------
        build_contact : The same rule, with overrides (this is ``build_contact`` without them).

        Examples
        --------
        >>> import contact_sim as cs
        >>> contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron',
        ...                                     radius=0.0127, damping_factor=8.87e5)
        >>> print(f"k = {contact.stiffness:.4e} N/m^1.5, lambda = {contact.damping:.4e}")
        k = 1.0952e+10 N/m^1.5, lambda = 9.9960e+04
        """
        return build_contact(require_law(law), sphere=sphere, plate=plate, radius=radius,
                             plate_radius=plate_radius, damping_factor=damping_factor)


def require_contact(contact, name='contact'):
    """Check that ``contact`` is a ``Contact``.

    Parameters
    ----------
    contact : object
        The value to check.
    name : str, optional
        The field the error names (default ``'contact'``).

    Returns
    -------
    Contact
        ``contact`` itself.

    Raises
    ------
    InputError
        Keyed ``name``: ``contact`` is not a ``Contact``.

    Examples
    --------
    >>> import contact_sim as cs
    >>> contact = cs.Contact(cs.LINEAR, 1e5, 2.0)
    >>> cs.require_contact(contact) is contact
    True
    >>> cs.require_contact(3)
    Traceback (most recent call last):
        ...
    contact_sim.validation.InputError: contact = 3 is not a Contact(law, stiffness, damping)
    """
    return require_instance(name, contact, Contact, 'a Contact(law, stiffness, damping)')


def build_contact(law, *, stiffness=None, damping=None, damping_factor=None, sphere=None,
                  plate=None, radius=None, plate_radius=math.inf):
    """The contact from materials or overrides: the one rule every front end uses.

    The one core function that takes a law's name (for the front ends and parameter files,
    resolved by ``get_law``); everything else in the core takes ``ContactLaw`` objects.

    * k = ``stiffness`` (N/m^n) if given, else the Hertz k = (4/3) E* √R (eqs. 5, 6, 10) from the
      ``sphere`` and ``plate`` materials (``Material`` or library name) and the radii (m); the
      Hertz k exists for laws with n = 1.5 only.
    * λ = ``damping`` if given, else λ = λ* √R (eq. 9) with λ* = ``damping_factor``.

    Parameters
    ----------
    law : ContactLaw or str
        The law, or its name in ``LAWS`` (resolved here, once).
    stiffness : float, optional
        Stiffness k, N/m^n, > 0; default: the Hertz k of the materials.
    damping : float, optional
        Damping λ, N·s^q/m^(p+q), >= 0; give it or ``damping_factor``, not both.
    damping_factor : float, optional
        Damping factor λ*, N·s^q/m^(p+q+1/2), >= 0; λ = λ* √R needs ``radius``.
    sphere, plate : Material or str, optional
        The materials (for the Hertz k), as ``Material`` values or names in ``MATERIALS``.
    radius : float, optional
        The sphere's radius R1, m, > 0.
    plate_radius : float, optional
        The plate's radius of curvature R2, m, > 0; ``inf`` (default) is a flat plate.

    Returns
    -------
    Contact
        The contact.

    Raises
    ------
    InputError
        Keyed by the argument (``law``, ``stiffness``, ``damping``, ``damping_factor``,
        ``sphere``, ``plate``, ``radius``, ``plate_radius``): a value out of range, an unknown
        name, a missing value, or both ``damping`` and ``damping_factor``.

    Examples
    --------
    >>> import contact_sim as cs
    >>> contact = cs.build_contact('azad_featherstone', sphere='steel', plate='cast_iron',
    ...                            radius=0.0127, damping_factor=8.87e5)
    >>> print(f"{contact.stiffness:.4e} {contact.damping:.4e}")
    1.0952e+10 9.9960e+04
    >>> cs.build_contact('linear', stiffness=1e5, damping=2.0)
    Contact(law=ContactLaw(name='linear', n=1.0, p=0.0, q=1.0), stiffness=100000.0, damping=2.0)
    >>> cs.build_contact('azad_featherstone', stiffness=1e10)
    Traceback (most recent call last):
        ...
    contact_sim.validation.InputError: damping is missing: give damping, or damping_factor with radius (lambda = lambda* sqrt(R)); 0 is elastic
    """
    law = get_law(law)
    r = None
    if radius is not None:
        r = equivalent_radius(radius, plate_radius)
    if stiffness is None:
        if sphere is None or plate is None or radius is None:
            raise InputError('stiffness', None, '{n[stiffness]} is missing: give {n[stiffness]} '
                             '(N/m^n), or {n[sphere]}, {n[plate]} and {n[radius]} for the Hertz '
                             'stiffness')
        k = _hertz_stiffness(law, sphere, plate, r)
    else:
        k = require_positive('stiffness', stiffness)
    if damping is not None and damping_factor is not None:
        raise InputError('damping', damping, '{n[damping]} and {n[damping_factor]} are both '
                         'given: allowed one of them')
    if damping is not None:
        lam = require_nonnegative('damping', damping)
    elif damping_factor is None:
        raise InputError('damping', None, '{n[damping]} is missing: give {n[damping]}, or '
                         '{n[damping_factor]} with {n[radius]} (lambda = lambda* sqrt(R)); '
                         '0 is elastic')
    else:
        factor = require_nonnegative('damping_factor', damping_factor)
        if r is None:
            raise InputError('damping_factor', factor, '{n[damping_factor]} needs {n[radius]}: '
                             'lambda = lambda* sqrt(R) (eq. 9)')
        lam = factor * math.sqrt(r)
    return Contact(law, k, lam)


def _hertz_stiffness(law, sphere, plate, r):
    """The one Hertz rule: k = (4/3) E* √R (eqs. 5, 6, 10) for a law with n = 1.5, else one
    ``InputError`` keyed ``stiffness`` (``Contact.from_materials`` and the front ends share it)."""
    if not law.hertz:
        raise InputError('stiffness', None, '{n[stiffness]} is missing: {n[law]} = %r has '
                         'n = %g and the Hertz stiffness needs n = 1.5; give {n[stiffness]} '
                         '(N/m^n)' % (law.name, law.n))
    return hertz_stiffness(effective_modulus(_material('sphere', sphere),
                                             _material('plate', plate)), r)


def _material(name, value):
    try:
        return get_material(value)
    except InputError as error:
        raise error.rekeyed(name) from None


def build_mass(mass=None, sphere=None, radius=None):
    """The (reduced) mass: ``mass`` if given, else (4/3) π R1³ ρ of the sphere's material.

    Parameters
    ----------
    mass : float, optional
        The mass, kg, > 0.
    sphere : Material or str, optional
        The sphere's material (for its density ρ), used when ``mass`` is not given.
    radius : float, optional
        The sphere's radius R1, m, > 0, used when ``mass`` is not given.

    Returns
    -------
    float
        The mass in kg.

    Raises
    ------
    InputError
        Keyed ``mass``, ``sphere`` or ``radius``: a value out of range, an unknown material, or
        neither ``mass`` nor ``sphere`` and ``radius``.

    Examples
    --------
    >>> import contact_sim as cs
    >>> cs.build_mass(0.05)
    0.05
    >>> print(f"{cs.build_mass(sphere='steel', radius=0.0127):.5f}")
    0.06735
    """
    if mass is not None:
        return require_positive('mass', mass)
    if sphere is None or radius is None:
        raise InputError('mass', None, '{n[mass]} is missing: give {n[mass]} (kg), or '
                         '{n[sphere]} and {n[radius]} for the sphere\'s mass from its density')
    return sphere_mass(_material('sphere', sphere).density, radius)

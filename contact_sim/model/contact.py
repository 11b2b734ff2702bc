"""A contact: a force law with its stiffness k and damping λ (SI units, see ``laws``)."""
import math
from dataclasses import dataclass

import numpy as np

from contact_sim.model.hertz import effective_modulus, equivalent_radius, hertz_stiffness, sphere_mass
from contact_sim.model.laws import ContactLaw, get_law
from contact_sim.model.materials import get_material
from contact_sim.validation import InputError, require_instance, require_nonnegative, require_positive


@dataclass(frozen=True)
class Contact:
    """A compliant contact F = k z^n + λ z^p ż|ż|^(q-1), clamped at zero (eq. 11)."""

    law: ContactLaw
    stiffness: float
    damping: float

    def __post_init__(self):
        object.__setattr__(self, 'law', get_law(self.law))
        object.__setattr__(self, 'stiffness', require_positive('stiffness', self.stiffness))
        object.__setattr__(self, 'damping', require_nonnegative('damping', self.damping))

    def force(self, z, zdot):
        """Clamped normal force (N) at penetration z (m) and penetration rate ż (m/s)."""
        return self.law.force(z, zdot, self.stiffness, self.damping)

    def force_at(self, z, zdot):
        """``force`` at one state, as a float (N)."""
        return self.law.force_at(float(z), float(zdot), self.stiffness, self.damping)

    def static_penetration(self, load):
        """Equilibrium depth z0 = (W / k)^(1/n) in m under a steady load W (N)."""
        return (require_nonnegative('load', load) / self.stiffness) ** (1.0 / self.law.n)

    def rest_linearisation(self, load):
        """(z0, k', c') at static equilibrium under ``load`` W (N): the depth z0 (m), and
        k' = dF/dz = n k z0^(n-1) (N/m) and c' = dF/dż = λ z0^p (N·s/m) for q = 1, so that small
        motions about z0 obey m ÿ + c' ẏ + k' y = 0."""
        law = self.law
        z0 = self.static_penetration(load)
        return (z0, law.n * self.stiffness * z0 ** (law.n - 1.0), self.damping * z0 ** law.p)

    @classmethod
    def from_materials(cls, law, sphere, plate, radius, plate_radius=math.inf,
                       damping_factor=0.0):
        """Build k from Hertz theory (eqs. 5, 6, 10) and λ = λ* √R (eq. 9).

        ``sphere`` and ``plate`` are ``Material`` values or library names; ``radius`` and
        ``plate_radius`` in m (``inf`` is a flat plate); ``damping_factor`` is λ*, in
        N·s/m² for the Azad-Featherstone law (the default 0 is a purely elastic contact).
        """
        law = get_law(law)
        if not law.hertz:
            raise ValueError(f'law = {law.name!r} has n = {law.n:g}: Hertz stiffness needs n = 1.5 '
                             '(allowed: azad_featherstone, hunt_crossley, lee_wang or a custom '
                             'law with n = 1.5)')
        r = equivalent_radius(radius, plate_radius)
        e_star = effective_modulus(get_material(sphere), get_material(plate))
        lam_star = require_nonnegative('damping_factor', damping_factor)
        return cls(law, hertz_stiffness(e_star, r), lam_star * np.sqrt(r))


def require_contact(contact, name='contact'):
    """Return ``contact`` if it is a ``Contact``, else raise ``InputError`` naming ``name``."""
    return require_instance(name, contact, Contact, 'a Contact(law, stiffness, damping)')


def build_contact(law, *, stiffness=None, damping=None, damping_factor=None, sphere=None,
                  plate=None, radius=None, plate_radius=math.inf):
    """The contact from materials or overrides: the one rule every front end uses.

    * k = ``stiffness`` (N/m^n) if given, else the Hertz k = (4/3) E* √R (eqs. 5, 6, 10) from the
      ``sphere`` and ``plate`` materials (``Material`` or library name) and the radii (m); the
      Hertz k exists for laws with n = 1.5 only.
    * λ = ``damping`` if given, else λ = λ* √R (eq. 9) with λ* = ``damping_factor``.

    Errors are ``InputError`` keyed by these argument names (``law``, ``stiffness``, ``damping``,
    ``damping_factor``, ``sphere``, ``plate``, ``radius``, ``plate_radius``).
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
        if not law.hertz:
            raise InputError('stiffness', None, '{n[stiffness]} is missing: {n[law]} = %r has '
                             'n = %g and the Hertz stiffness needs n = 1.5; give {n[stiffness]} '
                             '(N/m^n)' % (law.name, law.n))
        k = hertz_stiffness(effective_modulus(_material('sphere', sphere),
                                              _material('plate', plate)), r)
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


def _material(name, value):
    try:
        return get_material(value)
    except InputError as error:
        raise error.rekeyed(name) from None


def build_mass(mass=None, sphere=None, radius=None):
    """The (reduced) mass in kg: ``mass`` if given, else (4/3) π R1³ ρ of the ``sphere`` material
    of radius ``radius`` (m).  Errors are ``InputError`` keyed ``mass``, ``sphere``, ``radius``."""
    if mass is not None:
        return require_positive('mass', mass)
    if sphere is None or radius is None:
        raise InputError('mass', None, '{n[mass]} is missing: give {n[mass]} (kg), or '
                         '{n[sphere]} and {n[radius]} for the sphere\'s mass from its density')
    return sphere_mass(_material('sphere', sphere).density, radius)

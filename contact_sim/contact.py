"""A contact: a force law with its stiffness k and damping λ (SI units, see ``laws``)."""
import math
from dataclasses import dataclass

import numpy as np

from .hertz import effective_modulus, equivalent_radius, hertz_stiffness
from .laws import ContactLaw, get_law
from .materials import get_material
from .validation import require_nonnegative, require_positive


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
        if law.n != 1.5:
            raise ValueError(f'law = {law.name!r} has n = {law.n:g}: Hertz stiffness needs n = 1.5 '
                             '(allowed: azad_featherstone, hunt_crossley, lee_wang or a custom '
                             'law with n = 1.5)')
        r = equivalent_radius(radius, plate_radius)
        e_star = effective_modulus(get_material(sphere), get_material(plate))
        lam_star = require_nonnegative('damping_factor', damping_factor)
        return cls(law, hertz_stiffness(e_star, r), lam_star * np.sqrt(r))

"""The default contact, defined once: the README's steel ball on a cast-iron plate.

The ROS node declares its parameters' defaults from it and the command line falls back to it
when no contact is given, so both simulate the same sphere unless told otherwise.
"""
from dataclasses import dataclass

from contact_sim.model.contact import build_contact, build_mass


@dataclass(frozen=True)
class DefaultContact:
    """A contact given as materials, a radius and a damping factor (the paper's eq. 9).

    Attributes
    ----------
    law : str
        The contact law's name.
    sphere, plate : str
        Library material names (``MATERIALS``) of the sphere and of the flat plate.
    radius : float
        The sphere's radius R1, m.
    damping_factor : float
        λ*, N s/m^2 for azad_featherstone: λ = λ* √R (eq. 9).

    Examples
    --------
    >>> from contact_sim.model import DEFAULT_CONTACT
    >>> print(DEFAULT_CONTACT.describe())
    steel sphere R1 = 0.0127 m on cast_iron (flat), azad_featherstone law, lambda* = 8.87e+05
    >>> print(f"{DEFAULT_CONTACT.mass():.4f} kg")
    0.0674 kg
    """

    law: str
    sphere: str
    plate: str
    radius: float
    damping_factor: float

    def contact(self, law=None):
        """The ``Contact`` (Hertz stiffness, λ = λ* √R) of ``law`` (default: this one's).

        Parameters
        ----------
        law : str or ContactLaw, optional
            Another n = 1.5 law with the same materials and damping factor (a name is resolved
            by ``build_contact``, as the front ends' names are).

        Returns
        -------
        Contact
            The contact.

        Examples
        --------
        >>> from contact_sim.model import DEFAULT_CONTACT
        >>> print(f"{DEFAULT_CONTACT.contact().stiffness:.4e}")
        1.0952e+10
        """
        return build_contact(self.law if law is None else law, sphere=self.sphere,
                             plate=self.plate, radius=self.radius,
                             damping_factor=self.damping_factor)

    def mass(self):
        """The sphere's mass (4/3) π R1³ ρ, kg.

        Returns
        -------
        float
            The mass, kg.

        Examples
        --------
        >>> from contact_sim.model import DEFAULT_CONTACT
        >>> DEFAULT_CONTACT.mass() > 0.0
        True
        """
        return build_mass(sphere=self.sphere, radius=self.radius)

    def describe(self):
        """One line naming the bodies, the law and λ*.

        Returns
        -------
        str
            E.g. ``steel sphere R1 = 0.0127 m on cast_iron (flat), ...``.

        Examples
        --------
        >>> from contact_sim.model import DEFAULT_CONTACT
        >>> DEFAULT_CONTACT.describe().startswith('steel sphere')
        True
        """
        return (f'{self.sphere} sphere R1 = {self.radius:g} m on {self.plate} (flat), '
                f'{self.law} law, lambda* = {self.damping_factor:.3g}')


# The README's example and the node's parameter defaults: a 1/2-inch steel ball on cast iron
# with λ* = 8.87e5 N s/m², the paper's steel-on-cast-iron drop value (docs/limits.md).
DEFAULT_CONTACT = DefaultContact(law='azad_featherstone', sphere='steel', plate='cast_iron',
                                 radius=0.0127, damping_factor=8.87e5)

"""The model: contact laws (eq. 1), materials, Hertz geometry (eqs. 5, 6, 10) and the contact.

The lowest layer: it knows nothing of time.  ``laws`` (the law family and its registry: what
each law can do), ``closed_forms`` (exact dimensionless impact results of Hunt-Crossley and the
linear law, functions of ζ), ``master_curves`` (the shipped tables of the named laws),
``materials`` (elastic constants and densities), ``hertz`` (E*, R, k, masses), ``contact``
(a law with its stiffness and damping; ``build_contact``, the one rule from materials or
overrides), ``defaults`` (the default contact of the node and the command line).
"""
from contact_sim.model.contact import Contact, build_contact, build_mass, require_contact
from contact_sim.model.hertz import (effective_modulus, equivalent_radius, hertz_stiffness,
                                     reduced_mass, sphere_mass)
from contact_sim.model.closed_forms import ClosedForm
from contact_sim.model.laws import (AZAD_FEATHERSTONE, CLOSED_FORMS, HUNT_CROSSLEY, LAWS, LEE_WANG,
                                    LINEAR, ContactLaw, get_law, register_closed_form, require_law)
from contact_sim.model.master_curves import QUANTITIES, MasterCurve
from contact_sim.model.materials import (DENSITY_MIN, MATERIALS, MODULUS_MIN, Material,
                                          get_material)
from contact_sim.model.defaults import DEFAULT_CONTACT, DefaultContact

__all__ = ['AZAD_FEATHERSTONE', 'CLOSED_FORMS', 'DEFAULT_CONTACT', 'DENSITY_MIN', 'DefaultContact',
           'HUNT_CROSSLEY', 'LAWS', 'LEE_WANG', 'LINEAR', 'MATERIALS', 'MODULUS_MIN', 'QUANTITIES', 'ClosedForm', 'Contact', 'ContactLaw', 'MasterCurve',
           'Material', 'build_contact', 'build_mass', 'effective_modulus', 'equivalent_radius',
           'get_law', 'get_material', 'hertz_stiffness', 'reduced_mass', 'register_closed_form',
           'require_contact', 'require_law', 'sphere_mass']

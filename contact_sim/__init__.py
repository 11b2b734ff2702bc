"""contact_sim: the Azad-Featherstone compliant contact model and its relatives.

The core library imports neither rclpy nor any ROS package; only ``contact_sim.node`` does.
SI units throughout; z > 0 is penetration and ż > 0 is approach.
"""
from .contact import Contact
from .hertz import effective_modulus, equivalent_radius, hertz_stiffness, reduced_mass, sphere_mass
from .laws import AZAD_FEATHERSTONE, HUNT_CROSSLEY, LAWS, LEE_WANG, LINEAR, ContactLaw, get_law
from .materials import MATERIALS, Material, get_material

__version__ = '0.1.0'

__all__ = [
    'AZAD_FEATHERSTONE', 'HUNT_CROSSLEY', 'LAWS', 'LEE_WANG', 'LINEAR', 'MATERIALS',
    'Contact', 'ContactLaw', 'Material', 'effective_modulus', 'equivalent_radius', 'get_law',
    'get_material', 'hertz_stiffness', 'reduced_mass', 'sphere_mass',
]

"""contact_sim: the Azad-Featherstone compliant contact model and its relatives.

The core library imports neither rclpy nor any ROS package; only the ``contact_sim.ros``
subpackage (the node, the recorder) does.
SI units throughout; z > 0 is penetration and ż > 0 is approach.
"""
from contact_sim.calibration.bounce_fit import fit_bounces
from contact_sim.calibration.bounces import predict_bounces
from contact_sim.model.contact import Contact, build_contact, build_mass, require_contact
from contact_sim.drop.engine import (Advance, DropResult, DropSimulation, DropState, ImpactRecord, Samples,
                   TickBatch, check_drop, simulate_drop)
from contact_sim.flight.drag import AirDrag, FlightPath
from contact_sim.impact.damping_fit import DampingFit, compare_laws, damping_for_restitution, fit_damping
from contact_sim.model.hertz import effective_modulus, equivalent_radius, hertz_stiffness, reduced_mass, sphere_mass
from contact_sim.model.laws import AZAD_FEATHERSTONE, HUNT_CROSSLEY, LAWS, LEE_WANG, LINEAR, ContactLaw, get_law
from contact_sim.impact.simulate import ImpactResult, simulate_impact
from contact_sim.model.materials import MATERIALS, Material, get_material
from contact_sim.impact.restitution import (contact_duration, damping_group, max_penetration, peak_force,
                          restitution)
from contact_sim.validation import InputError

__version__ = '0.1.0'

__all__ = [
    'AZAD_FEATHERSTONE', 'HUNT_CROSSLEY', 'LAWS', 'LEE_WANG', 'LINEAR', 'MATERIALS',
    'AirDrag', 'Advance', 'Contact', 'ContactLaw', 'DampingFit', 'DropResult', 'DropSimulation', 'DropState',
    'FlightPath', 'ImpactRecord', 'ImpactResult', 'InputError', 'Material', 'Samples', 'TickBatch', 'build_contact',
    'build_mass', 'check_drop', 'compare_laws', 'contact_duration', 'require_contact',
    'damping_for_restitution', 'damping_group', 'effective_modulus', 'equivalent_radius',
    'fit_bounces', 'fit_damping', 'get_law', 'get_material', 'hertz_stiffness', 'max_penetration', 'peak_force', 'predict_bounces',
    'reduced_mass', 'restitution', 'simulate_drop', 'simulate_impact', 'sphere_mass',
]

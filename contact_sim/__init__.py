"""contact_sim: the Azad-Featherstone compliant contact model and its relatives.

The core library imports neither rclpy nor any ROS package; only the ``contact_sim.ros``
subpackage (the node, the recorder) does.  The layers, bottom up: ``model`` (laws, materials,
Hertz geometry, the contact), ``phase`` (one contact phase) and ``flight`` (flights in closed
form), ``impact`` (one impact, restitution, fits of λ), ``drop`` (the drop engine and the plate),
``calibration`` (recordings and the bounce-sequence fit); the front ends ``cli`` and ``ros``.
SI units throughout; z > 0 is penetration and ż > 0 is approach.
"""
from contact_sim.calibration import fit_bounces, predict_bounces
from contact_sim.drop import (Advance, DropResult, DropSimulation, DropState, ImpactRecord,
                              Samples, TickBatch, check_drop, simulate_drop)
from contact_sim.flight import AirDrag, FlightPath
from contact_sim.impact import (DampingFit, ImpactResult, compare_laws, contact_duration,
                                damping_for_restitution, damping_group, fit_damping,
                                max_penetration, peak_force, restitution, simulate_impact)
from contact_sim.model import (AZAD_FEATHERSTONE, HUNT_CROSSLEY, LAWS, LEE_WANG, LINEAR,
                               MATERIALS, Contact, ContactLaw, Material, build_contact,
                               build_mass, effective_modulus, equivalent_radius, get_law,
                               get_material, hertz_stiffness, reduced_mass, require_contact,
                               sphere_mass)
from contact_sim.validation import InputError

__version__ = '0.1.0'

__all__ = [
    'AZAD_FEATHERSTONE', 'HUNT_CROSSLEY', 'LAWS', 'LEE_WANG', 'LINEAR', 'MATERIALS',
    'AirDrag', 'Advance', 'Contact', 'ContactLaw', 'DampingFit', 'DropResult', 'DropSimulation',
    'DropState', 'FlightPath', 'ImpactRecord', 'ImpactResult', 'InputError', 'Material', 'Samples',
    'TickBatch', 'build_contact', 'build_mass', 'check_drop', 'compare_laws', 'contact_duration',
    'require_contact', 'damping_for_restitution', 'damping_group', 'effective_modulus',
    'equivalent_radius', 'fit_bounces', 'fit_damping', 'get_law', 'get_material',
    'hertz_stiffness', 'max_penetration', 'peak_force', 'predict_bounces', 'reduced_mass',
    'restitution', 'simulate_drop', 'simulate_impact', 'sphere_mass',
]

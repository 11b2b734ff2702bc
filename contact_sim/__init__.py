"""contact_sim: the Azad-Featherstone compliant contact model and its relatives.

The core library imports neither rclpy nor any ROS package; only the ``contact_sim.ros``
subpackage (the node, the recorder) does.  The layers, bottom up: ``model`` (laws, materials,
Hertz geometry, the contact), ``phase`` (one contact phase) and ``flight`` (flights in closed
form), ``impact`` (one impact, restitution, fits of λ), ``drop`` (the drop engine and the plate),
``calibration`` (recordings and the bounce-sequence fit); the front ends ``cli`` and ``ros``.
SI units throughout; z > 0 is penetration and ż > 0 is approach.
"""
from contact_sim._lazy import lazy_exports
from contact_sim.validation import InputError

# The public names, each from its layer, imported on first use (PEP 562, ``contact_sim._lazy``):
# `import contact_sim` and the command line's argument parsing do not pay for numpy, scipy and
# the compiled engine.  A layer (``contact_sim.impact``) is reached the same way.
_EXPORTS = {
    'contact_sim.calibration': ('fit_bounces', 'predict_bounces'),
    'contact_sim.drop': ('AdvanceResult', 'DropResult', 'DropSimulation', 'DropState', 'ImpactRecord',
                         'Samples', 'TickBatch', 'check_drop', 'simulate_drop'),
    'contact_sim.flight': ('AirDrag', 'FlightPath'),
    'contact_sim.impact': ('DampingFit', 'ImpactResult', 'compare_laws', 'contact_duration',
                           'damping_for_restitution', 'damping_group', 'fit_damping',
                           'max_penetration', 'peak_force', 'restitution', 'simulate_impact'),
    'contact_sim.model': ('AZAD_FEATHERSTONE', 'Contact', 'ContactLaw', 'HUNT_CROSSLEY', 'LAWS',
                          'LEE_WANG', 'LINEAR', 'MATERIALS', 'Material', 'build_contact',
                          'build_mass', 'effective_modulus', 'equivalent_radius', 'get_law',
                          'get_material', 'hertz_stiffness', 'reduced_mass', 'require_contact',
                          'sphere_mass'),
}
__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)

__version__ = '0.1.0'

__all__ = [
    'AZAD_FEATHERSTONE', 'HUNT_CROSSLEY', 'LAWS', 'LEE_WANG', 'LINEAR', 'MATERIALS',
    'AirDrag', 'AdvanceResult', 'Contact', 'ContactLaw', 'DampingFit', 'DropResult', 'DropSimulation',
    'DropState', 'FlightPath', 'ImpactRecord', 'ImpactResult', 'InputError', 'Material', 'Samples',
    'TickBatch', 'build_contact', 'build_mass', 'check_drop', 'compare_laws', 'contact_duration',
    'require_contact', 'damping_for_restitution', 'damping_group', 'effective_modulus',
    'equivalent_radius', 'fit_bounces', 'fit_damping', 'get_law', 'get_material',
    'hertz_stiffness', 'max_penetration', 'peak_force', 'predict_bounces', 'reduced_mass',
    'restitution', 'simulate_drop', 'simulate_impact', 'sphere_mass',
]

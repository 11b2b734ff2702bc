"""``contact_sim.ros.params`` without a ROS process: the presets and the built-in defaults,
``build_model``'s refusals (naming the parameter the user set, the depth check at its exact
bound), ``check_running`` and the flat plate. (``params`` imports rcl_interfaces for its
descriptors, so these are ``ros`` tests too.)
"""
import math
import re

import numpy as np
import pytest

import rclpy  # noqa: E402,F401  (pinned: a missing install fails here)

import contact_sim as cs  # noqa: E402
from contact_sim.ros import params as cs_params  # noqa: E402
from contact_sim.drop import SinusoidalPlate, plate  # noqa: E402
from contact_sim.validation import InputError  # noqa: E402
from .harness import CONFIG, yaml_parameters  # noqa: E402


def test_default_yaml_equals_the_built_in_defaults():
    values = yaml_parameters(CONFIG / 'default.yaml')
    assert values == cs_params.DEFAULTS
    for path in sorted(CONFIG.glob('*.yaml')):
        values = {**cs_params.DEFAULTS, **yaml_parameters(path)}
        assert set(values) == set(cs_params.DEFAULTS), path.name  # no unknown keys
        cs_params.build_model(values)  # valid


@pytest.mark.parametrize('path', sorted(CONFIG.glob('*.yaml')), ids=lambda p: p.stem)
def test_every_preset_simulates_to_rest_without_error(path):
    model = cs_params.build_model({**cs_params.DEFAULTS, **yaml_parameters(path)})
    sim = cs_params.make_simulation(model)
    for t in np.arange(0.5, 10.01, 0.5):
        while sim.time < t:
            sim.advance(t, max_steps=20000)
        state = sim.state
        assert all(math.isfinite(v) for v in (state.penetration, state.penetration_rate,
                                              state.force))
    assert math.isfinite(sim.settle_time), path.name


def test_a_contact_too_soft_for_the_drop_is_rejected_at_the_exact_bound():
    """k below (n+1)(m v1²/2 + m g R)/R^(n+1) lets the undamped sphere sink deeper than its
    radius R: such a value is rejected with the bound, and the bound is where the depth is R."""
    values = {**cs_params.DEFAULTS, 'stiffness': 5e4}
    with pytest.raises(ValueError) as error:
        cs_params.build_model(values)
    match = re.search(r'allowed stiffness >= ([0-9.e+]+) N/m\^1.5 or initial_height <= '
                      r'([0-9.e+]+) m', str(error.value))
    assert match and str(error.value).startswith('stiffness = 5e+04'), error.value
    minimum, highest = float(match.group(1)), float(match.group(2))
    model = cs_params.build_model({**values, 'stiffness': minimum * 1.001})
    cs_params.build_model({**values, 'initial_height': highest * 0.999})  # accepted
    radius = model.radius

    def first_depth(stiffness, height=model.height):
        undamped = cs.Contact(model.contact.law, stiffness, 0.0)
        sim = cs.DropSimulation(undamped, model.mass, height, gravity=model.gravity)
        while not sim.advance(sim.time + 0.1).impacts:
            pass
        return sim.impacts[0].max_penetration

    assert first_depth(minimum * 1.01) < radius < first_depth(minimum * 0.99)
    assert first_depth(5e4, highest * 0.99) < radius < first_depth(5e4, highest * 1.01)
    # the Hertz stiffness of soft custom materials is checked the same way
    soft = {**cs_params.DEFAULTS, 'sphere_material': 'custom', 'sphere_youngs_modulus': 1e3}
    with pytest.raises(ValueError, match=r'^stiffness = 165.1 N/m\^1.5 is too small for this '
                                         r'drop: .*\(stiffness = 0: k is the Hertz stiffness'):
        cs_params.build_model(soft)
    # no drop (no gravity, no speed), no bound
    cs_params.build_model({**values, 'stiffness': 1e-300, 'gravity': 0.0, 'initial_velocity': 0.0})


def test_the_depth_check_skips_a_sphere_that_never_lands_and_guards_the_running_drop():
    values = {**cs_params.DEFAULTS, 'stiffness': 1.0, 'damping': 0.0}
    soft = cs_params.Model(**{**vars(cs_params.build_model(cs_params.DEFAULTS)),
                              'contact': cs.Contact(cs.AZAD_FEATHERSTONE, 1.0, 0.0)})
    upwards = cs.DropSimulation(soft.contact, 0.067, 1.0, velocity=-1.0, gravity=0.0,
                                radius=0.0127)
    cs_params.check_running(upwards, soft, values, soft)  # never lands: nothing to check
    falling = cs.DropSimulation(cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 0.0), 0.067, 1.0,
                                velocity=-1.0, gravity=9.81, radius=0.0127)
    with pytest.raises(ValueError, match=r'^the running drop \(until ~/reset\) refuses it: '
                                         r'stiffness = 1 N/m\^1.5 is too small for this drop: '
                                         r'.* allowed stiffness >= '):
        cs_params.check_running(falling, soft, values, soft)
    with pytest.raises(ValueError, match='stiffness = 1 N/m'):   # as set_contact would refuse
        falling.set_contact(soft.contact)


def test_plate_radius_zero_is_the_flat_plate():
    flat = cs_params.build_model(dict(cs_params.DEFAULTS))
    assert math.isinf(flat.plate_radius)
    assert cs_params.build_model({**cs_params.DEFAULTS, 'plate_radius': math.inf}) == flat
    sphere = cs_params.build_model({**cs_params.DEFAULTS, 'plate_radius': 0.0127})
    assert sphere.contact.stiffness < flat.contact.stiffness  # R = R1 R2 / (R1 + R2)
    with pytest.raises(ValueError, match='plate_radius'):
        cs_params.build_model({**cs_params.DEFAULTS, 'plate_radius': -1.0})


@pytest.mark.parametrize('change, reason', [
    # found in review: each refusal named a core field, or a parameter the user had not set
    (dict(drag_coefficient=0.47, gravity=0.0),
     'gravity = 0.0 is out of range with air drag: .*drag_coefficient = 0 turns the air drag off'),
    (dict(sphere_radius=1e-12),
     r'sphere_mass = .* is out of range: .*\(sphere_mass = 0: the mass is \(4/3\) pi R1\^3 rho'),
    (dict(damping_factor=1e30),
     r'damping = .* is too large .*\(damping = 0: lambda = damping_factor sqrt\(R\)'),
    (dict(contact_law='linear'), "stiffness is missing: contact_law = 'linear' has n = 1"),
    (dict(plate_radius=-1.0), 'allowed 0 < plate_radius, or plate_radius = 0 for a flat plate'),
])
def test_refusals_name_the_parameter_the_user_set(change, reason):
    with pytest.raises(ValueError, match=reason):
        cs_params.build_model({**cs_params.DEFAULTS, **change})


def _model(**change):
    return cs_params.build_model({**cs_params.DEFAULTS, **change})


def test_build_model_makes_the_table_and_zero_amplitude_is_the_fixed_plate():
    assert _model().table is None
    assert _model(plate_frequency=20.0).table is None
    model = _model(plate_amplitude=0.001, plate_frequency=20.0, plate_phase=0.5)
    assert model.table == SinusoidalPlate(0.001, 20.0, 0.5)
    sim = cs_params.make_simulation(model)
    assert sim.plate == model.table and 'Gamma' in model.summary()


@pytest.mark.parametrize('change, reason', [
    (dict(plate_amplitude=math.nan), r'plate_amplitude = nan is not finite'),
    (dict(plate_amplitude=-0.001), r'plate_amplitude = -0.001 .*allowed 0 <= plate_amplitude'),
    (dict(plate_amplitude=0.5), r'allowed 0 <= plate_amplitude <= 0.1'),
    (dict(plate_frequency=-1.0), r'plate_frequency = -1.0 .*allowed 0 <= plate_frequency'),
    (dict(plate_phase=10.0), r'plate_phase = 10.0 .*<= plate_phase <= 6.28'),
    (dict(plate_amplitude=0.05, plate_frequency=100.0),
     r'plate_amplitude = 0.05 m at plate_frequency = 100 Hz .*plate_amplitude <= '),
    (dict(plate_amplitude=0.001, plate_frequency=20.0, gravity=0.0),
     'gravity = 0.0 is out of range with a moving plate.*plate_amplitude = 0 stops'),
])
def test_bad_table_parameters_are_refused_with_the_parameter_name(change, reason):
    with pytest.raises(ValueError, match=reason):
        _model(**change)


def test_check_running_refuses_a_table_too_fast_for_the_contact():
    # the running drop from 0.3 m hits at 2.4 m/s; the table's 0.31 m/s more sinks the sphere
    # deeper than its radius (the new model, from 1 mm at the next ~/reset, is fine)
    soft = dict(contact_law='linear', stiffness=3000.0, damping=1.0, initial_height=0.001)
    sim = cs_params.make_simulation(_model(**{**soft, 'initial_height': 0.3}))
    table = dict(plate_amplitude=0.005, plate_frequency=10.0)
    model = _model(**soft, **table)
    running = _model(**soft)
    cs_params.check_running(sim, running, {**cs_params.DEFAULTS, **soft}, running)
    with pytest.raises(ValueError, match='running drop .*stiffness = 3000 .* is too small'):
        cs_params.check_running(sim, model, {**cs_params.DEFAULTS, **soft, **table}, running)


def test_a_contact_and_a_table_changed_together_are_checked_together():
    # each alone is fine over the running drop; together the soft contact cannot take the table
    soft = dict(contact_law='linear', stiffness=3000.0, damping=1.0)
    table = dict(plate_amplitude=0.005, plate_frequency=10.0)
    running = _model(initial_height=0.3)
    sim = cs_params.make_simulation(running)
    sim.advance(0.05)
    values = {**cs_params.DEFAULTS, 'initial_height': 0.3}
    cs_params.check_running(sim, _model(initial_height=0.3, **table), {**values, **table},
                            running)
    cs_params.check_running(sim, _model(initial_height=0.001, **soft),
                            {**values, **soft}, running)
    with pytest.raises(ValueError, match='running drop .*stiffness = 3000 .* is too small'):
        cs_params.check_running(sim, _model(initial_height=0.001, **soft, **table),
                                {**values, **soft, **table}, running)
    # a contact waiting for the next contact phase is checked with a new table too
    bouncing = cs_params.make_simulation(running)
    bouncing.advance(math.sqrt(2.0 * 0.3 / 9.81) + 1e-5)      # inside the first contact
    assert bouncing.in_contact
    bouncing.set_contact(cs.Contact(cs.LINEAR, 3000.0, 1.0))   # waits for the lift-off
    with pytest.raises(InputError, match='stiffness = 3000'):
        bouncing.check_plate(plate.vibrating_table(0.005, 10.0, 0.0))
    # a plate changed during the bounce: the bounce goes on with its contact, the waiting one
    # takes over at the next contact phase
    stiff = bouncing.contact
    bouncing.set_plate(plate.command_motion(bouncing.time, 0.0, 0.0, [bouncing.time + 1.0],
                                            [0.0], [0.0]).motion)
    assert bouncing.contact == stiff and bouncing.in_contact


@pytest.mark.parametrize('name, tiny, extra', [
    ('real_time_factor', 5e-324, {}), ('real_time_factor', 1e-5, {}),
    ('plate_frequency', 5e-324, {'plate_amplitude': 0.001}), ('gravity', 5e-324, {}),
    ('initial_height', 5e-324, {}), ('stiffness', 5e-324, {}),
    ('initial_velocity', -5e-324, {'gravity': 0.0}), ('sphere_radius', 5e-324, {}),
    ('plate_radius', 5e-324, {})])
def test_values_in_the_declared_range_that_do_not_work_are_refused_naming_the_range(
        name, tiny, extra):
    # issue 34: real_time_factor 5e-324 stopped the simulated clock; plate_frequency 5e-324 was
    # refused with "math domain error"; subnormal gravity, initial_height and stiffness with a
    # message about speeds and Z and T; plate_radius 5e-324 was reported as sphere_radius
    values = {**cs_params.DEFAULTS, **extra, name: tiny}
    (spec,) = [s for s in cs_params.PARAMETERS if s.name == name]
    lo, hi = spec.range
    assert lo <= tiny <= hi or name == 'initial_velocity'   # rclpy's own check lets it through
    with pytest.raises(ValueError) as refused:
        cs_params.build(values)
        cs_params.loop_settings(values)
    text = str(refused.value)
    assert text.startswith(f'{name} = {tiny!r} is out of range: allowed'), text
    assert ('<= real_time_factor <= 1000' if name == 'real_time_factor'
            else spec.constraints) in text, text
    # 0 keeps its meaning, and the floor itself works (the softest stiffness without gravity:
    # with it, the depth check refuses 1e-300 in its own words, naming stiffness)
    floor = {'real_time_factor': cs_params.REAL_TIME_FACTOR_MIN, **cs_params._FLOORS}[name]
    if name == 'stiffness':
        values['gravity'] = 0.0
    for works in (0.0, math.copysign(floor, tiny)):
        if name == 'real_time_factor':
            assert cs_params.loop_settings({**values, name: works}).real_time_factor == works
        elif name != 'sphere_radius':   # (1 pm: a mass the core refuses, in its own words)
            cs_params.build({**values, name: works})

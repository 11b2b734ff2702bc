"""The core library: laws, materials, Hertz geometry, validation."""
import math
import subprocess
import sys

import numpy as np
import pytest

import contact_sim as cs


def test_importing_contact_sim_does_not_import_rclpy():
    code = ('import sys, contact_sim, contact_sim.cli; '
            'assert "rclpy" not in sys.modules, "rclpy imported"')
    subprocess.run([sys.executable, '-c', code], check=True)


def test_hertz_stiffness_steel_sphere_on_cast_iron_plate_matches_hand_computation():
    # By hand: 1/E* = (1 - 0.30²)/207 GPa + (1 - 0.26²)/100 GPa = 1.372014e-11 1/Pa
    # E* = 72.8856 GPa; k = 4/3 · E* · √0.0127 = 1.095172e10 N/m^1.5
    e_star = cs.effective_modulus(cs.MATERIALS['steel'], cs.MATERIALS['cast_iron'])
    assert e_star == pytest.approx(7.288557e10, rel=1e-6)
    k = cs.hertz_stiffness(e_star, cs.equivalent_radius(0.0127))
    assert k == pytest.approx(1.095172e10, rel=1e-6)
    contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron', 0.0127,
                                        damping_factor=2.0e5)
    assert contact.stiffness == pytest.approx(k, rel=1e-12)
    assert contact.damping == pytest.approx(2.0e5 * math.sqrt(0.0127), rel=1e-12)  # eq. 9


def test_equivalent_radius_of_two_spheres_and_of_a_plate():
    assert cs.equivalent_radius(0.015, 0.015) == pytest.approx(0.0075)
    assert cs.equivalent_radius(0.01, 0.03) == pytest.approx(0.0075)
    assert cs.equivalent_radius(0.02) == 0.02
    assert cs.equivalent_radius(math.inf, 0.02) == 0.02


def test_reduced_mass():
    assert cs.reduced_mass(2.0) == 2.0
    assert cs.reduced_mass(2.0, 2.0) == 1.0
    assert cs.reduced_mass(1.0, 3.0) == pytest.approx(0.75)


def test_named_laws_have_the_papers_exponents():
    assert (cs.AZAD_FEATHERSTONE.n, cs.AZAD_FEATHERSTONE.p, cs.AZAD_FEATHERSTONE.q) == (1.5, 0.5, 1)
    assert (cs.HUNT_CROSSLEY.n, cs.HUNT_CROSSLEY.p, cs.HUNT_CROSSLEY.q) == (1.5, 1.5, 1)
    assert (cs.LEE_WANG.n, cs.LEE_WANG.p, cs.LEE_WANG.q) == (1.5, 1.0, 1)
    assert (cs.LINEAR.n, cs.LINEAR.p, cs.LINEAR.q) == (1.0, 0.0, 1)
    assert set(cs.LAWS) == {'azad_featherstone', 'hunt_crossley', 'lee_wang', 'linear'}


@pytest.mark.parametrize('law', list(cs.LAWS.values()), ids=list(cs.LAWS))
def test_force_is_zero_outside_contact_and_never_pulls(law):
    z = np.array([-1e-3, 0.0, 1e-4, 1e-4, 1e-4])
    zdot = np.array([5.0, 5.0, 0.0, -1e5, 1.0])
    f = law.force(z, zdot, 1e9, 1e5)
    assert f[0] == 0.0 and f[1] == 0.0          # no contact where z <= 0
    assert f[2] == pytest.approx(1e9 * 1e-4 ** law.n)  # pure spring at rest
    assert f[3] == 0.0                          # fast separation: clamped, not pulling
    assert f[4] > f[2]                          # approach adds damping force
    assert np.all(f >= 0.0)


def test_azad_featherstone_force_is_eq_11():
    z, zdot, k, lam = 2e-5, -0.3, 1e10, 1e5
    expected = max(0.0, math.sqrt(z) * (k * z + lam * zdot))
    assert cs.AZAD_FEATHERSTONE.force(z, zdot, k, lam) == pytest.approx(expected, rel=1e-12)


def test_force_broadcasts_and_returns_arrays():
    z = np.linspace(-1e-4, 1e-4, 5).reshape(5, 1)
    zdot = np.linspace(-1, 1, 3).reshape(1, 3)
    f = cs.AZAD_FEATHERSTONE.force(z, zdot, 1e10, 1e5)
    assert f.shape == (5, 3)
    assert isinstance(cs.LINEAR.force(0.1, 0.0, 1.0, 0.0), np.ndarray)
    contact = cs.Contact(cs.HUNT_CROSSLEY, 1e9, 10.0)
    assert contact.force(np.zeros((2, 4)), 1.0).shape == (2, 4)


def test_material_library_has_the_papers_materials_with_sources():
    for name in ('steel', 'cast_iron', 'brass', 'cork', 'lead', 'aluminium', 'glass', 'nylon'):
        material = cs.MATERIALS[name]
        assert material.source and material.source != 'user supplied'
    custom = cs.Material('rubber', 5e6, 0.49, 1100.0)
    assert cs.get_material(custom) is custom
    with pytest.raises(ValueError, match=r"material = 'unobtainium' is unknown: allowed one of"):
        cs.get_material('unobtainium')


@pytest.mark.parametrize('kwargs, field, pattern', [
    (dict(youngs_modulus=-1.0), 'youngs_modulus', r'youngs_modulus = -1\.0 is out of range: allowed 1 <= youngs_modulus \(Pa\)'),
    (dict(youngs_modulus=0.0), 'youngs_modulus', r'allowed 1 <= youngs_modulus'),
    (dict(youngs_modulus=float('nan')), 'youngs_modulus', r'youngs_modulus = nan is not finite'),
    (dict(poisson_ratio=0.5), 'poisson_ratio', r'poisson_ratio = 0\.5 is out of range: allowed -1 < poisson_ratio < 0\.5'),
    (dict(poisson_ratio=-1.0), 'poisson_ratio', r'allowed -1 < poisson_ratio < 0\.5'),
    (dict(density=0.0), 'density', r'density = 0\.0 is out of range: allowed 0\.001 <= density'),
    (dict(density='heavy'), 'density', r"density = 'heavy' is not a number"),
])
def test_material_validation_names_field_value_and_range(kwargs, field, pattern):
    args = dict(name='x', youngs_modulus=1e9, poisson_ratio=0.3, density=1000.0)
    args.update(kwargs)
    with pytest.raises(ValueError, match=pattern):
        cs.Material(**args)


@pytest.mark.parametrize('call, pattern', [
    (lambda: cs.ContactLaw('x', 0.0, 0.5, 1.0), r'n = 0\.0 is out of range: allowed 0 < n'),
    (lambda: cs.ContactLaw('x', 1.5, -0.5, 1.0), r'p = -0\.5 is out of range: allowed 0 <= p'),
    (lambda: cs.ContactLaw('x', 1.5, 0.5, 0.0), r'q = 0\.0 is out of range: allowed 0 < q'),
    (lambda: cs.ContactLaw('x', math.inf, 0.5, 1.0), r'n = inf is not finite'),
    (lambda: cs.Contact(cs.LINEAR, -5.0, 1.0), r'stiffness = -5\.0 is out of range: allowed 0 < stiffness'),
    (lambda: cs.Contact(cs.LINEAR, 5.0, -1.0), r'damping = -1\.0 is out of range: allowed 0 <= damping'),
    (lambda: cs.Contact('linear', 5.0, 1.0), r"law = 'linear' is a name: allowed a ContactLaw"),
    (lambda: cs.build_contact('bouncy', stiffness=5.0, damping=1.0),
     r"law = 'bouncy' is unknown: allowed one of"),
    (lambda: cs.equivalent_radius(-0.01), r'radius = -0\.01 is out of range: allowed 0 < radius'),
    (lambda: cs.equivalent_radius(0.01, 0.0), r'plate_radius = 0\.0 is out of range'),
    (lambda: cs.equivalent_radius(math.inf, math.inf), r'at least one radius must be finite'),
    (lambda: cs.reduced_mass(float('nan')), r'mass = nan is not finite'),
    (lambda: cs.hertz_stiffness(1e9, 0.0), r'radius = 0\.0 is out of range'),
    (lambda: cs.Contact.from_materials(cs.LINEAR, 'steel', 'steel', 0.01),
     r"stiffness is missing: law = 'linear' has n = 1 and the Hertz stiffness needs n = 1\.5"),
    (lambda: cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'steel', 0.01,
                                       damping_factor=-2.0),
     r'damping_factor = -2\.0 is out of range: allowed 0 <= damping_factor'),
])
def test_constructors_reject_bad_values_with_field_value_and_range(call, pattern):
    with pytest.raises(ValueError, match=pattern):
        call()


def test_values_are_frozen():
    contact = cs.Contact(cs.LINEAR, 1.0, 0.0)
    with pytest.raises(AttributeError):
        contact.stiffness = 2.0
    with pytest.raises(AttributeError):
        cs.MATERIALS['steel'].density = 1.0


# -- issue 7: one rule for the contact, errors keyed by the field ---------------------------
def test_effective_modulus_takes_library_names():
    # reproduced: AttributeError: 'str' object has no attribute 'poisson_ratio'
    assert cs.effective_modulus('steel', 'brass') == cs.effective_modulus(
        cs.MATERIALS['steel'], cs.MATERIALS['brass'])


def test_build_contact_is_the_hertz_and_damping_factor_rule_with_overrides():
    from contact_sim.model.contact import build_contact, build_mass
    hertz = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron', 0.0127,
                                      damping_factor=8.87e5)
    assert build_contact('azad_featherstone', sphere='steel', plate='cast_iron', radius=0.0127,
                         damping_factor=8.87e5) == hertz
    assert build_contact('azad_featherstone', stiffness=2e9, sphere='steel', plate='cast_iron',
                         radius=0.0127, damping_factor=8.87e5).damping == hertz.damping
    assert build_contact('linear', stiffness=1e6, damping=3.0) == cs.Contact(cs.LINEAR, 1e6, 3.0)
    assert build_mass(None, 'steel', 0.0127) == cs.sphere_mass(7850.0, 0.0127)
    assert build_mass(0.5) == 0.5


@pytest.mark.parametrize('kwargs, field', [
    (dict(law='linear', sphere='steel', plate='cast_iron', radius=0.01, damping=1.0),
     'stiffness'),
    (dict(law='azad_featherstone', stiffness=1e9), 'damping'),
    (dict(law='azad_featherstone', stiffness=1e9, damping=1.0, damping_factor=1.0), 'damping'),
    (dict(law='azad_featherstone', stiffness=1e9, damping_factor=1.0), 'damping_factor'),
    (dict(law='azad_featherstone', sphere='wood', plate='steel', radius=0.01, damping=0.0),
     'sphere'),
    (dict(law='nope', stiffness=1e9, damping=0.0), 'law'),
    (dict(law='azad_featherstone', stiffness=-1.0, damping=0.0), 'stiffness'),
])
def test_contact_rule_errors_are_keyed_and_rendered_in_each_front_ends_names(kwargs, field):
    from contact_sim.model.contact import build_contact
    with pytest.raises(ValueError) as info:
        build_contact(**kwargs)
    error = info.value
    assert error.field == field and f'{field}' in str(error)
    shown = error.render({field: f'--{field.replace("_", "-")}'})
    assert f'--{field.replace("_", "-")}' in shown


def test_input_error_renders_every_field_it_mentions():
    sim_error = None
    try:
        cs.simulate_drop(cs.Contact(cs.AZAD_FEATHERSTONE, 5e4, 0.0), 0.0674, 1.0, radius=0.0127)
    except ValueError as error:
        sim_error = error
    node_text = sim_error.render({'stiffness': 'stiffness', 'height': 'initial_height'})
    assert 'initial_height <= ' in node_text and 'stiffness >= ' in node_text
    cli_text = sim_error.render({'stiffness': '--stiffness', 'height': '--height'})
    assert '--height <= ' in cli_text and '--stiffness >= ' in cli_text


@pytest.mark.parametrize('law', list(cs.LAWS.values()), ids=lambda law: law.name)
def test_the_scalar_force_equals_the_array_force(law):
    """force_at (one state, plain floats: the engine's state once a tick) gives the same numbers
    as the array path force() (one state or many at once), at the clamp, at touch, for NaN and
    infinities, and at random."""
    import itertools
    import warnings
    edges = itertools.product([-1e-6, 0.0, 1e-9, 3e-6, math.nan, math.inf, -math.inf],
                              [-2.0, -1e-3, -0.0, 0.0, 0.5, math.nan, -math.inf, math.inf])
    rng = np.random.default_rng(3)
    states = list(edges) + list(zip(rng.uniform(-1e-6, 1e-5, 500), rng.normal(0.0, 1.0, 500)))
    zs, zdots = (np.array(column) for column in zip(*states))
    with warnings.catch_warnings():
        warnings.simplefilter('ignore', RuntimeWarning)    # inf - inf in the array path
        together = law.force(zs, zdots, 1e10, 1e5)         # the drop's batched tick ends
    for (z, zdot), whole in zip(states, together.tolist()):
        scalar = law.force_at(float(z), float(zdot), 1e10, 1e5)
        with warnings.catch_warnings():
            warnings.simplefilter('ignore', RuntimeWarning)
            array = float(law.force(np.array(z), np.array(zdot), 1e10, 1e5))
        assert type(scalar) is float
        for value in (array, whole):   # the same operations: equal to round-off (bit for bit
            # here; numpy's AVX-512 pow, where a CPU has it, may differ in the last bit)
            assert scalar == pytest.approx(value, rel=1e-14, abs=0.0, nan_ok=True), (z, zdot)


def test_a_law_answers_its_kernel_curve_and_bounce_table_and_a_twin_gets_none():
    kernels = {law.name: law.kernel for law in cs.LAWS.values()}
    assert kernels == {'azad_featherstone': 1, 'hunt_crossley': 2, 'lee_wang': 3, 'linear': 4}
    for law in cs.LAWS.values():
        table = law.bounce_table
        assert law.master_curve is not None and law.master_curve.law_key == (law.n, law.p, law.q)
        assert table.log_zeta.size == table.x_lift.size == table.a.size == table.b.size > 10
        assert np.all(np.diff(table.log_zeta) > 0.0)
    for law in cs.LAWS.values():       # a custom law with a named law's exponents: none of them
        twin = cs.ContactLaw(f'{law.name}_twin', law.n, law.p, law.q)
        assert (twin.kernel, twin.master_curve, twin.bounce_table, twin.closed_form) == \
            (0, None, None, None)
    # and a named law's name on other exponents finds nothing either
    impostor = cs.ContactLaw('azad_featherstone', 1.5, 0.25, 1.0)
    assert (impostor.kernel, impostor.master_curve, impostor.bounce_table) == (0, None, None)


def test_one_hertz_rule_and_one_error_type_for_from_materials_and_build_contact():
    args = dict(sphere='steel', plate='cast_iron', radius=0.0127, damping_factor=8.87e5)
    assert cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, **args) == \
        cs.build_contact(cs.AZAD_FEATHERSTONE, **args)
    messages = set()
    for call in (lambda: cs.Contact.from_materials(cs.LINEAR, **args),
                 lambda: cs.build_contact(cs.LINEAR, **args)):
        with pytest.raises(cs.InputError) as refused:
            call()
        assert refused.value.field == 'stiffness'
        messages.add(str(refused.value))
    assert messages == {"stiffness is missing: law = 'linear' has n = 1 and the Hertz stiffness "
                        "needs n = 1.5; give stiffness (N/m^n)"}

"""The coupling in MuJoCo (``contact_sim.coupling.mujoco``): the README's steel ball dropped and
thrown, Hunt-Crossley, two free spheres, friction, bad input; against the package's own exact
results."""
import math

import numpy as np
import pytest

import contact_sim as cs

import mujoco
from contact_sim.coupling.mujoco import CoupledContacts  # noqa: E402

G = 9.81
R = 0.0127
STEEL = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron', radius=R,
                                  damping_factor=8.87e5)
HUNT = cs.Contact(cs.HUNT_CROSSLEY, STEEL.stiffness, 0.08 * STEEL.stiffness)
MASS = float(cs.sphere_mass(cs.MATERIALS["steel"].density, R))
SPEEDS = np.geomspace(0.05, 10.0, 12)
PHASES = np.arange(8) / 8.0


def ball_scene(dt, height, gravity=G, integrator='implicitfast', extra=''):
    """A free steel ball (its lowest point ``height`` above a floor plane) and ``extra``."""
    xml = f'''<mujoco><option timestep="{dt!r}" gravity="0 0 {-float(gravity)!r}"
      integrator="{integrator}"/><worldbody>
      <geom name="floor" type="plane" size="1 1 0.1"/>
      <body name="ball" pos="0 0 {float(height + R)!r}"><freejoint/>
        <geom name="ball" type="sphere" size="{R!r}" mass="{MASS!r}"/></body>{extra}
      </worldbody></mujoco>'''
    model = mujoco.MjModel.from_xml_string(xml)
    return model, mujoco.MjData(model)


def run(coupled, data, steps):
    heights, times = np.empty(steps), np.empty(steps)
    for i in range(steps):
        coupled.step()
        heights[i], times[i] = data.qpos[2] - R, data.time
    return times, heights


@pytest.fixture(scope='module')
def exact_drop():
    return cs.simulate_drop(STEEL, MASS, height=1.0)


@pytest.mark.slow
@pytest.mark.parametrize('dt', [1e-4, 5e-4, 1e-3, 2e-3])
def test_drop_of_the_readme_ball(dt, exact_drop):
    model, data = ball_scene(dt, 1.0)
    coupled = CoupledContacts(model, data, [('ball', 'floor', STEEL)], friction=0.3)
    rest_from = exact_drop.permanent_contact_time + 0.1
    times, heights = run(coupled, data, int(round((rest_from + 10.0) / dt)))
    touch = [i.time for i in coupled.impacts]
    apex = [heights[(times > touch[k]) & (times < touch[k + 1])].max() for k in range(10)]
    for k, (h, h_exact) in enumerate(zip(apex, exact_drop.apex_heights)):
        allowed = max(0.01 * h_exact, coupled.impacts[k].speed_out * dt)
        assert abs(h - h_exact) <= allowed, (k, h, h_exact)
    assert all(b < a for a, b in zip(apex, apex[1:]))
    z0 = STEEL.static_penetration(MASS * G)
    rest = times > rest_from
    assert times[-1] - rest_from >= 10.0 - 2 * dt
    assert np.max(np.abs(-heights[rest] - z0)) < 1e-6
    assert np.all(np.abs(data.qpos[:2]) < 1e-12)       # no sideways drift


def _throw(contact, speed, phase, dt, integrator='implicitfast', steps=10):
    model, data = ball_scene(dt, speed * dt * (3.0 + phase), gravity=0.0, integrator=integrator)
    data.qvel[2] = -speed
    coupled = CoupledContacts(model, data, [('ball', 'floor', contact)])
    for _ in range(steps):
        coupled.step()
    assert len(coupled.impacts) == 1
    return data.qvel[2] / speed, coupled.impacts[0].restitution


@pytest.mark.parametrize('dt', [1e-4, 5e-4, 1e-3, 2e-3])
@pytest.mark.parametrize('contact', [STEEL, HUNT], ids=['azad_featherstone', 'hunt_crossley'])
def test_throws_at_every_phase_of_the_step(dt, contact):
    exact = cs.restitution(contact, MASS, SPEEDS)
    for speed, e in zip(SPEEDS, exact):
        for phase in PHASES:
            e_host, e_impact = _throw(contact, speed, phase, dt)
            assert abs(e_host - e) < 0.005 and abs(e_impact - e) < 0.005, (speed, phase)


def test_euler_and_implicitfast_agree():
    for speed in (0.1, 3.0):
        e_euler = _throw(STEEL, speed, 0.4, 1e-3, 'Euler')[0]
        e_fast = _throw(STEEL, speed, 0.4, 1e-3, 'implicitfast')[0]
        assert e_euler == pytest.approx(e_fast, abs=1e-12)
        assert e_euler == pytest.approx(float(cs.restitution(STEEL, MASS, speed)), abs=0.005)


def test_two_free_spheres_head_on():
    r2, m2 = 0.02, 0.5          # a heavier, larger second sphere
    contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'steel', radius=R,
                                        plate_radius=r2, damping_factor=8.87e5)
    dt = 1e-3
    xml = f'''<mujoco><option timestep="{dt!r}" gravity="0 0 0"/><worldbody>
      <body name="a" pos="0 0 0"><freejoint/><geom name="a" type="sphere" size="{R!r}"
        mass="{MASS!r}"/></body>
      <body name="b" pos="{R + r2 + 0.0031!r} 0 0"><freejoint/><geom name="b" type="sphere"
        size="{r2!r}" mass="{m2!r}"/></body></worldbody></mujoco>'''
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    data.qvel[0], data.qvel[6] = 2.0, -0.5
    momentum = MASS * 2.0 + m2 * -0.5
    coupled = CoupledContacts(model, data, [('a', 'b', contact)])
    for _ in range(12):
        coupled.step()
    assert len(coupled.impacts) == 1
    after = MASS * data.qvel[0] + m2 * data.qvel[6]
    assert abs(after - momentum) <= 1e-12 * abs(momentum)
    reduced = MASS * m2 / (MASS + m2)
    e = float(cs.restitution(contact, reduced, 2.5))
    assert (data.qvel[6] - data.qvel[0]) / 2.5 == pytest.approx(e, abs=0.005)
    assert coupled.impacts[0].restitution == pytest.approx(e, abs=0.005)


@pytest.mark.parametrize('friction, regime', [(0.9, 'stick'), (0.05, 'slip')])
def test_oblique_impact_with_friction(friction, regime):
    dt, vn, vt = 1e-3, 1.0, 0.3
    model, data = ball_scene(dt, vn * dt * 3.4, gravity=0.0)
    # a solid sphere: the free joint's inertia from the geom (2/5 m R²)
    data.qvel[0], data.qvel[2] = vt, -vn
    coupled = CoupledContacts(model, data, [('ball', 'floor', STEEL)], friction=friction)
    for _ in range(10):
        coupled.step()
    e = float(cs.restitution(STEEL, MASS, vn))
    expected = 5.0 / 7.0 * vt if regime == 'stick' else vt - friction * (1.0 + e) * vn
    assert data.qvel[0] == pytest.approx(expected, rel=0.02)
    spin = data.qvel[4]                                  # about y: rolling for +x travel
    expected_spin = 5.0 / 2.0 * (vt - expected) / R      # impulse m Δv at R: I ω = m Δv R
    assert spin == pytest.approx(expected_spin, rel=0.02)
    assert data.qvel[2] / vn == pytest.approx(e, abs=0.005)


def test_bad_input_names_its_field():
    model, data = ball_scene(1e-3, 0.1, extra='<geom name="box" type="box" size="0.1 0.1 0.1" '
                                              'pos="1 1 1"/>')
    cases = [([('ball', 'table', STEEL)], 'pairs'),            # no such geom
             ([('box', 'floor', STEEL)], 'pairs'),             # no sphere
             ([('ball', 'floor', 'steel')], 'pairs'),          # not a Contact
             ([], 'pairs'),
             (None, 'pairs')]
    for pairs, field in cases:
        with pytest.raises(cs.InputError) as refused:
            CoupledContacts(model, data, pairs)
        assert refused.value.field == field, pairs
    with pytest.raises(cs.InputError) as refused:
        CoupledContacts(model, data, [('ball', 'floor', STEEL)], friction=-0.1)
    assert refused.value.field == 'friction'
    rk4, rk4_data = ball_scene(1e-3, 0.1, integrator='RK4')
    with pytest.raises(cs.InputError) as refused:
        CoupledContacts(rk4, rk4_data, [('ball', 'floor', STEEL)])
    assert refused.value.field == 'integrator'
    static, static_data = ball_scene(1e-3, 0.1, extra='<geom name="fixed" type="sphere" '
                                                      'size="0.01" pos="0 1 1"/>')
    with pytest.raises(cs.InputError) as refused:
        CoupledContacts(static, static_data, [('fixed', 'floor', STEEL)])
    assert refused.value.field == 'pairs' and 'degree of freedom' in str(refused.value)


def test_the_coupled_sphere_leaves_mujocos_own_collisions():
    model, data = ball_scene(1e-3, 0.1)
    CoupledContacts(model, data, [('ball', 'floor', STEEL)])
    ball = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, 'ball')
    assert model.geom_contype[ball] == 0 and model.geom_conaffinity[ball] == 0
    assert math.isfinite(data.qpos[2])


def test_the_example_ball_on_a_table():
    """examples/coupled_mujoco_drop.py: a ball dropped on a box table, its first apexes."""
    import importlib.util
    from pathlib import Path
    path = Path(__file__).resolve().parents[2] / 'examples' / 'coupled_mujoco_drop.py'
    spec = importlib.util.spec_from_file_location('coupled_mujoco_drop', path)
    example = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(example)
    dt = 1e-3
    heights = example.apexes(example.coupled(dt, 2.2), 4)
    exact = cs.simulate_drop(STEEL, MASS, height=1.0).apex_heights[:4]
    for h, h_exact in zip(heights, exact):
        assert abs(h - h_exact) <= max(0.01 * h_exact, math.sqrt(2 * G * h_exact) * dt)
    assert len(heights) == 4


STRIKER = '''<mujoco><option timestep="{dt!r}" gravity="0 0 0" integrator="implicitfast"/>
  <worldbody>
    <geom name="wall" type="plane" size="1 1 0.1" pos="{wall!r} 0 0" zaxis="-1 0 0"/>
    <body name="arm" pos="0 0 0.3"><joint name="hinge" type="hinge" axis="0 1 0"/>
      <geom name="rod" type="capsule" fromto="0 0 0 0 0 -0.28" size="0.005" mass="0.2"
        {own}/>
      <geom name="ball" type="sphere" pos="0 0 -0.3" size="{r!r}" mass="{m!r}" {own}/>
    </body></worldbody></mujoco>'''


def striker(dt, own=''):
    """A sphere at the end of a 0.3 m pendulum, swung at 1 m/s into a wall 2 mm ahead."""
    xml = STRIKER.format(dt=dt, wall=R + 0.002, r=R, m=MASS, own=own)
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    data.qvel[0] = -1.0 / 0.3
    return model, data


def test_an_articulated_striker_against_naive_force_at_one_microsecond():
    """The velocity after the impact within 2 % of the same model at a 1e-6 s step with the
    law's force evaluated every step (naive force converges there)."""
    model, data = striker(1e-6, own='contype="0" conaffinity="0"')
    ball = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, 'ball')
    arm = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, 'arm')
    wall_x = R + 0.002
    for _ in range(5000):
        mujoco.mj_kinematics(model, data)
        mujoco.mj_comPos(model, data)
        centre = data.geom_xpos[ball]
        jac = np.zeros((3, model.nv))
        mujoco.mj_jac(model, data, jac, None, centre, arm)
        z, zdot = centre[0] + R - wall_x, float(jac[0] @ data.qvel)
        force = STEEL.force_at(z, zdot)
        data.qfrc_applied[:] = 0.0
        mujoco.mj_applyFT(model, data, np.array([-force, 0.0, 0.0]), np.zeros(3),
                          centre + np.array([R, 0.0, 0.0]), arm, data.qfrc_applied)
        mujoco.mj_step(model, data)
    reference = data.qvel[0]
    assert reference > 0.0                          # it came back
    for dt in (1e-3, 2e-3, 5e-4):
        model, data = striker(dt)
        coupled = CoupledContacts(model, data, [('ball', 'wall', STEEL)])
        for _ in range(int(5e-3 / dt) + 1):      # a whole step of flight after the impact
            coupled.step()
        assert len(coupled.impacts) == 1
        assert data.qvel[0] == pytest.approx(reference, rel=0.02), dt


def test_the_example_two_link_arm_strikes_a_ball():
    """examples/coupled_mujoco_arm.py: the ball's velocity after the strike, coupled at 2 ms,
    within 2 % of naive force at 1 µs; momentum along x shared between arm and ball."""
    import importlib.util
    from pathlib import Path
    path = Path(__file__).resolve().parents[2] / 'examples' / 'coupled_mujoco_arm.py'
    spec = importlib.util.spec_from_file_location('coupled_mujoco_arm', path)
    example = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(example)
    reference_ball, reference_arm = example.naive()
    ball, arm, impacts = example.coupled(2e-3)
    assert len(impacts) == 1 and reference_ball[0] > 1.0
    assert np.max(np.abs(ball - reference_ball)) <= 0.02 * abs(reference_ball[0])
    assert np.max(np.abs(arm - reference_arm)) <= 0.02 * np.max(np.abs(reference_arm))

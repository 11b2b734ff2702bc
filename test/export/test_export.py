"""The export: what it says MuJoCo and PyBullet give is what they give (each engine run here, by
this test's own throw), and Drake's and Gazebo's laws are the engines' laws exactly."""
import re

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from contact_sim.export import export_contact, make_target
from contact_sim.model import MATERIALS, build_contact, build_mass, get_law
from contact_sim.validation import InputError

RADIUS = 0.0127
SPEEDS = [0.1, 1.0, 10.0]


def steel_on_cast_iron(speeds=SPEEDS):
    """The issue's contact: azad_featherstone, steel on cast iron, R1 = 0.0127 m, lambda* 8.87e5."""
    contact = build_contact(get_law('azad_featherstone'), sphere=MATERIALS['steel'],
                            plate=MATERIALS['cast_iron'], radius=RADIUS, damping_factor=8.87e5)
    return make_target(contact, build_mass(None, MATERIALS['steel'], RADIUS), RADIUS, speeds)


def ode_restitution(force, mass, speed):
    """e of m x'' = -force(x, x') from x = 0, x' = speed, to lift-off (force back to 0)."""
    return ode_contact(force, mass, speed)[0]


def ode_contact(force, mass, speed):
    """(e, duration in s, peak force in N) of m x'' = -force(x, x') from x = 0, x' = speed, to
    lift-off (force back to 0)."""
    def rhs(_, y):
        return [y[1], -max(force(y[0], y[1]), 0.0) / mass]

    def lift_off(_, y):
        return y[0] if y[1] < 0 else 1.0
    lift_off.terminal, lift_off.direction = True, -1
    out = solve_ivp(rhs, (0.0, 1e3), [0.0, speed], events=lift_off, rtol=1e-10, atol=1e-14,
                    max_step=np.inf, dense_output=True)
    end = out.t_events[0][0]
    times = np.linspace(0.0, end, 200001)
    forces = np.array([force(a, b) for a, b in zip(*out.sol(times))])
    pushing = np.flatnonzero(forces[1:] <= 0.0)   # the force is back to 0 (or x is)
    return (-out.y_events[0][0][1] / speed, times[1 + pushing[0]] if pushing.size else end,
            forces.max())


def test_gazebo_law_is_odes_kp_kd_law():
    target = steel_on_cast_iron()
    result = export_contact('gazebo', target, 1e-3)
    p = result.parameters
    # impacts toward the plate: x is the penetration, xdot its rate (positive inward)
    e, duration, peak = np.transpose([ode_contact(lambda x, xd: p['kp'] * x + p['kd'] * xd,
                                                  target.mass, v) for v in SPEEDS])
    assert result.engine_restitution_source == 'predicted'
    np.testing.assert_allclose(result.engine_restitution, e, atol=1e-6)
    np.testing.assert_allclose(result.engine_duration, duration, rtol=1e-4)
    np.testing.assert_allclose(result.engine_peak_force, peak, rtol=1e-5)


def test_linear_engine_stays_half_the_targets_spread_away():
    """A linear spring-damper gives one e: the best choice misses by half the target's spread."""
    target = steel_on_cast_iron(np.geomspace(0.1, 10.0, 6))
    result = export_contact('gazebo', target, 1e-3)
    half_spread = (target.restitution.max() - target.restitution.min()) / 2
    assert np.ptp(result.engine_restitution) < 1e-9
    assert half_spread - 1e-9 <= result.max_abs_error <= half_spread + 1e-4


def mujoco_throw(mjcf_geom, timestep, speed, gap):
    """This test's own MuJoCo throw: the snippet's geom as the ball, over a plane."""
    import mujoco
    geom = mjcf_geom.replace('<geom ', '<geom pos="0 0 0" ')
    xml = (f'<mujoco><option timestep="{timestep}" gravity="0 0 0"/><worldbody>'
           f'<geom type="plane" size="2 2 0.1"/><body pos="0 0 {RADIUS + gap}"><freejoint/>'
           f'{geom}</body></worldbody></mujoco>')
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    data.qvel[2] = -speed
    while not (data.qvel[2] > 0 and data.qpos[2] > RADIUS + gap):
        mujoco.mj_step(model, data)
    return data.qvel[2] / speed


@pytest.mark.parametrize('timestep', [1e-3, 1e-4])
def test_mujoco_gives_what_the_export_says(timestep):
    result = export_contact('mujoco', steel_on_cast_iron(), timestep)
    geom = re.search(r'<geom [^>]*/>', result.snippet).group(0)
    assert result.engine_restitution_source == 'measured'
    for speed, said in zip(SPEEDS, result.engine_restitution):
        for gap in (0.0013, 0.37 * speed * timestep):   # phases a user's drop may have
            assert abs(mujoco_throw(geom, timestep, speed, gap) - said) < 0.01
    # its contact: a linear spring-damper of m w^2 and m 2 zeta w (solref's direct form)
    stiffness, damping = -np.multiply(result.parameters['solref'], steel_on_cast_iron().mass)
    e, duration, peak = np.transpose([ode_contact(lambda x, xd: stiffness * x + damping * xd,
                                                  steel_on_cast_iron().mass, v) for v in SPEEDS])
    np.testing.assert_allclose(result.engine_peak_force, peak, rtol=0.03)
    np.testing.assert_allclose(result.engine_duration, duration, rtol=0.03, atol=2 * timestep)


def pybullet_throw(parameters, mass, speed):
    """This test's own PyBullet throw with the export's changeDynamics arguments."""
    import pybullet as p
    client = p.connect(p.DIRECT)
    try:
        p.setGravity(0, 0, 0, physicsClientId=client)
        p.setTimeStep(parameters['timestep'], physicsClientId=client)
        p.createMultiBody(0, p.createCollisionShape(p.GEOM_PLANE, physicsClientId=client),
                          physicsClientId=client)
        ball = p.createMultiBody(mass, p.createCollisionShape(
            p.GEOM_SPHERE, radius=RADIUS, physicsClientId=client), basePosition=[0, 0, 0.1],
            physicsClientId=client)
        kwargs = {key: parameters[key] for key in ('restitution', 'contactStiffness',
                                                   'contactDamping')}
        p.changeDynamics(ball, -1, linearDamping=0, angularDamping=0, physicsClientId=client,
                         **kwargs)
        p.resetBaseVelocity(ball, [0, 0, -speed], physicsClientId=client)
        while True:
            p.stepSimulation(physicsClientId=client)
            z = p.getBasePositionAndOrientation(ball, physicsClientId=client)[0][2]
            vz = p.getBaseVelocity(ball, physicsClientId=client)[0][2]
            if vz > 0 and z > 0.1:
                return vz / speed
    finally:
        p.disconnect(physicsClientId=client)


def test_pybullet_gives_what_the_export_says():
    target = steel_on_cast_iron()
    result = export_contact('pybullet', target, 1e-3)
    assert result.engine_restitution_source == 'measured'
    for speed, said in zip(SPEEDS, result.engine_restitution):
        assert abs(pybullet_throw(result.parameters, target.mass, speed) - said) < 0.01


@pytest.mark.parametrize('engine, timestep, field', [
    ('gazebo', 0.0, 'timestep'), ('drake', 0.5, 'timestep'), ('nope', 1e-3, 'engine')])
def test_bad_input_names_the_field(engine, timestep, field):
    with pytest.raises(InputError) as error:
        export_contact(engine, steel_on_cast_iron(), timestep)
    assert error.value.field == field

"""The MuJoCo coupling on bodies an impact sets spinning (``contact_sim.coupling.mujoco``): a
sphere whose centre of mass is off its centre and a box landing on a sphere at a corner get from
one impact the momentum naive force gives at a 1 µs step, at 0.5, 1 and 2 ms steps, although
their contact Jacobian turns (147 and 57 rad/s) between the two steps that share the impact."""
import numpy as np
import pytest

import contact_sim as cs

import mujoco
from contact_sim.coupling.mujoco import CoupledContacts  # noqa: E402

R = 0.0127
STEEL = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron', radius=R,
                                  damping_factor=8.87e5)
MASS = float(cs.sphere_mass(cs.MATERIALS["steel"].density, R))
INERTIA = 0.4 * MASS * R * R
SPEED = 1.917
# the eccentric ball: its centre of mass 4 mm off the sphere's centre, tilted 30°
ECCENTRIC = f'''<body pos="0 0 {R + 5e-4!r}" euler="0 30 0"><freejoint/>
  <inertial pos="0.004 0 0" mass="{MASS!r}" diaginertia="{INERTIA!r} {INERTIA!r} {INERTIA!r}"/>
  <geom name="ball" type="sphere" size="{R!r}"/></body>'''
# a box (not in contact) landing tilted on a sphere at its corner
BOX = f'''<body pos="0 0 0.2" euler="8 20 0"><freejoint/>
  <geom type="box" size="0.05 0.03 0.01" mass="0.3" contype="0" conaffinity="0"/>
  <geom name="ball" type="sphere" pos="0.05 0.03 -0.01" size="{R!r}" mass="{MASS!r}"/></body>'''


def scene(body, dt):
    """The body falling at ``SPEED``, its sphere's lowest point 0.5 mm above the floor (no
    gravity: the host's flight before the touch is exact)."""
    xml = f'''<mujoco><option timestep="{dt!r}" gravity="0 0 0"/><worldbody>
      <geom name="floor" type="plane" size="1 1 0.1"/>{body}</worldbody></mujoco>'''
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    ball = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, 'ball')
    data.qpos[2] -= data.geom_xpos[ball, 2] - R - 5e-4
    data.qvel[2] = -SPEED
    return model, data


def momentum(model, data, force, dt):
    """The linear impulse (N·s) and the angular impulse about the centre of mass (N·m·s) in the
    world of the free body's generalized ``force`` over a step ``dt``."""
    linear = force[:3] * dt
    about_origin = data.xmat[1].reshape(3, 3) @ force[3:6] * dt    # the free joint's body frame
    return linear, about_origin + np.cross(data.xpos[1] - data.xipos[1], linear)


def naive(body, dt=1e-6, duration=6e-4):
    """The contact's impulses with the law's force evaluated at every step of ``dt``."""
    model, data = scene(body, dt)
    ball = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, 'ball')
    model.geom_contype[ball] = model.geom_conaffinity[ball] = 0
    jac = np.zeros((3, model.nv))
    total = [np.zeros(3), np.zeros(3)]
    for _ in range(int(round(duration / dt))):
        mujoco.mj_step1(model, data)
        gap = data.geom_xpos[ball, 2] - R
        data.qfrc_applied[:] = 0.0
        if gap < 0.0:
            mujoco.mj_jac(model, data, jac, None, data.geom_xpos[ball] - [0.0, 0.0, R], 1)
            force = STEEL.force_at(-gap, -float(jac[2] @ data.qvel))
            data.qfrc_applied[:] = jac[2] * force
            for k, part in enumerate(momentum(model, data, data.qfrc_applied, dt)):
                total[k] += part
        mujoco.mj_step2(model, data)
    return total


def coupled(body, dt, monkeypatch):
    """The coupled contact's impulses over three steps of ``dt`` (the impact and the step that
    carries the rest of its impulse), read from the force each MuJoCo step applies."""
    model, data = scene(body, dt)
    pairs = CoupledContacts(model, data, [('ball', 'floor', STEEL)])
    total = [np.zeros(3), np.zeros(3)]
    step2 = mujoco.mj_step2

    def recorded(m, d):
        for k, part in enumerate(momentum(m, d, d.qfrc_applied, dt)):
            total[k] += part
        step2(m, d)

    monkeypatch.setattr(mujoco, 'mj_step2', recorded)
    for _ in range(3):
        pairs.step()
    monkeypatch.undo()
    assert len(pairs.impacts) == 1
    return total


@pytest.mark.parametrize('body', [ECCENTRIC, BOX], ids=['eccentric', 'box'])
def test_an_impact_that_sets_the_body_spinning_gives_naive_forces_momentum(body, monkeypatch):
    """Linear and angular impulse within 0.2 % of naive force at 1 µs (measured: 6e-5 and
    7.5e-4 for the eccentric ball, 5.4e-4 and 2.8e-4 for the box; with the rest of the impulse
    along the next step's Jacobian, before: 2.2 % and 0.7 % for the ball, 0.41 % and 0.08 % for
    the box at 2 ms)."""
    linear, angular = naive(body)
    assert linear[2] > 1.2 * MASS * SPEED                     # it bounced
    assert np.linalg.norm(angular) > 0.003 * linear[2]       # and spins
    for dt in (5e-4, 1e-3, 2e-3):
        got_linear, got_angular = coupled(body, dt, monkeypatch)
        assert np.linalg.norm(got_linear - linear) <= 2e-3 * np.linalg.norm(linear), dt
        assert np.linalg.norm(got_angular - angular) <= 2e-3 * np.linalg.norm(angular), dt


def test_only_a_contact_whose_direction_can_turn_carries_the_last_steps_push_in_its_own():
    # a sphere centred on a free body's centre of mass, or on a body that cannot move, gives
    # the same momenta along any step's n J: it keeps the step's own direction (and its cost)
    from contact_sim.coupling.mujoco_model import turns
    hinged = f'''<body pos="0 0 0.3"><joint type="hinge" axis="0 1 0"/>
      <geom name="arm" type="sphere" pos="0.3 0 0" size="{R!r}" mass="{MASS!r}"/></body>'''
    centred = f'''<body pos="0.5 0 0.3"><freejoint/><geom name="free" type="sphere"
      size="{R!r}" mass="{MASS!r}"/></body>'''
    xml = f'''<mujoco><worldbody><geom name="floor" type="plane" size="1 1 0.1"/>
      {ECCENTRIC}{hinged}{centred}{BOX.replace('name="ball"', 'name="corner"')}</worldbody></mujoco>'''
    model = mujoco.MjModel.from_xml_string(xml)
    found = {name: turns(model, mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, name))
             for name in ('floor', 'free', 'ball', 'arm', 'corner')}
    assert found == {'floor': False, 'free': False, 'ball': True, 'arm': True, 'corner': True}

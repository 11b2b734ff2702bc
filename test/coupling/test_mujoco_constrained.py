"""The MuJoCo coupling where the coupled bodies bear on MuJoCo's own constraints or damping
(``contact_sim.coupling.mujoco``): the rest of the system's acceleration and the effective mass
along the normal are MuJoCo's constrained step's, so a ball on a free crate standing on MuJoCo's
floor bounces with the law's e and comes to rest, and a damped striker rebounds as naive force
does at a 1 µs step."""
import numpy as np
import pytest

import contact_sim as cs

import mujoco
from contact_sim.coupling.mujoco import CoupledContacts  # noqa: E402

G = 9.81
R = 0.0127
STEEL = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron', radius=R,
                                  damping_factor=8.87e5)
MASS = float(cs.sphere_mass(cs.MATERIALS['steel'].density, R))
HALF = 0.1          # the crate's half side, m


def crate_scene(integrator, joint='<freejoint/>', dt=1e-3):
    """The steel ball 0.3 m above a 1 kg crate (0.2 m cube) standing on MuJoCo's floor by
    MuJoCo's own contact (``joint`` '' fixes the crate to the world)."""
    xml = f'''<mujoco><option timestep="{dt!r}" integrator="{integrator}"/><worldbody>
      <geom name="floor" type="plane" size="1 1 0.1"/>
      <body name="crate" pos="0 0 {HALF!r}">{joint}<geom name="crate" type="box"
        size="{HALF!r} {HALF!r} {HALF!r}" mass="1"/></body>
      <body name="ball" pos="0 0 {2 * HALF + 0.3 + R!r}"><freejoint/><geom name="ball"
        type="sphere" size="{R!r}" mass="{MASS!r}"/></body></worldbody></mujoco>'''
    model = mujoco.MjModel.from_xml_string(xml)
    return model, mujoco.MjData(model)


@pytest.mark.parametrize('integrator', ['implicitfast', 'Euler'])
def test_a_ball_dropped_on_a_free_crate_on_mujocos_floor_bounces_and_rests(integrator):
    # before: the constraint forces were left out of the pair's acceleration and mass, and the
    # ball bounced 176 times in 4 s, still moving 3.5 mm in its last 0.5 s
    model, data = crate_scene(integrator)
    coupled = CoupledContacts(model, data, [('ball', 'crate', STEEL)], friction=0.3)
    ball = model.jnt_qposadr[1]
    heights = np.empty(4000)
    for i in range(heights.size):
        coupled.step()
        heights[i] = data.qpos[ball + 2]
    first = coupled.impacts[0]
    assert first.speed_in == pytest.approx(np.sqrt(2 * G * 0.3), rel=0.01)
    assert abs(first.restitution - float(cs.restitution(STEEL, MASS, first.speed_in))) < 0.005
    assert coupled.impacts[-1].time < 3.0
    assert np.ptp(heights[-500:]) < 1e-6                 # at rest over its last 0.5 s
    gap = data.qpos[ball + 2] - R - (data.qpos[2] + HALF)
    assert gap == pytest.approx(-STEEL.static_penetration(MASS * G), rel=1e-6)


def test_the_free_crate_gives_the_fixed_crates_bounces():
    runs = []
    for joint in ('<freejoint/>', ''):
        model, data = crate_scene('implicitfast', joint)
        coupled = CoupledContacts(model, data, [('ball', 'crate', STEEL)])
        for _ in range(2000):
            coupled.step()
        runs.append([i.restitution for i in coupled.impacts[:5]])
    assert len(runs[0]) == 5
    assert np.max(np.abs(np.subtract(*runs))) < 0.005


def test_an_oblique_impact_on_the_free_crate_sticks_as_rigid_body_theory_says():
    # the tangential response is measured on MuJoCo's step too (the crate held by its floor)
    model, data = crate_scene('implicitfast')
    ball_v = model.jnt_dofadr[1]
    data.qpos[model.jnt_qposadr[1] + 2] = 2 * HALF + R + 0.002
    data.qvel[ball_v], data.qvel[ball_v + 2] = 1.0, -1.0
    coupled = CoupledContacts(model, data, [('ball', 'crate', STEEL)], friction=0.5)
    for _ in range(20):
        coupled.step()
    assert len(coupled.impacts) == 1
    assert data.qvel[ball_v] == pytest.approx(5.0 / 7.0, rel=0.02)        # stick
    assert data.qvel[ball_v + 4] == pytest.approx(2.5 * (1.0 - 5.0 / 7.0) / R, rel=0.02)
    first = coupled.impacts[0]
    assert abs(first.restitution - float(cs.restitution(STEEL, MASS, first.speed_in))) < 0.005


STRIKER = '''<mujoco><option timestep="{dt!r}" gravity="0 0 0" integrator="{integrator}"/>
  <worldbody>
    <geom name="wall" type="plane" size="1 1 0.1" pos="{wall!r} 0 0" zaxis="-1 0 0"/>
    <body name="arm" pos="0 0 0.3"><joint type="hinge" axis="0 1 0" damping="{damping!r}"/>
      <geom type="capsule" fromto="0 0 0 0 0 -0.28" size="0.005" mass="0.2" {own}/>
      <geom name="ball" type="sphere" pos="0 0 -0.3" size="{r!r}" mass="{m!r}" {own}/>
    </body></worldbody></mujoco>'''


def damped_striker(dt, integrator, damping, lead=0.0, own=''):
    """A sphere on a 0.3 m pendulum whose hinge is damped, swung at 1 m/s into a wall 2 mm
    ahead, started ``lead`` (s) of swing closer to it."""
    xml = STRIKER.format(dt=dt, integrator=integrator, wall=R + 0.002, damping=damping, r=R,
                         m=MASS, own=own)
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    data.qvel[0] = -1.0 / 0.3
    data.qpos[0] = lead / 0.3
    return model, data


def naive_striker(integrator, damping, lead, dt=1e-6, duration=6e-3):
    """The hinge's velocity after the impact with the law's force evaluated every ``dt``."""
    model, data = damped_striker(dt, integrator, damping, lead, own='contype="0" conaffinity="0"')
    ball = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, 'ball')
    arm = model.geom_bodyid[ball]
    jac = np.zeros((3, model.nv))
    for _ in range(int(round(duration / dt))):
        mujoco.mj_kinematics(model, data)
        mujoco.mj_comPos(model, data)
        centre = data.geom_xpos[ball]
        mujoco.mj_jac(model, data, jac, None, centre, arm)
        force = STEEL.force_at(centre[0] + R - (R + 0.002), float(jac[0] @ data.qvel))
        data.qfrc_applied[:] = 0.0
        mujoco.mj_applyFT(model, data, np.array([-force, 0.0, 0.0]), np.zeros(3),
                          centre + np.array([R, 0.0, 0.0]), arm, data.qfrc_applied)
        mujoco.mj_step(model, data)
    return float(data.qvel[0])


@pytest.mark.parametrize('integrator', ['implicitfast', 'Euler'])
def test_a_damped_striker_against_naive_force_at_one_microsecond(integrator):
    """The hinge's velocity 6 ms on, the impact at several phases within the step, within
    0.5 % of naive force at 1 µs (issue 31 asks 2 %; measured: 0.17 % at most; with M⁻¹ and
    q̈_smooth, before, up to 1.7 % at 2 ms)."""
    damping = 0.1       # N·m·s on a hinge of 0.0114 kg m²: the swing loses 0.9 % a ms
    for dt, phase in ((5e-4, 0.0), (1e-3, 0.5), (2e-3, 0.75)):
        reference = naive_striker(integrator, damping, phase * dt)
        assert reference > 0.0                          # it came back
        model, data = damped_striker(dt, integrator, damping, phase * dt)
        coupled = CoupledContacts(model, data, [('ball', 'wall', STEEL)])
        for _ in range(int(round(6e-3 / dt))):        # 6 ms, as the reference
            coupled.step()
        assert len(coupled.impacts) == 1
        assert data.qvel[0] == pytest.approx(reference, rel=0.005), (dt, phase)

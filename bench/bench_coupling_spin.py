#!/usr/bin/env python3
"""The MuJoCo coupling on bodies an impact sets spinning, against naive force at 1 µs:

* the eccentric ball (a sphere of R = 12.7 mm at its body's origin, its centre of mass 4 mm off,
  tilted 30°, steel on cast iron, 147 rad/s after the impact) and a box landing tilted on a
  sphere at its corner, both falling at 1.917 m/s under gravity onto the floor: the linear
  impulse and the angular impulse about the centre of mass (world) the contact gives, read from
  the force of every MuJoCo step, relative to naive force's; qvel z 6 ms after the start; the
  same with the impact's remainder along the next step's Jacobian (``--before``: as the adapter
  did before); and qvel z when MuJoCo is given naive force's whole impulse in the impact's
  step (the host's own floor);
* MuJoCo's own flight of the eccentric ball spinning at 147 rad/s (no gravity, no contact),
  its centre of mass's z velocity 0.8 m/s: that velocity after 0.16 s at each step.

    python bench/bench_coupling_spin.py [--friction MU]
"""
import argparse

import mujoco
import numpy as np

import contact_sim as cs
import contact_sim.coupling.mujoco as coupled_mujoco

R = 0.0127
STEEL = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron', radius=R,
                                  damping_factor=8.87e5)
MASS = float(cs.sphere_mass(cs.MATERIALS['steel'].density, R))
INERTIA = 0.4 * MASS * R * R
SPEED, DURATION = 1.917, 6e-3
BODIES = {
    'eccentric ball': f'''<body pos="0 0 0.1" euler="0 30 0"><freejoint/><inertial
        pos="0.004 0 0" mass="{MASS!r}" diaginertia="{INERTIA!r} {INERTIA!r} {INERTIA!r}"/>
        <geom name="ball" type="sphere" size="{R!r}"/></body>''',
    'box on a corner sphere': f'''<body pos="0 0 0.2" euler="8 20 0"><freejoint/>
        <geom type="box" size="0.05 0.03 0.01" mass="0.3" contype="0" conaffinity="0"/>
        <geom name="ball" type="sphere" pos="0.05 0.03 -0.01" size="{R!r}" mass="{MASS!r}"/>
        </body>'''}


def scene(body, dt, gravity=9.81):
    xml = f'''<mujoco><option timestep="{dt!r}" gravity="0 0 {-gravity!r}"/><worldbody>
      <geom name="floor" type="plane" size="1 1 0.1"/>{body}</worldbody></mujoco>'''
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    ball = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, 'ball')
    data.qpos[2] -= data.geom_xpos[ball, 2] - R - 5e-4      # 0.5 mm above the floor
    data.qvel[2] = -SPEED
    return model, data, ball


def momentum(data, force, dt):
    """World linear impulse and angular impulse about the centre of mass of a free body's
    generalized force over dt."""
    linear = force[:3] * dt
    about_origin = data.xmat[1].reshape(3, 3) @ force[3:6] * dt
    return np.concatenate((linear, about_origin + np.cross(data.xpos[1] - data.xipos[1], linear)))


def naive(body, friction, dt=1e-6):
    model, data, ball = scene(body, dt)
    model.geom_contype[ball] = model.geom_conaffinity[ball] = 0
    jac, total = np.zeros((3, model.nv)), np.zeros(6)
    for _ in range(int(round(DURATION / dt))):
        mujoco.mj_step1(model, data)
        gap = data.geom_xpos[ball, 2] - R
        data.qfrc_applied[:] = 0.0
        if gap < 0.0:
            mujoco.mj_jac(model, data, jac, None, data.geom_xpos[ball] - [0.0, 0.0, R], 1)
            velocity = jac @ data.qvel
            force = np.array([0.0, 0.0, STEEL.force_at(-gap, -velocity[2])])
            slide = np.hypot(velocity[0], velocity[1])
            if friction > 0.0 and force[2] > 0.0 and slide > 1e-9:
                force[:2] = -friction * force[2] * velocity[:2] / slide
            data.qfrc_applied[:] = jac.T @ force
            total += momentum(data, data.qfrc_applied, dt)
        mujoco.mj_step2(model, data)
    return total, data.qvel[2]


def coupled(body, friction, dt, turned=True):
    model, data, _ = scene(body, dt)
    saved = coupled_mujoco._TURNED
    coupled_mujoco._TURNED = saved if turned else np.inf     # inf: the next step's Jacobian
    pairs = coupled_mujoco.CoupledContacts(model, data, [('ball', 'floor', STEEL)],
                                           friction=friction)
    total, step2 = np.zeros(6), mujoco.mj_step2

    def recorded(m, d):
        total[:] += momentum(d, d.qfrc_applied, dt)
        step2(m, d)
    mujoco.mj_step2 = recorded
    try:
        for _ in range(int(round(DURATION / dt))):
            pairs.step()
    finally:
        mujoco.mj_step2, coupled_mujoco._TURNED = step2, saved
    return total, data.qvel[2]


def given_whole(body, dt, impulse):
    """MuJoCo at dt with naive force's whole impulse given in the impact's (first) step."""
    model, data, ball = scene(body, dt)
    model.geom_contype[ball] = model.geom_conaffinity[ball] = 0
    for i in range(int(round(DURATION / dt))):
        mujoco.mj_step1(model, data)
        data.qfrc_applied[:] = 0.0
        if i == 0:
            linear = impulse[:3]
            about_origin = impulse[3:] + np.cross(data.xipos[1] - data.xpos[1], linear)
            data.qfrc_applied[:3] = linear / dt
            data.qfrc_applied[3:6] = data.xmat[1].reshape(3, 3).T @ about_origin / dt
        mujoco.mj_step2(model, data)
    return data.qvel[2]


def flight(dt, duration=0.16):
    model, data, _ = scene(BODIES['eccentric ball'], dt, gravity=0.0)
    model.geom_contype[:] = model.geom_conaffinity[:] = 0
    mujoco.mj_forward(model, data)
    spin = np.array([0.0, 147.0, 0.0])
    data.qvel[3:6] = data.xmat[1].reshape(3, 3).T @ spin
    data.qvel[:3] = [0.0, 0.0, 0.8] - np.cross(spin, data.xipos[1] - data.xpos[1])
    for _ in range(int(round(duration / dt))):
        mujoco.mj_step(model, data)
    mujoco.mj_forward(model, data)
    spin = data.xmat[1].reshape(3, 3) @ data.qvel[3:6]
    return (data.qvel[:3] + np.cross(spin, data.xipos[1] - data.xpos[1]))[2]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--friction', type=float, default=0.0)
    friction = parser.parse_args().friction

    def rel(a, b):
        return np.linalg.norm(a - b) / np.linalg.norm(b)
    print(f'μ = {friction}; relative to naive force at 1 µs')
    print('| body | dt (s) | linear impulse | angular impulse | qvel z at 6 ms | before: '
          'linear, angular, qvel z | naive impulse given whole: qvel z |')
    print('| --- | --- | --- | --- | --- | --- | --- |')
    for name, body in BODIES.items():
        reference, v_ref = naive(body, friction)
        for dt in (5e-4, 1e-3, 2e-3):
            got, v = coupled(body, friction, dt)
            old, v_old = coupled(body, friction, dt, turned=False)
            v_whole = given_whole(body, dt, reference)
            print(f'| {name} | {dt:g} | {rel(got[:3], reference[:3]):.2e} | '
                  f'{rel(got[3:], reference[3:]):.2e} | {(v - v_ref) / v_ref:+.3f} | '
                  f'{rel(old[:3], reference[:3]):.2e}, {rel(old[3:], reference[3:]):.2e}, '
                  f'{(v_old - v_ref) / v_ref:+.3f} | {(v_whole - v_ref) / v_ref:+.3f} |')
    print('MuJoCo\'s own flight of the eccentric ball at 147 rad/s, centre of mass z velocity '
          '0.8 m/s, after 0.16 s: ' + ', '.join(f'{dt:g} s: {flight(dt):.4f}'
                                                 for dt in (2e-3, 1e-3, 2e-4, 1e-6)))


if __name__ == '__main__':
    main()

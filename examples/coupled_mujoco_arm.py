#!/usr/bin/env python3
"""A free steel ball struck by a two-link arm in MuJoCo (gravity off): the ball's velocity and the
arm's joint velocities after the strike, with the coupling at 0.5, 1 and 2 ms steps beside the
law's force evaluated every step at 1 µs (where naive evaluation converges).

    python examples/coupled_mujoco_arm.py
"""
import numpy as np

import contact_sim as cs

R_BALL, R_TIP = 0.0127, 0.02
MASS = float(cs.sphere_mass(cs.MATERIALS['steel'].density, R_BALL))
CONTACT = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'steel', radius=R_BALL,
                                    plate_radius=R_TIP, damping_factor=8.87e5)
GAP = 0.003            # between the tip and the ball at the start, m
DURATION = 0.01        # s simulated


def scene(dt, own=''):
    """The arm (shoulder and elbow hinges about y, links 0.3 m and 0.25 m, a sphere tip) swung
    towards a free ball ``GAP`` ahead of its tip; ``own``: attributes of both spheres."""
    import mujoco
    ball_x = R_TIP + R_BALL + GAP
    xml = f'''<mujoco><option timestep="{dt!r}" gravity="0 0 0" integrator="implicitfast"/>
      <worldbody>
        <body name="upper" pos="0 0 0.55"><joint name="shoulder" type="hinge" axis="0 1 0"/>
          <geom type="capsule" fromto="0 0 0 0 0 -0.3" size="0.01" mass="0.5" {own}/>
          <body name="fore" pos="0 0 -0.3"><joint name="elbow" type="hinge" axis="0 1 0"/>
            <geom type="capsule" fromto="0 0 0 0 0 -0.23" size="0.008" mass="0.3" {own}/>
            <geom name="tip" type="sphere" pos="0 0 -0.25" size="{R_TIP!r}" mass="0.2" {own}/>
          </body></body>
        <body name="ball" pos="{ball_x!r} 0 0"><freejoint/>
          <geom name="ball" type="sphere" size="{R_BALL!r}" mass="{MASS!r}" {own}/></body>
      </worldbody></mujoco>'''
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    data.qvel[0], data.qvel[1] = -2.0, -1.0      # the tip moves along +x at 1.35 m/s
    return mujoco, model, data


def coupled(dt):
    """(ball velocity m/s, shoulder and elbow rad/s) after the strike, with the coupling."""
    from contact_sim.coupling.mujoco import CoupledContacts
    _, model, data = scene(dt)
    run = CoupledContacts(model, data, [('tip', 'ball', CONTACT)])
    for _ in range(int(round(DURATION / dt))):
        run.step()
    return data.qvel[2:5].copy(), data.qvel[:2].copy(), run.impacts


def naive(dt=1e-6):
    """The same with the law's force evaluated every step at ``dt``."""
    mujoco, model, data = scene(dt, 'contype="0" conaffinity="0"')
    tip = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, 'tip')
    ball = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, 'ball')
    fore, free = model.geom_bodyid[tip], model.geom_bodyid[ball]
    jac_t, jac_b = np.zeros((3, model.nv)), np.zeros((3, model.nv))
    for _ in range(int(round(DURATION / dt))):
        mujoco.mj_kinematics(model, data)
        mujoco.mj_comPos(model, data)
        c_t, c_b = data.geom_xpos[tip].copy(), data.geom_xpos[ball].copy()
        d = c_b - c_t
        dist = float(np.linalg.norm(d))
        n = d / dist
        point = c_b - R_BALL * n
        mujoco.mj_jac(model, data, jac_t, None, point, fore)
        mujoco.mj_jac(model, data, jac_b, None, point, free)
        rate = -float(n @ ((jac_b - jac_t) @ data.qvel))       # approach > 0
        force = CONTACT.force_at(R_TIP + R_BALL - dist, rate)
        data.qfrc_applied[:] = 0.0
        mujoco.mj_applyFT(model, data, force * n, np.zeros(3), point, free, data.qfrc_applied)
        mujoco.mj_applyFT(model, data, -force * n, np.zeros(3), point, fore, data.qfrc_applied)
        mujoco.mj_step(model, data)
    return data.qvel[2:5].copy(), data.qvel[:2].copy()


def main():
    reference_ball, reference_arm = naive()
    print('naive force at 1 µs:   ball v = ' + ' '.join(f'{v:+.5f}' for v in reference_ball)
          + ' m/s, joints ' + ' '.join(f'{w:+.5f}' for w in reference_arm) + ' rad/s')
    rows = {}
    for dt in (5e-4, 1e-3, 2e-3):
        ball, arm, impacts = coupled(dt)
        rows[dt] = (ball, arm)
        error = np.max(np.abs(ball - reference_ball)) / np.max(np.abs(reference_ball))
        print(f'coupled at {dt * 1e3:.1f} ms:     ball v = ' + ' '.join(f'{v:+.5f}' for v in ball)
              + ' m/s, joints ' + ' '.join(f'{w:+.5f}' for w in arm)
              + f' rad/s; {len(impacts)} impact, e = {impacts[0].restitution:.4f}, '
              f'relative error {error:.1e}')
    return reference_ball, reference_arm, rows


if __name__ == '__main__':
    main()

#!/usr/bin/env python3
"""The MuJoCo coupling where the coupled bodies bear on MuJoCo's own constraints or damping:

* the README's steel ball dropped from 0.3 m on a 1 kg crate (0.2 m cube) standing on MuJoCo's
  floor by MuJoCo's own contact, free or fixed to the world, 1 ms, implicitfast and Euler: the
  impacts in 4 s, the first e beside the law's at its speed, the last impact's time, the ball's
  largest motion over its last 0.5 s; the µs of a step at rest on the free crate, beside the bare
  step with MuJoCo's own contact holding the ball;
* a sphere on a 0.3 m pendulum whose hinge is damped (0.1 N·m·s) swung at 1 m/s into a wall:
  the hinge's velocity 6 ms on, relative to the law's force evaluated every 1 µs, the impact at
  three phases within the step.

    python bench/bench_coupling_constrained.py
"""
import os
import time

import numpy as np

import contact_sim as cs

G, R, HALF = 9.81, 0.0127, 0.1
STEEL = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron', radius=R,
                                  damping_factor=8.87e5)
MASS = float(cs.sphere_mass(cs.MATERIALS['steel'].density, R))


def crate(integrator, joint='<freejoint/>', height=0.3):
    import mujoco
    xml = f'''<mujoco><option timestep="0.001" integrator="{integrator}"/><worldbody>
      <geom name="floor" type="plane" size="1 1 0.1"/>
      <body name="crate" pos="0 0 {HALF!r}">{joint}<geom name="crate" type="box"
        size="{HALF!r} {HALF!r} {HALF!r}" mass="1"/></body>
      <body name="ball" pos="0 0 {2 * HALF + height + R!r}"><freejoint/><geom name="ball"
        type="sphere" size="{R!r}" mass="{MASS!r}"/></body></worldbody></mujoco>'''
    model = mujoco.MjModel.from_xml_string(xml)
    return model, mujoco.MjData(model)


def crate_figures(integrator, joint):
    from contact_sim.coupling.mujoco import CoupledContacts
    model, data = crate(integrator, joint)
    coupled = CoupledContacts(model, data, [('ball', 'crate', STEEL)], friction=0.3)
    z = model.jnt_qposadr[model.njnt - 1] + 2
    heights = np.empty(4000)
    for i in range(heights.size):
        coupled.step()
        heights[i] = data.qpos[z]
    first = coupled.impacts[0]
    law = float(cs.restitution(STEEL, MASS, first.speed_in))
    return (len(coupled.impacts), first.restitution, law, coupled.impacts[-1].time,
            float(np.ptp(heights[-500:])))


def rest_cost(friction, steps=2000, repeat=5):
    """µs a step with the ball at rest on the free crate: bare (MuJoCo's own contact) and
    coupled."""
    import mujoco
    from contact_sim.coupling.mujoco import CoupledContacts
    out = []
    for coupled in (False, True):
        best = float('inf')
        for _ in range(repeat):
            model, data = crate('implicitfast', height=0.0)
            run = CoupledContacts(model, data, [('ball', 'crate', STEEL)],
                                  friction=friction).step if coupled else (
                lambda: mujoco.mj_step(model, data))
            for _ in range(500):
                run()
            start = time.process_time()
            for _ in range(steps):
                run()
            best = min(best, (time.process_time() - start) / steps)
        out.append(best * 1e6)
    return out


STRIKER = '''<mujoco><option timestep="{dt!r}" gravity="0 0 0" integrator="{integrator}"/>
  <worldbody>
    <geom name="wall" type="plane" size="1 1 0.1" pos="{wall!r} 0 0" zaxis="-1 0 0"/>
    <body name="arm" pos="0 0 0.3"><joint type="hinge" axis="0 1 0" damping="0.1"/>
      <geom type="capsule" fromto="0 0 0 0 0 -0.28" size="0.005" mass="0.2" {own}/>
      <geom name="ball" type="sphere" pos="0 0 -0.3" size="{r!r}" mass="{m!r}" {own}/>
    </body></worldbody></mujoco>'''


def striker(dt, integrator, lead, own=''):
    import mujoco
    model = mujoco.MjModel.from_xml_string(STRIKER.format(
        dt=dt, integrator=integrator, wall=R + 0.002, r=R, m=MASS, own=own))
    data = mujoco.MjData(model)
    data.qvel[0], data.qpos[0] = -1.0 / 0.3, lead / 0.3
    return model, data


def naive_striker(integrator, lead, dt=1e-6, duration=6e-3):
    import mujoco
    model, data = striker(dt, integrator, lead, own='contype="0" conaffinity="0"')
    arm = 1
    jac = np.zeros((3, model.nv))
    for _ in range(int(round(duration / dt))):
        mujoco.mj_kinematics(model, data)
        mujoco.mj_comPos(model, data)
        centre = data.geom_xpos[2]
        mujoco.mj_jac(model, data, jac, None, centre, arm)
        force = STEEL.force_at(centre[0] - 0.002, float(jac[0] @ data.qvel))
        data.qfrc_applied[:] = 0.0
        mujoco.mj_applyFT(model, data, np.array([-force, 0.0, 0.0]), np.zeros(3),
                          centre + np.array([R, 0.0, 0.0]), arm, data.qfrc_applied)
        mujoco.mj_step(model, data)
    return float(data.qvel[0])


def striker_error(integrator, dt, phase):
    from contact_sim.coupling.mujoco import CoupledContacts
    reference = naive_striker(integrator, phase * dt)
    model, data = striker(dt, integrator, phase * dt)
    coupled = CoupledContacts(model, data, [('ball', 'wall', STEEL)])
    for _ in range(int(round(6e-3 / dt))):
        coupled.step()
    return data.qvel[0] / reference - 1.0


def main():
    print(f'load average {os.getloadavg()[0]:.1f}')
    print('| integrator | crate | impacts in 4 s | first e / law | last impact (s) | '
          'ball moves over its last 0.5 s (m) |')
    print('| --- | --- | --- | --- | --- | --- |')
    for integrator in ('implicitfast', 'Euler'):
        for name, joint in (('free', '<freejoint/>'), ('fixed', '')):
            count, e, law, last, moves = crate_figures(integrator, joint)
            print(f'| {integrator} | {name} | {count} | {e:.4f} / {law:.4f} | {last:.2f} | '
                  f'{moves:.1e} |', flush=True)
    for friction in (0.0, 0.3):
        bare, coupled = rest_cost(friction)
        print(f'at rest on the free crate, friction {friction}: µs a step bare (own contact) '
              f'{bare:.1f}, coupled {coupled:.1f}', flush=True)
    print('| integrator | damped striker: relative error at 0.5 / 1 / 2 ms, phases 0 / 0.5 / '
          '0.75 |')
    print('| --- | --- |')
    for integrator in ('implicitfast', 'Euler'):
        errors = [striker_error(integrator, dt, phase) for dt in (5e-4, 1e-3, 2e-3)
                  for phase in (0.0, 0.5, 0.75)]
        print(f'| {integrator} | ' + ' '.join(f'{e:+.1e}' for e in errors) + ' |', flush=True)


if __name__ == '__main__':
    main()

#!/usr/bin/env python3
"""A steel ball dropped from 1 m on a cast-iron table in MuJoCo at a 1 ms step: its apex heights
exact (``simulate_drop``), with the coupling (``contact_sim.coupling.mujoco``), with MuJoCo's own
contact at ``contact-sim export``'s solref/solimp, and with the law's force evaluated once a step
(naive), printed side by side (and drawn with ``--plot FILE``).

    python examples/coupled_mujoco_drop.py [--dt 0.001] [--plot apexes.png]
"""
import argparse

import numpy as np

import contact_sim as cs

R, G, HEIGHT = 0.0127, 9.81, 1.0
CONTACT = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron', radius=R,
                                    damping_factor=8.87e5)
MASS = float(cs.sphere_mass(cs.MATERIALS['steel'].density, R))
TABLE_TOP = 0.75


def scene(dt, ball_extra='', integrator='implicitfast'):
    import mujoco
    xml = f'''<mujoco><option timestep="{dt!r}" integrator="{integrator}"/><worldbody>
      <geom name="floor" type="plane" size="2 2 0.1"/>
      <geom name="table" type="box" size="0.4 0.4 {TABLE_TOP / 2!r}" pos="0 0 {TABLE_TOP / 2!r}"/>
      <body pos="0 0 {TABLE_TOP + HEIGHT + R!r}"><freejoint/>
        <geom name="ball" type="sphere" size="{R!r}" mass="{MASS!r}" {ball_extra}/></body>
      </worldbody></mujoco>'''
    model = mujoco.MjModel.from_xml_string(xml)
    return mujoco, model, mujoco.MjData(model)


def apexes(heights, count=10):
    """The local maxima of the height after the first minimum (the apexes of the bounces)."""
    h = np.asarray(heights)
    peaks = [h[i] for i in range(1, len(h) - 1) if h[i - 1] < h[i] >= h[i + 1]]
    return peaks[:count]


def coupled(dt, seconds):
    from contact_sim.coupling.mujoco import CoupledContacts
    _, model, data = scene(dt)
    run = CoupledContacts(model, data, [('ball', 'table', CONTACT)], friction=0.3)
    heights = []
    for _ in range(int(seconds / dt)):
        run.step()
        heights.append(data.qpos[2] - R - TABLE_TOP)
    return heights


def own_contact(dt, seconds):
    from contact_sim.export import export_contact, make_target
    params = export_contact('mujoco', make_target(CONTACT, MASS, R, [0.5, 1.0, 2.0, 4.4]),
                            dt).parameters
    extra = (f'solref="{" ".join(map(str, params["solref"]))}" '
             f'solimp="{" ".join(map(str, params["solimp"]))}"')
    mujoco, model, data = scene(dt, extra, params['integrator'])
    heights = []
    for _ in range(int(seconds / dt)):
        mujoco.mj_step(model, data)
        heights.append(data.qpos[2] - R - TABLE_TOP)
    return heights


def naive(dt, seconds):
    mujoco, model, data = scene(dt, 'contype="0" conaffinity="0"')
    heights, launch = [], 0.0
    for _ in range(int(seconds / dt)):
        z = TABLE_TOP + R - data.qpos[2]
        data.xfrc_applied[1, 2] = CONTACT.force_at(z, -data.qvel[2])
        mujoco.mj_step(model, data)
        heights.append(data.qpos[2] - R - TABLE_TOP)
        launch = max(launch, data.qvel[2])
    return heights, launch


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--dt', type=float, default=1e-3, help='MuJoCo step, s')
    parser.add_argument('--seconds', type=float, default=3.0)
    parser.add_argument('--plot', help='draw the apexes to this image file')
    args = parser.parse_args()
    exact = list(cs.simulate_drop(CONTACT, MASS, height=HEIGHT).apex_heights[:10])
    rows = {'exact (simulate_drop)': exact,
            'coupled': apexes(coupled(args.dt, args.seconds)),
            "MuJoCo's own contact (export)": apexes(own_contact(args.dt, args.seconds)),
            'naive force once a step': []}
    heights, launch = naive(args.dt, min(args.seconds, 1.0))
    rows['naive force once a step'] = apexes(heights, 3)
    print(f'apex heights (m) of the first bounces, dt = {args.dt:g} s')
    for name, values in rows.items():
        if values:
            print(f'{name:32s} ' + ' '.join(f'{v:9.4g}' for v in values[:6]))
    if not rows['naive force once a step']:
        print(f'naive force once a step: launched at {launch:.3g} m/s, no apex within 1 s')
    if args.plot:
        import matplotlib
        matplotlib.use('Agg')
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(6, 4))
        for (name, values), marker in zip(rows.items(), 'o^sx'):
            ax.semilogy(range(1, len(values) + 1), values, marker=marker, label=name)
        ax.set_xlabel('bounce')
        ax.set_ylabel('apex height (m)')
        ax.legend()
        fig.tight_layout()
        fig.savefig(args.plot)
    return rows


if __name__ == '__main__':
    main()

#!/usr/bin/env python3
"""The README's steel ball dropped from 1 m in PyBullet (1/240 s) and Drake (a discrete plant at
1 ms and a continuous one coupled every 1 ms) with the coupling: the first apexes beside the
package's own ``simulate_drop`` (and drawn with ``--plot FILE``).

    python examples/coupled_engines_drop.py [--seconds 3] [--plot apexes.png]
"""
import argparse

import numpy as np

import contact_sim as cs

R, G = 0.0127, 9.81
CONTACT = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron', radius=R,
                                    damping_factor=8.87e5)
MASS = float(cs.sphere_mass(cs.MATERIALS['steel'].density, R))


def apexes(times, heights, impacts, count=6):
    """The highest point between successive impacts (m)."""
    touch = [i.time for i in impacts]
    return [float(heights[(times > a) & (times < b)].max())
            for a, b in zip(touch[:count], touch[1:count + 1])]


def pybullet_drop(dt, seconds):
    import pybullet
    from contact_sim.coupling.pybullet import CoupledContacts
    client = pybullet.connect(pybullet.DIRECT)
    pybullet.setGravity(0, 0, -G, physicsClientId=client)
    pybullet.setTimeStep(dt, physicsClientId=client)
    floor = pybullet.createMultiBody(0, pybullet.createCollisionShape(
        pybullet.GEOM_PLANE, physicsClientId=client), physicsClientId=client)
    ball = pybullet.createMultiBody(MASS, pybullet.createCollisionShape(
        pybullet.GEOM_SPHERE, radius=R, physicsClientId=client), basePosition=(0, 0, 1.0 + R),
        physicsClientId=client)
    pybullet.changeDynamics(ball, -1, linearDamping=0, angularDamping=0, physicsClientId=client)
    coupled = CoupledContacts(client, [(ball, floor, CONTACT)], friction=0.3)
    steps = int(seconds / dt)
    heights = np.empty(steps)
    for i in range(steps):
        coupled.step()
        heights[i] = pybullet.getBasePositionAndOrientation(ball, physicsClientId=client)[0][2] - R
    pybullet.disconnect(client)
    return apexes((np.arange(steps) + 1) * dt, heights, coupled.impacts)


def drake_drop(dt, seconds, continuous):
    from pydrake.all import (AddMultibodyPlantSceneGraph, CoulombFriction, DiagramBuilder,
                             HalfSpace, RigidTransform, Simulator, SpatialInertia, Sphere)
    from contact_sim.coupling.drake import CoupledContacts
    builder = DiagramBuilder()
    plant, scene_graph = AddMultibodyPlantSceneGraph(builder,
                                                     time_step=0.0 if continuous else dt)
    ball = plant.AddRigidBody('ball', SpatialInertia.SolidSphereWithMass(MASS, R))
    plant.RegisterCollisionGeometry(ball, RigidTransform(), Sphere(R), 'ball',
                                    CoulombFriction(0.3, 0.3))
    plant.RegisterCollisionGeometry(plant.world_body(), RigidTransform(), HalfSpace(), 'floor',
                                    CoulombFriction(0.3, 0.3))
    plant.Finalize()
    coupled = builder.AddSystem(CoupledContacts(   # the shapes from the scene graph
        plant, [(ball, plant.world_body(), CONTACT)], friction=0.3,
        period=dt if continuous else None, scene_graph=scene_graph))
    builder.Connect(plant.get_state_output_port(), coupled.get_input_port())
    builder.Connect(coupled.get_output_port(), plant.get_applied_spatial_force_input_port())
    simulator = Simulator(builder.Build())
    context = plant.GetMyMutableContextFromRoot(simulator.get_mutable_context())
    plant.SetFreeBodyPose(context, ball, RigidTransform([0.0, 0.0, 1.0 + R]))
    steps = int(seconds / dt)
    heights = np.empty(steps)
    for i in range(steps):
        simulator.AdvanceTo((i + 1) * dt)
        heights[i] = plant.EvalBodyPoseInWorld(context, ball).translation()[2] - R
    return apexes((np.arange(steps) + 1) * dt, heights, coupled.impacts)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--seconds', type=float, default=3.0)
    parser.add_argument('--plot', help='draw the apexes to this image file')
    args = parser.parse_args()
    rows = {'exact (simulate_drop)': list(cs.simulate_drop(CONTACT, MASS, height=1.0)
                                          .apex_heights[:6]),
            'PyBullet, 1/240 s': pybullet_drop(1.0 / 240.0, args.seconds),
            'Drake discrete, 1 ms': drake_drop(1e-3, args.seconds, continuous=False),
            'Drake continuous, every 1 ms': drake_drop(1e-3, args.seconds, continuous=True)}
    print('apex heights (m) of the first bounces, coupled')
    for name, values in rows.items():
        print(f'{name:30s} ' + ' '.join(f'{v:9.5g}' for v in values))
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

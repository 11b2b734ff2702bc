#!/usr/bin/env python3
"""The coupling (``contact_sim.coupling``) in MuJoCo, PyBullet and Drake's discrete plant: its accuracy figures beside
naive force evaluation and the engine's own contact with ``contact-sim export``'s parameters,
measured in the same run, and the cost of a step with and without it.

Per engine and host step:
* drop of the README's steel ball from 1 m: the worst apex error of the first 10 bounces over
  what issue 31 allows (max(1 %, v dt); <= 1 passes), whether the apexes decrease, the largest
  distance from the static penetration over 10 s at rest;
* throws at 12 speeds 0.05-10 m/s, gravity off, 8 phases within the step: the worst abs(e - exact)
  for Azad-Featherstone and Hunt-Crossley (λ = 0.08 s/m k);
* naive force (the law's force at the step's start, applied for the step): the first apex of the
  same drop (MuJoCo and PyBullet); the engine's own contact with the export's parameters: its worst abs(e - exact) over
  the export's speeds (the export measures it);
* cost: µs of a bare step, of a coupled step at rest on the floor (contact active) and far from
  it (no contact in reach): CPU time, best of several runs (the machine is shared); for PyBullet
  also the floor of a far step: the bare step with the engine calls it cannot do without; for Drake
  also a step with a no-op Python LeafSystem in the coupling's place (``drake_noop``, measured
  beside its own bare step), the floor of any Python system on that port, and the ball on a
  prismatic joint, which the coupling serves through its plant context (an articulated body).

    python bench/bench_coupling.py [--quick] [--engine mujoco]
"""
import argparse
import os
import time

import numpy as np

import contact_sim as cs

G, R = 9.81, 0.0127
STEEL = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron', radius=R,
                                  damping_factor=8.87e5)
HUNT = cs.Contact(cs.HUNT_CROSSLEY, STEEL.stiffness, 0.08 * STEEL.stiffness)
MASS = float(cs.sphere_mass(cs.MATERIALS['steel'].density, R))
SPEEDS = np.geomspace(0.05, 10.0, 12)
PHASES = np.arange(8) / 8.0


# -- the engines: a ball over a floor, stepped coupled or naive --------------------------------
class MujocoBall:
    name = 'mujoco'

    def __init__(self, dt, height, gravity=G, vz=0.0, coupled=True, contact=STEEL):
        import mujoco
        from contact_sim.coupling.mujoco import CoupledContacts
        self.mujoco, self.dt = mujoco, dt
        xml = f'''<mujoco><option timestep="{dt!r}" gravity="0 0 {-gravity!r}"
          integrator="implicitfast"/><worldbody><geom name="floor" type="plane" size="1 1 .1"/>
          <body pos="0 0 {float(height + R)!r}"><freejoint/><geom name="ball" type="sphere"
          size="{R!r}" mass="{MASS!r}"/></body></worldbody></mujoco>'''
        self.model = mujoco.MjModel.from_xml_string(xml)
        self.data = mujoco.MjData(self.model)
        self.data.qvel[2] = vz
        self.coupled = CoupledContacts(self.model, self.data, [('ball', 'floor', contact)],
                                       friction=0.3) if coupled else None

    def step(self):
        if self.coupled is not None:
            self.coupled.step()
            return
        d = self.data
        d.xfrc_applied[1, 2] = STEEL.force_at(R - d.qpos[2], -d.qvel[2])
        self.mujoco.mj_step(self.model, d)

    def bare_step(self):
        self.mujoco.mj_step(self.model, self.data)

    def height(self):
        return self.data.qpos[2] - R

    def vz(self):
        return self.data.qvel[2]

    @property
    def impacts(self):
        return self.coupled.impacts


class BulletBall:
    name = 'pybullet'

    def __init__(self, dt, height, gravity=G, vz=0.0, coupled=True, contact=STEEL):
        import pybullet
        from contact_sim.coupling.pybullet import CoupledContacts
        self.p, self.dt = pybullet, dt
        self.client = c = pybullet.connect(pybullet.DIRECT)
        pybullet.setGravity(0, 0, -gravity, physicsClientId=c)
        pybullet.setTimeStep(dt, physicsClientId=c)
        floor = pybullet.createMultiBody(0, pybullet.createCollisionShape(
            pybullet.GEOM_PLANE, physicsClientId=c), physicsClientId=c)
        self.ball = pybullet.createMultiBody(MASS, pybullet.createCollisionShape(
            pybullet.GEOM_SPHERE, radius=R, physicsClientId=c),
            basePosition=(0, 0, height + R), physicsClientId=c)
        pybullet.changeDynamics(self.ball, -1, linearDamping=0, angularDamping=0,
                                physicsClientId=c)
        pybullet.resetBaseVelocity(self.ball, (0, 0, vz), physicsClientId=c)
        self.coupled = CoupledContacts(c, [(self.ball, floor, contact)], friction=0.3)
        if not coupled:
            pybullet.setCollisionFilterPair(self.ball, floor, -1, -1, 0, physicsClientId=c)
            self.coupled = None

    def step(self):
        if self.coupled is not None:
            self.coupled.step()
            return
        force = STEEL.force_at(-self.height(), -self.vz())
        self.p.applyExternalForce(self.ball, -1, (0, 0, force), (0, 0, 0), self.p.LINK_FRAME,
                                  physicsClientId=self.client)
        self.p.stepSimulation(physicsClientId=self.client)

    def bare_step(self):
        self.p.stepSimulation(physicsClientId=self.client)

    def height(self):
        return self.p.getBasePositionAndOrientation(self.ball, physicsClientId=self.client)[0][2] - R

    def vz(self):
        return self.p.getBaseVelocity(self.ball, physicsClientId=self.client)[0][2]

    @property
    def impacts(self):
        return self.coupled.impacts

    def close(self):
        self.p.disconnect(self.client)


def drake_noop(plant):
    """A Python LeafSystem wired as the coupling is (the plant's state in, evaluated each step;
    an empty list of applied spatial forces out) that does nothing else: the floor of any
    Python system on that port."""
    from pydrake.common.cpp_param import List
    from pydrake.common.value import Value
    from pydrake.multibody.plant import ExternallyAppliedSpatialForce_
    from pydrake.systems.framework import LeafSystem

    class Noop(LeafSystem):
        def __init__(self):
            LeafSystem.__init__(self)
            self.port = self.DeclareVectorInputPort('plant_state', plant.num_multibody_states())
            self.DeclareAbstractOutputPort(
                'applied_spatial_force',
                lambda: Value[List[ExternallyAppliedSpatialForce_[float]]]([]), self._output)

        def _output(self, context, output):
            self.port.Eval(context)
            output.set_value([])
    return Noop()


class DrakeBall:
    name = 'drake'

    def __init__(self, dt, height, gravity=G, vz=0.0, coupled=True, contact=STEEL, noop=False,
                 articulated=False):
        """``noop``: ``drake_noop`` in the coupling's place; ``articulated``: the ball on a
        vertical prismatic joint instead of free (the coupling then serves it through its plant
        context, as any articulated body)."""
        from pydrake.all import (AddMultibodyPlantSceneGraph, DiagramBuilder, PrismaticJoint,
                                 RigidTransform, Simulator, SpatialInertia, SpatialVelocity)
        from contact_sim.coupling.drake import CoupledContacts
        self.dt = dt
        builder = DiagramBuilder()
        plant, _ = AddMultibodyPlantSceneGraph(builder, time_step=dt)
        plant.mutable_gravity_field().set_gravity_vector([0.0, 0.0, -gravity])
        self.body = plant.AddRigidBody('ball', SpatialInertia.SolidSphereWithMass(MASS, R))
        if articulated:
            plant.AddJoint(PrismaticJoint('slide', plant.world_frame(), self.body.body_frame(),
                                          [0.0, 0.0, 1.0]))
        plant.Finalize()
        self.coupled = builder.AddSystem(drake_noop(plant) if noop else CoupledContacts(
            plant, [('ball', plant.world_body(), contact, R, 0.0)], friction=0.3))
        builder.Connect(plant.get_state_output_port(), self.coupled.get_input_port())
        if coupled:
            builder.Connect(self.coupled.get_output_port(),
                            plant.get_applied_spatial_force_input_port())
        self.simulator = Simulator(builder.Build())
        self.plant = plant
        self.context = plant.GetMyMutableContextFromRoot(self.simulator.get_mutable_context())
        if articulated:
            plant.SetPositionsAndVelocities(self.context, [height + R, vz])
        else:
            plant.SetFreeBodyPose(self.context, self.body, RigidTransform([0.0, 0.0, height + R]))
            plant.SetFreeBodySpatialVelocity(self.context, self.body, SpatialVelocity(
                np.zeros(3), np.array([0.0, 0.0, vz])))
        self.steps = 0

    def step(self):
        self.steps += 1
        self.simulator.AdvanceTo(self.steps * self.dt)

    bare_step = step        # the bare plant: built with coupled=False

    def height(self):
        return self.plant.EvalBodyPoseInWorld(self.context, self.body).translation()[2] - R

    def vz(self):
        return self.plant.EvalBodySpatialVelocityInWorld(self.context,
                                                         self.body).translational()[2]

    @property
    def impacts(self):
        return self.coupled.impacts


ENGINES = {'mujoco': (MujocoBall, [1e-4, 5e-4, 1e-3, 2e-3]),
           'pybullet': (BulletBall, [1.0 / 240.0, 1e-3]),
           'drake': (DrakeBall, [1e-3])}


def only(names):
    """The engines named (all if none)."""
    return {k: v for k, v in ENGINES.items() if not names or k in names}


def drop_figures(engine, dt, exact, rest_seconds):
    ball = engine(dt, 1.0)
    rest_from = exact.permanent_contact_time + 0.1
    steps = int(round((rest_from + rest_seconds) / dt))
    heights, times = np.empty(steps), (np.arange(steps) + 1) * dt
    for i in range(steps):
        ball.step()
        heights[i] = ball.height()
    touch = [i.time for i in ball.impacts]
    apex = [heights[(times > touch[k]) & (times < touch[k + 1])].max() for k in range(10)]
    ratio = max(abs(h - he) / max(0.01 * he, ball.impacts[k].speed_out * dt)
                for k, (h, he) in enumerate(zip(apex, exact.apex_heights)))
    z0 = STEEL.static_penetration(MASS * G)
    rest = np.max(np.abs(-heights[times > rest_from] - z0))
    getattr(ball, 'close', lambda: None)()
    return ratio, all(b < a for a, b in zip(apex, apex[1:])), rest


def throw_error(engine, dt, contact):
    exact = cs.restitution(contact, MASS, SPEEDS)
    worst = 0.0
    for speed, e in zip(SPEEDS, exact):
        for phase in PHASES:
            ball = engine(dt, speed * dt * (3.0 + phase), gravity=0.0, vz=-speed,
                          contact=contact)
            for _ in range(10):
                ball.step()
            worst = max(worst, abs(ball.vz() / speed - e))
            getattr(ball, 'close', lambda: None)()
    return worst


def naive_first_apex(engine, dt):
    """The first apex (m) of the 1 m drop with the force evaluated once a step (nan: it never
    came back within 3 s)."""
    ball = engine(dt, 1.0, coupled=False)
    heights = []
    for _ in range(int(3.0 / dt)):
        ball.step()
        heights.append(ball.height())
    getattr(ball, 'close', lambda: None)()
    h = np.array(heights)
    low = int(np.argmin(h[: int(0.6 / dt)]))
    after = h[low:]
    return float(after.max()) if after.size else float('nan'), float(h.min())


def export_error(name, dt):
    """The engine's own contact with the export's parameters: max abs(e - target) (measured)."""
    from contact_sim.export import export_contact, make_target
    try:
        result = export_contact(name, make_target(STEEL, MASS, R, [0.1, 0.5, 1.0, 2.0, 5.0]), dt)
    except Exception as error:     # noqa: BLE001  (the table says why)
        return f'({type(error).__name__})'
    return f'{result.max_abs_error:.3f}'


def cost(engine, dt, repeat=5, steps=2000, kinds=('bare', 'rest', 'far'), **options):
    """µs a step: bare, coupled at rest (contact active), coupled far from the floor (and for
    Drake, 'noop': ``drake_noop`` in the coupling's place, far from the floor); ``options`` go
    to the engine."""
    z0 = STEEL.static_penetration(MASS * G)
    out = []
    for kind in kinds:
        best = float('inf')
        for _ in range(repeat):
            extra = dict(options, noop=True) if kind == 'noop' else options
            ball = engine(dt, 0.5 if kind != 'rest' else -z0, gravity=0.0 if kind in (
                'far', 'noop') else G, coupled=kind != 'bare' or engine is not DrakeBall, **extra)
            run = ball.bare_step if kind == 'bare' else ball.step
            for _ in range(50):
                run()
            start = time.process_time()
            for _ in range(steps):
                run()
            best = min(best, (time.process_time() - start) / steps)
            getattr(ball, 'close', lambda: None)()
        out.append(best * 1e6)
    return out


def bullet_floor(dt, repeat=5, steps=20000):
    """µs a step of the calls a PyBullet step far from contact cannot do without, the ball of
    ``cost``'s far case: a bare ``stepSimulation``; it with one ``getClosestPoints`` at the
    coupling's reach; it with that and ``getPhysicsEngineParameters`` (the step's dt and
    ``numSubSteps``, read every step)."""
    from contact_sim.coupling.pybullet import REACH
    ball = BulletBall(dt, 0.5, gravity=0.0)
    p, c, floor = ball.p, ball.client, ball.coupled.pairs[0][6]
    step, closest, params = p.stepSimulation, p.getClosestPoints, p.getPhysicsEngineParameters
    body = ball.ball

    def bare():
        step(physicsClientId=c)

    def query():
        step(physicsClientId=c)
        closest(body, floor, REACH, -1, -1, physicsClientId=c)

    def both():
        step(physicsClientId=c)
        params(physicsClientId=c)
        closest(body, floor, REACH, -1, -1, physicsClientId=c)

    out = []
    for run in (bare, query, both):
        best = float('inf')
        for _ in range(repeat):
            start = time.process_time()
            for _ in range(steps):
                run()
            best = min(best, (time.process_time() - start) / steps)
        out.append(best * 1e6)
    ball.close()
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--quick', action='store_true', help='1 s at rest instead of 10')
    parser.add_argument('--engine', action='append', choices=sorted(ENGINES),
                        help='only this engine (repeatable; default all)')
    args = parser.parse_args()
    exact = cs.simulate_drop(STEEL, MASS, height=1.0)
    print(f'load average {os.getloadavg()[0]:.1f}')
    print('| engine | dt (s) | drop: apex error / allowed | apexes decrease | rest: max abs(z - z0) '
          '(m) | throws AF max abs(Δe) | throws HC max abs(Δe) | naive force: 1st apex (m), '
          'deepest (m) | export: max abs(Δe) | µs a step: bare / coupled at rest / coupled far |')
    print('| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |')
    floor = []
    for name, (engine, steps) in only(args.engine).items():
        for dt in steps:
            ratio, decreasing, rest = drop_figures(engine, dt, exact, 1.0 if args.quick else 10.0)
            af, hc = throw_error(engine, dt, STEEL), throw_error(engine, dt, HUNT)
            apex, deepest = naive_first_apex(engine, dt) if engine is not DrakeBall else (
                float('nan'), float('nan'))
            bare, at_rest, far = cost(engine, dt)
            print(f'| {name} | {dt:.3g} | {ratio:.3f} | {decreasing} | {rest:.1e} | {af:.1e} | '
                  f'{hc:.1e} | {apex:.3g}, {deepest:.2g} | {export_error(name, dt)} | '
                  f'{bare:.1f} / {at_rest:.1f} / {far:.1f} |', flush=True)
            if engine is DrakeBall:
                floor.append((dt, cost(engine, dt, kinds=('bare', 'noop')),
                              cost(engine, dt, articulated=True)))
    for dt, (bare, noop), jointed in floor:
        print(f'drake {dt:.3g}: a no-op Python LeafSystem wired as the coupling (reads the state, '
              f'outputs no force): bare {bare:.1f} / no-op {noop:.1f} µs a step; the ball on a '
              'prismatic joint (served through the plant context): bare / at rest / far '
              + ' / '.join(f'{c:.1f}' for c in jointed) + ' µs a step')
    if 'pybullet' in only(args.engine):
        bare, query, both = bullet_floor(1e-3)
        print(f'\npybullet floor of a far step (1 ms, µs): bare {bare:.2f} / + getClosestPoints '
              f'{query:.2f} / + getPhysicsEngineParameters + getClosestPoints {both:.2f}')


if __name__ == '__main__':
    main()

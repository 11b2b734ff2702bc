"""The coupling in Drake (``contact_sim.coupling.drake``): a discrete MultibodyPlant at 1 ms, the
README's steel ball dropped and thrown, Hunt-Crossley, two free spheres, friction, bad input."""
import numpy as np
import pytest

import contact_sim as cs

import pydrake.all as pydrake
from contact_sim.coupling.drake import CoupledContacts  # noqa: E402

G, R = 9.81, 0.0127
STEEL = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron', radius=R,
                                  damping_factor=8.87e5)
HUNT = cs.Contact(cs.HUNT_CROSSLEY, STEEL.stiffness, 0.08 * STEEL.stiffness)
MASS = float(cs.sphere_mass(cs.MATERIALS['steel'].density, R))
SPEEDS = np.geomspace(0.05, 10.0, 12)
PHASES = np.arange(8) / 8.0
DT = 1e-3


PLANTS = ['discrete', 'continuous']


def build(bodies, pairs, gravity=G, dt=DT, friction=0.0, plant_kind='discrete'):
    """A plant (discrete at dt, or continuous with the coupling's period dt) with free spheres
    ``bodies`` ((name, mass, radius)), the coupling over ``pairs`` (names; 'world' is the
    floor) wired in; returns (simulator, plant, context, coupled, {name: body})."""
    builder = pydrake.DiagramBuilder()
    continuous = plant_kind == 'continuous'
    plant, _ = pydrake.AddMultibodyPlantSceneGraph(builder, time_step=0.0 if continuous else dt)
    plant.mutable_gravity_field().set_gravity_vector([0.0, 0.0, -gravity])
    made = {name: plant.AddRigidBody(name, pydrake.SpatialInertia.SolidSphereWithMass(m, r))
            for name, m, r in bodies}
    plant.Finalize()
    radius = {name: r for name, _, r in bodies}
    rows = [(a, plant.world_body() if b == 'world' else b, contact, radius[a],
             radius.get(b, 0.0)) for a, b, contact in pairs]
    coupled = builder.AddSystem(CoupledContacts(plant, rows, friction=friction,
                                                period=dt if continuous else None))
    builder.Connect(plant.get_state_output_port(), coupled.get_input_port())
    builder.Connect(coupled.get_output_port(), plant.get_applied_spatial_force_input_port())
    simulator = pydrake.Simulator(builder.Build())
    context = plant.GetMyMutableContextFromRoot(simulator.get_mutable_context())
    return simulator, plant, context, coupled, made


def place(plant, context, body, position, velocity=(0.0, 0.0, 0.0)):
    plant.SetFreeBodyPose(context, body, pydrake.RigidTransform(list(position)))
    plant.SetFreeBodySpatialVelocity(context, body, pydrake.SpatialVelocity(
        np.zeros(3), np.asarray(velocity)))


def velocity(plant, context, body):
    v = plant.EvalBodySpatialVelocityInWorld(context, body)
    return v.translational(), v.rotational()


@pytest.mark.slow
@pytest.mark.parametrize('plant_kind', PLANTS)
def test_drop_of_the_readme_ball(plant_kind):
    exact = cs.simulate_drop(STEEL, MASS, height=1.0)
    simulator, plant, context, coupled, bodies = build(
        [('ball', MASS, R)], [('ball', 'world', STEEL)], friction=0.3, plant_kind=plant_kind)
    ball = bodies['ball']
    place(plant, context, ball, (0.0, 0.0, 1.0 + R))
    rest_from = exact.permanent_contact_time + 0.1
    steps = int(round((rest_from + 10.0) / DT))
    heights, times = np.empty(steps), (np.arange(steps) + 1) * DT
    for i in range(steps):
        simulator.AdvanceTo(times[i])
        heights[i] = plant.EvalBodyPoseInWorld(context, ball).translation()[2] - R
    touch = [i.time for i in coupled.impacts]
    apex = [heights[(times > touch[k]) & (times < touch[k + 1])].max() for k in range(10)]
    for k, (h, h_exact) in enumerate(zip(apex, exact.apex_heights)):
        assert abs(h - h_exact) <= max(0.01 * h_exact, coupled.impacts[k].speed_out * DT)
    assert all(b < a for a, b in zip(apex, apex[1:]))
    z0 = STEEL.static_penetration(MASS * G)
    assert np.max(np.abs(-heights[times > rest_from] - z0)) < 1e-6


@pytest.mark.parametrize('plant_kind', PLANTS)
@pytest.mark.parametrize('contact', [STEEL, HUNT], ids=['azad_featherstone', 'hunt_crossley'])
def test_throws_at_every_phase_of_the_step(contact, plant_kind):
    simulator, plant, context, coupled, bodies = build(
        [('ball', MASS, R)], [('ball', 'world', contact)], gravity=0.0, plant_kind=plant_kind)
    ball = bodies['ball']
    exact = cs.restitution(contact, MASS, SPEEDS)
    start = simulator.get_context().get_time()
    for speed, e in zip(SPEEDS, exact):
        for phase in PHASES:
            place(plant, context, ball, (0.0, 0.0, R + speed * DT * (3.0 + phase)),
                  (0.0, 0.0, -speed))
            count = len(coupled.impacts)
            for _ in range(10):
                start += DT
                simulator.AdvanceTo(start)
            assert len(coupled.impacts) == count + 1
            e_host = velocity(plant, context, ball)[0][2] / speed
            assert abs(e_host - e) < 0.005, (speed, phase, e_host, e)
            assert abs(coupled.impacts[-1].restitution - e) < 0.005


@pytest.mark.parametrize('plant_kind', PLANTS)
def test_two_free_spheres_head_on(plant_kind):
    r2, m2 = 0.02, 0.5
    contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'steel', radius=R,
                                        plate_radius=r2, damping_factor=8.87e5)
    simulator, plant, context, coupled, bodies = build(
        [('a', MASS, R), ('b', m2, r2)], [('a', 'b', contact)], gravity=0.0,
        plant_kind=plant_kind)
    place(plant, context, bodies['a'], (0.0, 0.0, 0.0), (2.0, 0.0, 0.0))
    place(plant, context, bodies['b'], (R + r2 + 0.0031, 0.0, 0.0), (-0.5, 0.0, 0.0))
    simulator.AdvanceTo(12 * DT)
    va = velocity(plant, context, bodies['a'])[0][0]
    vb = velocity(plant, context, bodies['b'])[0][0]
    momentum = MASS * 2.0 - m2 * 0.5
    assert len(coupled.impacts) == 1
    assert abs(MASS * va + m2 * vb - momentum) <= 1e-12 * abs(momentum)
    e = float(cs.restitution(contact, MASS * m2 / (MASS + m2), 2.5))
    assert (vb - va) / 2.5 == pytest.approx(e, abs=0.005)


@pytest.mark.parametrize('friction, regime', [(0.9, 'stick'), (0.05, 'slip')])
def test_oblique_impact_with_friction(friction, regime):
    vn, vt = 1.0, 0.3
    simulator, plant, context, coupled, bodies = build(
        [('ball', MASS, R)], [('ball', 'world', STEEL)], gravity=0.0, friction=friction)
    place(plant, context, bodies['ball'], (0.0, 0.0, R + vn * DT * 3.4), (vt, 0.0, -vn))
    simulator.AdvanceTo(10 * DT)
    e = float(cs.restitution(STEEL, MASS, vn))
    expected = 5.0 / 7.0 * vt if regime == 'stick' else vt - friction * (1.0 + e) * vn
    lin, ang = velocity(plant, context, bodies['ball'])
    assert lin[0] == pytest.approx(expected, rel=0.02)
    assert ang[1] == pytest.approx(2.5 * (vt - expected) / R, rel=0.02)


def test_bad_input_names_its_field():
    builder = pydrake.DiagramBuilder()
    plant, _ = pydrake.AddMultibodyPlantSceneGraph(builder, time_step=0.0)
    plant.AddRigidBody('ball', pydrake.SpatialInertia.SolidSphereWithMass(MASS, R))
    plant.Finalize()
    with pytest.raises(cs.InputError) as refused:     # continuous: the step must be given
        CoupledContacts(plant, [('ball', plant.world_body(), STEEL, R, 0.0)])
    assert refused.value.field == 'period'
    with pytest.raises(cs.InputError) as refused:
        CoupledContacts(plant, [('ball', plant.world_body(), STEEL, R, 0.0)], period=-1e-3)
    assert refused.value.field == 'period'
    builder = pydrake.DiagramBuilder()
    plant, _ = pydrake.AddMultibodyPlantSceneGraph(builder, time_step=DT)
    plant.AddRigidBody('ball', pydrake.SpatialInertia.SolidSphereWithMass(MASS, R))
    fixed = plant.AddRigidBody('fixed', pydrake.SpatialInertia.SolidSphereWithMass(MASS, R))
    plant.WeldFrames(plant.world_frame(), fixed.body_frame())
    plant.Finalize()
    world = plant.world_body()
    for pairs in ([('ball', 'table', STEEL, R, 0.0)], [('ball', world, 'steel', R, 0.0)],
                  [('ball', world, STEEL, 0.0, 0.0)], [('fixed', world, STEEL, R, 0.0)],
                  [('ball', world, STEEL, -R, 0.0)], [], None, [('ball', world, STEEL)]):
        with pytest.raises(cs.InputError) as refused:
            CoupledContacts(plant, pairs)
        assert refused.value.field == 'pairs', pairs
    with pytest.raises(cs.InputError) as refused:
        CoupledContacts(plant, [('ball', world, STEEL, R, 0.0)], friction=-1.0)
    assert refused.value.field == 'friction'


@pytest.mark.slow
def test_the_example_drops_in_pybullet_and_drake():
    """examples/coupled_engines_drop.py: the first apexes in PyBullet and both Drake plants."""
    import importlib.util
    from pathlib import Path
    path = Path(__file__).resolve().parents[2] / 'examples' / 'coupled_engines_drop.py'
    spec = importlib.util.spec_from_file_location('coupled_engines_drop', path)
    example = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(example)
    exact = cs.simulate_drop(STEEL, MASS, height=1.0).apex_heights[:3]
    for heights in (example.pybullet_drop(1.0 / 240.0, 2.2),
                    example.drake_drop(1e-3, 2.2, continuous=False),
                    example.drake_drop(1e-3, 2.2, continuous=True)):
        assert len(heights) >= 3
        for h, h_exact in zip(heights, exact):
            assert h == pytest.approx(h_exact, rel=0.01)


def free_bodies_plant(plant_kind='discrete', gravity=(0.3, -0.2, -G)):
    """A plant with a uniform steel ball 'a' and a free body 'b' of a box's (unequal) inertia
    carrying a 2 cm sphere, both coupled: a on the floor, b on a, the gravity vector set after
    the coupling was made; returns (simulator, plant, context, coupled, bodies)."""
    builder = pydrake.DiagramBuilder()
    continuous = plant_kind == 'continuous'
    plant, _ = pydrake.AddMultibodyPlantSceneGraph(builder, time_step=0.0 if continuous else DT)
    bodies = {'a': plant.AddRigidBody('a', pydrake.SpatialInertia.SolidSphereWithMass(MASS, R)),
              'b': plant.AddRigidBody('b', pydrake.SpatialInertia.SolidBoxWithMass(
                  0.4, 0.02, 0.05, 0.09))}
    plant.Finalize()
    contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'steel', radius=R,
                                        plate_radius=0.02, damping_factor=8.87e5)
    coupled = builder.AddSystem(CoupledContacts(
        plant, [('a', plant.world_body(), STEEL, R, 0.0), ('b', 'a', contact, 0.02, R)],
        friction=0.3, period=DT if continuous else None))
    plant.mutable_gravity_field().set_gravity_vector(list(gravity))     # after: it may change
    builder.Connect(plant.get_state_output_port(), coupled.get_input_port())
    builder.Connect(coupled.get_output_port(), plant.get_applied_spatial_force_input_port())
    simulator = pydrake.Simulator(builder.Build())
    context = plant.GetMyMutableContextFromRoot(simulator.get_mutable_context())
    return simulator, plant, context, coupled, bodies


def through_the_plant(coupled):
    """Make ``coupled`` serve every pair from its plant context (its general path, as for an
    articulated body) instead of the free bodies' state vector."""
    for pair in coupled.pairs:
        pair.sides = None
    coupled._general = True


def test_free_bodies_terms_are_the_plants():
    """The free-body path's velocity, acceleration (gravity, ω × I ω) and inverse mass at the
    contact point are the plant's (CalcJacobianTranslationalVelocity, CalcMassMatrix,
    CalcBiasTerm, CalcGravityGeneralizedForces) on random states and gravity vectors (changed
    after the coupling was made), and so is the impulse."""
    from contact_sim.coupling import NormalCoupling
    from contact_sim.coupling.drake_free import free_terms
    _, plant, _, coupled, _ = free_bodies_plant()
    assert all(pair.sides is not None for pair in coupled.pairs)
    rng = np.random.default_rng(31)
    for _ in range(8):
        state = np.concatenate([rng.normal(size=4), rng.normal(scale=0.05, size=3),
                                rng.normal(size=4), rng.normal(scale=0.05, size=3),
                                rng.normal(scale=20.0, size=3), rng.normal(size=3),
                                rng.normal(scale=20.0, size=3), rng.normal(size=3)])
        plant.mutable_gravity_field().set_gravity_vector(rng.normal(scale=5.0, size=3))
        plant.SetPositionsAndVelocities(coupled._context, state)
        x, gravity = state.tolist(), plant.gravity_field().gravity_vector().tolist()
        for pair in coupled.pairs:
            centres = [x[side.q + 4:side.q + 7] if side else None for side in pair.sides]
            if centres[1] is None:
                normal = np.array([0.0, 0.0, 1.0])
            else:
                normal = np.subtract(centres[0], centres[1])
                normal /= np.linalg.norm(normal)
            point = (np.array(centres[0]) - pair.r_s * normal).tolist()
            fast = [np.array(t) for t in free_terms(pair.sides, x, point, centres, gravity)]
            general = [np.array(t) for t in coupled._terms(pair.sphere, pair.other, point)]
            for f, g in zip(fast, general):
                np.testing.assert_allclose(f, g, rtol=0.0, atol=1e-12 * np.abs(g).max())
            impulses = []
            for velocity, acceleration, inverse in (fast, general):    # 10 µm in, closing
                coupling = NormalCoupling(pair.coupling.contact)
                impulses.append(coupling.step(0.0, -1e-5, -abs(float(normal @ velocity)) - 0.1,
                                              1.0 / float(normal @ inverse @ normal),
                                              float(normal @ acceleration), DT).impulse)
            assert impulses[0] > 0.0
            assert impulses[0] == pytest.approx(impulses[1], rel=1e-12, abs=0.0)


@pytest.mark.parametrize('plant_kind', PLANTS)
def test_free_bodies_move_as_through_the_plant(plant_kind):
    """A spinning ball bounces on the floor, then a spinning body of unequal inertia strikes
    it obliquely as it rises (friction 0.3, tilted gravity): the free-body path and the plant's
    give the same motion."""
    runs = []
    for general in (False, True):
        simulator, plant, context, coupled, bodies = free_bodies_plant(plant_kind)
        if general:
            through_the_plant(coupled)
        plant.SetFreeBodyPose(context, bodies['a'], pydrake.RigidTransform([0.0, 0.0, R + 0.004]))
        plant.SetFreeBodySpatialVelocity(context, bodies['a'], pydrake.SpatialVelocity(
            np.array([0.0, 4.0, 0.0]), np.array([0.3, 0.0, -1.0])))
        plant.SetFreeBodyPose(context, bodies['b'], pydrake.RigidTransform(
            pydrake.RollPitchYaw(0.3, -0.5, 1.1), [0.005, 0.0, 2 * R + 0.02 + 0.02]))
        plant.SetFreeBodySpatialVelocity(context, bodies['b'], pydrake.SpatialVelocity(
            np.array([3.0, -5.0, 20.0]), np.array([-0.2, 0.1, -1.5])))
        simulator.AdvanceTo(11 * DT)    # before the ball, struck down, meets the floor again
        assert [len(pair.coupling.impacts) for pair in coupled.pairs] == [1, 1]
        runs.append((plant.GetPositionsAndVelocities(context), coupled.impacts))
    (fast, fast_impacts), (general, general_impacts) = runs
    for a, b in zip(fast_impacts, general_impacts):
        assert a.speed_out == pytest.approx(b.speed_out, rel=1e-9)
    np.testing.assert_allclose(fast, general, rtol=1e-9, atol=1e-12)


def test_an_articulated_or_offset_body_goes_through_the_plant():
    builder = pydrake.DiagramBuilder()
    plant, _ = pydrake.AddMultibodyPlantSceneGraph(builder, time_step=DT)
    arm = plant.AddRigidBody('arm', pydrake.SpatialInertia.SolidSphereWithMass(MASS, R))
    plant.AddJoint(pydrake.RevoluteJoint('hinge', plant.world_frame(), arm.body_frame(),
                                         [0.0, 1.0, 0.0]))
    plant.AddRigidBody('offset', pydrake.SpatialInertia(
        MASS, [0.0, 0.0, 0.003], pydrake.UnitInertia.SolidSphere(R)))
    plant.Finalize()
    world = plant.world_body()
    coupled = CoupledContacts(plant, [('arm', world, STEEL, R, 0.0),
                                      ('offset', world, STEEL, R, 0.0)])
    assert [pair.sides for pair in coupled.pairs] == [None, None]

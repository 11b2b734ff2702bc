"""The Drake coupling's pairs as the issue writes them, ``(body_a, body_b, contact)``: the shapes
from the scene graph (``contact_sim.coupling.drake_shapes``): a ball's ``Sphere`` (offset from
its body's origin or not) on the world's ``HalfSpace``, level or tilted, or on an SDF's static
ground, two spheres; the same impacts as the radii given as a 5-tuple; the refusals."""
import numpy as np
import pytest

import contact_sim as cs

import pydrake.all as pydrake
from contact_sim.coupling.drake import CoupledContacts  # noqa: E402

G, R, DT = 9.81, 0.0127, 1e-3
STEEL = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron', radius=R,
                                  damping_factor=8.87e5)
MASS = float(cs.sphere_mass(cs.MATERIALS['steel'].density, R))
FRICTION = pydrake.CoulombFriction(0.3, 0.3)
PLANTS = ['discrete', 'continuous']


def plant_of(plant_kind='discrete'):
    builder = pydrake.DiagramBuilder()
    plant, scene_graph = pydrake.AddMultibodyPlantSceneGraph(
        builder, time_step=0.0 if plant_kind == 'continuous' else DT)
    plant.mutable_gravity_field().set_gravity_vector([0.0, 0.0, -G])
    return builder, plant, scene_graph


def ball_of(plant, name='ball', mass=MASS, radius=R, centre=(0.0, 0.0, 0.0), shape=True):
    """A free ball whose centre of mass, and Sphere if ``shape``, sit at ``centre`` in its
    body's frame."""
    centre = np.asarray(centre, dtype=float)
    ball = plant.AddRigidBody(name, pydrake.SpatialInertia.SolidSphereWithMass(
        mass, radius).Shift(-centre))
    if shape:
        plant.RegisterCollisionGeometry(ball, pydrake.RigidTransform(centre),
                                        pydrake.Sphere(radius), name, FRICTION)
    return ball


def half_space(plant, normal=(0.0, 0.0, 1.0), point=(0.0, 0.0, 0.0)):
    plant.RegisterCollisionGeometry(plant.world_body(), pydrake.HalfSpace.MakePose(
        np.asarray(normal, float), np.asarray(point, float)), pydrake.HalfSpace(), 'floor',
        FRICTION)


def wire(builder, plant, pairs, plant_kind='discrete', **options):
    coupled = builder.AddSystem(CoupledContacts(
        plant, pairs, period=DT if plant_kind == 'continuous' else None, **options))
    builder.Connect(plant.get_state_output_port(), coupled.get_input_port())
    builder.Connect(coupled.get_output_port(), plant.get_applied_spatial_force_input_port())
    simulator = pydrake.Simulator(builder.Build())
    return simulator, plant.GetMyMutableContextFromRoot(simulator.get_mutable_context()), coupled


def place(plant, context, body, centre, velocity=(0.0, 0.0, 0.0), offset=(0.0, 0.0, 0.0),
          rotation=None):
    """Put ``body`` so that the point ``offset`` of its frame is at ``centre``."""
    rotation = rotation or pydrake.RotationMatrix()
    plant.SetFreeBodyPose(context, body, pydrake.RigidTransform(
        rotation, np.asarray(centre, float) - rotation.multiply(np.asarray(offset, float))))
    plant.SetFreeBodySpatialVelocity(context, body, pydrake.SpatialVelocity(
        np.zeros(3), np.asarray(velocity, float)))


def drop(plant_kind, form, seconds=0.6):
    """The ball dropped from 0.2 m on the level half-space, friction 0.3: its impacts."""
    builder, plant, scene_graph = plant_of(plant_kind)
    ball = ball_of(plant, shape=form == 3)
    if form == 3:
        half_space(plant)
    plant.Finalize()
    row = ('ball', plant.world_body(), STEEL) + ((R, 0.0) if form == 5 else ())
    simulator, context, coupled = wire(builder, plant, [row], plant_kind, friction=0.3,
                                       scene_graph=scene_graph)
    place(plant, context, ball, (0.0, 0.0, 0.2))
    simulator.AdvanceTo(seconds)
    return coupled.impacts


@pytest.mark.parametrize('plant_kind', PLANTS)
def test_the_issues_form_gives_the_impacts_of_the_radii_form(plant_kind):
    shaped, given = drop(plant_kind, 3), drop(plant_kind, 5)
    assert len(shaped) == len(given) >= 2
    for a, b in zip(shaped, given):
        assert a.time == pytest.approx(b.time, rel=1e-9, abs=0.0)
        assert a.speed_out == pytest.approx(b.speed_out, rel=1e-9)
        assert a.restitution == pytest.approx(b.restitution, abs=1e-9)


def test_two_spheres_by_their_shapes_as_by_their_radii():
    r2, m2 = 0.02, 0.5
    contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'steel', radius=R,
                                        plate_radius=r2, damping_factor=8.87e5)
    out = []
    for form in (3, 5):
        builder, plant, scene_graph = plant_of()
        plant.mutable_gravity_field().set_gravity_vector([0.0, 0.0, 0.0])
        a = ball_of(plant, 'a', shape=form == 3)
        b = ball_of(plant, 'b', m2, r2, shape=form == 3)
        plant.Finalize()
        row = ('a', 'b', contact) + ((R, r2) if form == 5 else ())
        simulator, context, coupled = wire(builder, plant, [row], scene_graph=scene_graph)
        place(plant, context, a, (0.0, 0.0, 0.0), (2.0, 0.0, 0.0))
        place(plant, context, b, (R + r2 + 0.0031, 0.0, 0.0), (-0.5, 0.0, 0.0))
        simulator.AdvanceTo(12 * DT)
        out.append((coupled.impacts, plant.GetVelocities(context)))
    (shaped, v_shaped), (given, v_given) = out
    assert len(shaped) == len(given) == 1
    assert shaped[0].speed_out == pytest.approx(given[0].speed_out, rel=1e-9)
    np.testing.assert_allclose(v_shaped, v_given, rtol=0.0, atol=1e-12)


@pytest.mark.parametrize('plant_kind', PLANTS)
def test_a_sphere_off_its_bodys_origin_drops_as_one_on_it(plant_kind):
    # the body's origin 6 cm from the ball's centre (its centre of mass), the body turned
    # 0.7 rad: the centre read from GetPoseInFrame falls as the centred ball's does
    offset = (0.03, -0.02, 0.05)
    given = drop(plant_kind, 5)
    builder, plant, scene_graph = plant_of(plant_kind)
    ball = ball_of(plant, centre=offset)
    half_space(plant)
    plant.Finalize()
    simulator, context, coupled = wire(builder, plant, [(ball, plant.world_body(), STEEL)],
                                       plant_kind, friction=0.3, scene_graph=scene_graph)
    place(plant, context, ball, (0.0, 0.0, 0.2), offset=offset,
          rotation=pydrake.RotationMatrix.MakeXRotation(0.7))
    simulator.AdvanceTo(0.6)
    shaped = coupled.impacts
    assert len(shaped) == len(given) >= 2
    for a, b in zip(shaped, given):
        assert a.time == pytest.approx(b.time, abs=1e-9)
        assert a.speed_out == pytest.approx(b.speed_out, rel=1e-9)


@pytest.mark.parametrize('plant_kind', PLANTS)
def test_a_ball_rolls_down_a_tilted_half_space(plant_kind):
    """On a plane tilted 0.2 rad, μ = 0.3 (stick needs 2/7 tan θ = 0.058): from rest the ball
    rolls without slipping, its speed along the slope 5/7 g sin θ t, on the plane.  (Before the
    force was applied at the sphere's centre with its torque held in the world, the continuous
    plant turned the contact point with the ball over each step: 0.745 m/s at 0.5 s instead of
    0.696.)"""
    theta, seconds = 0.2, 0.5
    normal = np.array([np.sin(theta), 0.0, np.cos(theta)])
    down = np.array([np.cos(theta), 0.0, -np.sin(theta)])
    builder, plant, scene_graph = plant_of(plant_kind)
    ball = ball_of(plant)
    half_space(plant, normal, (0.0, 0.0, 0.1))
    plant.Finalize()
    simulator, context, coupled = wire(builder, plant, [('ball', plant.world_body(), STEEL)],
                                       plant_kind, friction=0.3, scene_graph=scene_graph)
    height = 0.1 * normal[2]            # the plane's height along its normal
    z0 = STEEL.static_penetration(MASS * G * np.cos(theta))
    start = (height + R - z0) * normal
    place(plant, context, ball, start)
    simulator.AdvanceTo(seconds)
    v = plant.EvalBodySpatialVelocityInWorld(context, ball)
    rolling = 5.0 / 7.0 * G * np.sin(theta) * seconds
    assert float(v.translational() @ down) == pytest.approx(rolling, rel=0.01)
    assert float(v.rotational()[1]) * R == pytest.approx(rolling, rel=0.01)     # no slip
    centre = plant.EvalBodyPoseInWorld(context, ball).translation()
    assert abs(float(centre @ normal) - height - R + z0) < 1e-6
    assert abs(float((centre - start) @ down) - 0.5 * rolling * seconds) < 0.01 * rolling


@pytest.mark.parametrize('plant_kind', PLANTS)
def test_a_ball_rolling_on_the_floor_keeps_its_speed(plant_kind):
    """Thrown along the floor at 0.5 m/s without spin, μ = 0.3: it rolls at 5/7 of it for 1 s.
    (Before the force was applied at the sphere's centre, the continuous plant's ball sped up
    to 0.467 m/s in 1 s instead of 0.357.)"""
    builder, plant, scene_graph = plant_of(plant_kind)
    ball = ball_of(plant, shape=False)
    plant.Finalize()
    simulator, context, coupled = wire(builder, plant, [('ball', plant.world_body(), STEEL,
                                                         R, 0.0)], plant_kind, friction=0.3)
    place(plant, context, ball, (0.0, 0.0, R - STEEL.static_penetration(MASS * G)),
          (0.5, 0.0, 0.0))
    for t in (0.1, 1.0):
        simulator.AdvanceTo(t)
        v = plant.EvalBodySpatialVelocityInWorld(context, ball)
        assert v.translational()[0] == pytest.approx(0.5 * 5.0 / 7.0, rel=1e-6), t
        assert v.rotational()[1] * R == pytest.approx(0.5 * 5.0 / 7.0, rel=1e-6), t


SCENE = """<?xml version="1.0"?>
<sdf version="1.7">
  <model name="scene">
    <link name="ground">
      <collision name="plane"><geometry><plane><normal>0 0 1</normal><size>10 10</size>
      </plane></geometry></collision>
    </link>
    <joint name="weld" type="fixed"><parent>world</parent><child>ground</child></joint>
    <link name="ball">
      <inertial><mass>%r</mass><inertia><ixx>%r</ixx><iyy>%r</iyy><izz>%r</izz>
      <ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial>
      <collision name="sphere"><geometry><sphere><radius>%r</radius></sphere></geometry>
      </collision>
    </link>
  </model>
</sdf>"""


def test_a_scene_loaded_from_sdf_its_ground_welded_to_the_world():
    inertia = 0.4 * MASS * R * R
    builder, plant, scene_graph = plant_of()
    pydrake.Parser(plant).AddModelsFromString(SCENE % (MASS, inertia, inertia, inertia, R),
                                              'sdf')
    plant.Finalize()
    ball, ground = plant.GetBodyByName('ball'), plant.GetBodyByName('ground')
    simulator, context, coupled = wire(builder, plant, [(ball, ground, STEEL)], friction=0.3,
                                       scene_graph=scene_graph)
    place(plant, context, ball, (0.0, 0.0, 0.2))
    simulator.AdvanceTo(0.6)
    given = drop('discrete', 5)
    assert len(coupled.impacts) == len(given) >= 2
    for a, b in zip(coupled.impacts, given):
        assert a.speed_out == pytest.approx(b.speed_out, rel=1e-9)


def refused(build, pairs=None, scene_graph=True):
    """The InputError of the coupling over ``build(plant)``'s scene (pairs: ball on world)."""
    builder, plant, graph = plant_of()
    build(plant)
    plant.Finalize()
    pairs = pairs or [('ball', plant.world_body(), STEEL)]
    with pytest.raises(cs.InputError) as error:
        CoupledContacts(plant, pairs, scene_graph=graph if scene_graph is True else scene_graph)
    return error.value


def _ball_and_floor(plant):
    ball_of(plant)
    half_space(plant)


def _two_shapes(plant):
    ball = ball_of(plant)
    plant.RegisterCollisionGeometry(ball, pydrake.RigidTransform([0.0, 0.0, 0.01]),
                                    pydrake.Sphere(R), 'second', FRICTION)
    half_space(plant)


def _box_ball(plant):
    ball = ball_of(plant, shape=False)
    plant.RegisterCollisionGeometry(ball, pydrake.RigidTransform(), pydrake.Box(R, R, R), 'box',
                                    FRICTION)


def _box_world(plant):
    ball_of(plant)
    plant.RegisterCollisionGeometry(plant.world_body(), pydrake.RigidTransform(),
                                    pydrake.Box(1.0, 1.0, 0.1), 'table', FRICTION)


def _half_space_on_the_ball(plant):
    ball = ball_of(plant, shape=False)
    plant.RegisterCollisionGeometry(ball, pydrake.RigidTransform(), pydrake.HalfSpace(), 'hs',
                                    FRICTION)


@pytest.mark.parametrize('build, words', [
    (_two_shapes, ('ball', '2 collision geometries')),
    (_box_ball, ('ball', 'Box', 'Sphere')),
    (_box_world, ('world', 'Box', 'HalfSpace')),
    (_half_space_on_the_ball, ('ball', 'HalfSpace', 'welded')),
    (lambda plant: ball_of(plant, shape=False), ('ball', '0 collision geometries', 'radius')),
], ids=['several', 'box_ball', 'box_world', 'moving_half_space', 'no_geometry'])
def test_a_shape_the_coupling_cannot_use_is_refused_on_pairs(build, words):
    error = refused(build)
    assert error.field == 'pairs'
    for word in words:
        assert word in str(error), (word, str(error))


def test_the_shapes_need_the_plants_scene_graph():
    error = refused(_ball_and_floor, scene_graph=None)
    assert error.field == 'scene_graph'
    assert 'ball' in str(error) and 'SceneGraph' in str(error) and 'radius' in str(error)
    _, other = pydrake.AddMultibodyPlantSceneGraph(pydrake.DiagramBuilder(), time_step=DT)
    for wrong in (other, 'scene'):
        error = refused(_ball_and_floor, scene_graph=wrong)
        assert error.field == 'scene_graph', wrong


def test_a_row_of_another_length_is_refused():
    error = refused(_ball_and_floor, pairs=[('ball', 'world', STEEL, R)])
    assert error.field == 'pairs' and '(body, body, Contact)' in str(error)

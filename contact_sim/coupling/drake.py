"""The coupling in Drake: ``CoupledContacts(plant, pairs)``, a ``LeafSystem`` whose output goes
to the plant's applied spatial force input port.

Each pair names two bodies of a finalized ``MultibodyPlant`` (by ``RigidBody`` or by name) and
a contact, ``(body_a, body_b, contact)``: the shapes are read once from the ``scene_graph``
given (``contact_sim.coupling.drake_shapes``): a sphere (a body's one ``Sphere`` collision
geometry, its centre anywhere in the body's frame) against the world's ``HalfSpace`` (or one on
a body welded to the world; any orientation: its normal and height from its pose), against the
world without collision geometry (the floor z = ``floor_height``, normal +z), or against
another sphere.  The radii may instead be given with the pair, ``(body_a, body_b, contact,
radius_a, radius_b)`` (0 for the world's floor; a sphere's centre is then its body's origin; no
scene graph needed).  A plane is kept as (unit normal, height along it), a sphere's centre as
a point of its body's frame.  The system reads the plant's state (connect
``plant.get_state_output_port()`` to ``get_input_port()``), and at each of the plant's steps
evaluates, in a plant context of its own (free bodies: from the state vector, below): the gap and normal from the bodies' poses, the contact
point's relative velocity and translational Jacobian (``CalcJacobianTranslationalVelocity``),
the effective mass along the normal (``CalcMassMatrix``), the rest of the system's normal
acceleration J M⁻¹ (τ_g − C v) (``CalcGravityGeneralizedForces``, ``CalcBiasTerm``; J̇v left
out), then ``NormalCoupling.step`` and friction, and outputs impulse / dt as an
``ExternallyAppliedSpatialForce`` on each body: at its origin, the force with its moment about
the origin from the contact point (the point's offset from the origin is held in the world over
the step, as a sphere's contact point is).

The discrete plant steps the velocities with the applied forces and then the positions with
the new velocities (``NormalCoupling``'s ``'semi_implicit'`` host): the output is computed once
per plant step, keyed on the context's time.  A continuous plant (``time_step`` = 0) is coupled
at the ``period`` given: a periodic update at each period's start plans the step (the
``'continuous'`` host), and the output is the force linear in time over the period that brings
the plant's gap and velocity to the exact ones at its end (exact for an integrator of order 3
or more on a free body; the tangential impulse is held constant).

A pair whose bodies are free (a floating base with a quaternion, no body outboard of it, its
centre of mass at its origin) or the world is served without the plant context: the bodies'
poses and velocities are read from the state vector (quaternion and position; angular then
translational velocity, in the world), and the same terms come from each body's mass and
rotational inertia read at construction (constant in its frame; the plant's default
parameters, as the plant context's), the plant's gravity vector (read at each step in reach:
it may be changed after ``Finalize``) and the gyroscopic term ω × I ω.  ``test_drake.py`` holds
them to the plant context's to 1e-12.  Drake's own contact between a pair's collision
geometries is filtered out in the ``scene_graph`` given (refused without it).  Units: SI.
"""
import math

import numpy as np
from pydrake.common.cpp_param import List
from pydrake.common.value import AbstractValue, Value
from pydrake.geometry import CollisionFilterDeclaration, GeometrySet
from pydrake.multibody.math import SpatialForce
from pydrake.multibody.plant import (ExternallyAppliedSpatialForce,
                                     ExternallyAppliedSpatialForce_)
from pydrake.multibody.tree import JacobianWrtVariable
from pydrake.systems.framework import LeafSystem

from contact_sim.coupling.core import NormalCoupling
from contact_sim.coupling.drake_free import WORLD, FreeBody, dot, free_terms
from contact_sim.coupling.drake_shapes import UP, body_shape
from contact_sim.coupling.rows import pair_rows, refuse_tunnel, tangential_impulse
from contact_sim.model import require_contact
from contact_sim.validation import (InputError, require_nonnegative, require_positive,
                                    require_real)


# a pair whose gap is beyond this (m) and that carries no state is not looked at further
REACH = 0.05


class CoupledContacts(LeafSystem):
    """Drake stepped with the package's exact contacts between body pairs.

    Parameters
    ----------
    plant : pydrake.multibody.plant.MultibodyPlant
        A finalized plant, discrete (``time_step`` > 0) or continuous.
    pairs : sequence of (body, body, Contact) or (body, body, Contact, float, float)
        (body_a, body_b, contact): bodies as ``RigidBody`` or names, their shapes from
        ``scene_graph``: a body's one ``Sphere`` collision geometry (centred anywhere in its
        frame), the world's ``HalfSpace`` (or one on a body welded to the world), or the world
        without collision geometry (the floor z = ``floor_height``).  Or (body_a, body_b,
        contact, radius_a, radius_b): the radii of their spheres in m, centred on the bodies'
        origins (0: the world's floor, z = ``floor_height``).
    friction : float, optional
        Coulomb's μ of every pair, >= 0 (default 0).
    floor_height : float, optional
        The height of the world's floor, m (default 0): the world without collision geometry,
        or radius 0 in a 5-tuple (a ``HalfSpace``'s height comes from its pose).
    period : float, optional
        The coupling's step, s, > 0: needed for a continuous plant; a discrete plant's is its
        ``time_step``.
    reach : float, optional
        A pair farther apart than this (m) and carrying no contact state costs its poses only;
        > 0 (default ``REACH``); it must exceed the distance the bodies close in one step.
    scene_graph : pydrake.geometry.SceneGraph, optional
        The plant's scene graph (of ``AddMultibodyPlantSceneGraph``), before its context is
        made: the shapes of a 3-tuple's bodies are read there (``model_inspector``), and
        Drake's own contact between the collision geometries of a coupled pair's bodies is
        filtered out there.  Needed for 3-tuples with collision geometry, and when both bodies
        of a pair have collision geometry.

    Raises
    ------
    InputError
        Keyed ``plant`` (not finalized), ``period`` (a continuous plant without one, or one
        that is not a discrete plant's ``time_step``), ``reach``,
        ``pairs`` (no such body, no sphere, no degree of freedom, a bad radius, a row of
        another length; a body with no or several collision geometries, or a shape that is not
        a ``Sphere`` or, on a body that does not move, a ``HalfSpace``), ``friction``,
        ``floor_height`` or ``scene_graph`` (missing or not the plant's while a 3-tuple's shape
        must be read, or while both bodies of a pair have collision geometry: Drake's own
        contact would act beside the coupling).

    Examples
    --------
    >>> import contact_sim as cs
    >>> from pydrake.all import (AddMultibodyPlantSceneGraph, CoulombFriction, DiagramBuilder,
    ...                          HalfSpace, RigidTransform, Simulator, SpatialInertia, Sphere)
    >>> from contact_sim.coupling.drake import CoupledContacts
    >>> builder = DiagramBuilder()
    >>> plant, scene_graph = AddMultibodyPlantSceneGraph(builder, time_step=1e-3)
    >>> ball = plant.AddRigidBody('ball', SpatialInertia.SolidSphereWithMass(0.0669, 0.0127))
    >>> _ = plant.RegisterCollisionGeometry(ball, RigidTransform(), Sphere(0.0127), 'ball',
    ...                                     CoulombFriction(0.3, 0.3))
    >>> _ = plant.RegisterCollisionGeometry(plant.world_body(), RigidTransform(), HalfSpace(),
    ...                                     'floor', CoulombFriction(0.3, 0.3))
    >>> plant.Finalize()
    >>> contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron',
    ...                                     radius=0.0127, damping_factor=8.87e5)
    >>> coupled = builder.AddSystem(CoupledContacts(
    ...     plant, [(ball, plant.world_body(), contact)], scene_graph=scene_graph))
    >>> _ = builder.Connect(plant.get_state_output_port(), coupled.get_input_port())
    >>> _ = builder.Connect(coupled.get_output_port(),
    ...                     plant.get_applied_spatial_force_input_port())
    >>> diagram = builder.Build()
    >>> simulator = Simulator(diagram)
    >>> context = plant.GetMyMutableContextFromRoot(simulator.get_mutable_context())
    >>> plant.SetFreeBodyPose(context, ball, RigidTransform([0, 0, 0.1]))
    >>> _ = simulator.AdvanceTo(0.3)
    >>> print(f"e = {coupled.impacts[0].restitution:.3f}")
    e = 0.726
    """

    def __init__(self, plant, pairs, friction=0.0, floor_height=0.0, period=None, reach=REACH,
                 scene_graph=None):
        LeafSystem.__init__(self)
        if not plant.is_finalized():
            raise InputError('plant', 'not finalized', '{n[plant]} is {value}: allowed a '
                             'finalized MultibodyPlant', value='not finalized')
        self.continuous = not plant.time_step() > 0.0
        if self.continuous:
            if period is None:
                raise InputError('period', None, '{n[period]} is missing: a continuous plant '
                                 '(time_step = 0) needs the coupling\'s step, period > 0 (s)')
            self.dt = require_positive('period', period)
        else:
            if period is not None and require_positive('period', period) != plant.time_step():
                raise InputError('period', period, '{n[period]} = {value}: allowed the '
                                 "discrete plant's time_step, %r" % plant.time_step())
            self.dt = float(plant.time_step())
        self.plant = plant
        self.friction = require_nonnegative('friction', friction)
        self.reach = require_positive('reach', reach)
        self.floor_height = require_real('floor_height', floor_height)
        rows = pair_rows(pairs, '(body, body, Contact)')
        self._context = plant.CreateDefaultContext()
        self._free = {}             # body index: FreeBody, the free bodies of the pairs
        self._applied = []          # an ExternallyAppliedSpatialForce a moving side, reused
        self.pairs = [self._pair(row, i, scene_graph) for i, row in enumerate(rows)]
        self._leave_drakes_contact(scene_graph)
        self._general = any(p.sides is None for p in self.pairs)   # a pair needs the context
        self._gravity = plant.gravity_field()
        self._memo = (None, [])
        self._far = set()           # the pairs out of reach at the last step
        self._port = self.DeclareVectorInputPort('plant_state', plant.num_multibody_states())
        self.DeclareAbstractOutputPort(
            'applied_spatial_force',
            lambda: Value[List[ExternallyAppliedSpatialForce_[float]]]([]), self._output)
        if self.continuous:     # the plan of a step, made at its start: (t₀, rows)
            self._plan = self.DeclareAbstractState(AbstractValue.Make((0.0, [])))
            self.DeclarePeriodicUnrestrictedUpdateEvent(self.dt, 0.0, self._update)

    def _leave_drakes_contact(self, scene_graph):
        """Filter Drake's own contact between each pair's collision geometries out."""
        plant = self.plant
        if not plant.geometry_source_is_registered():
            return
        for index, pair in enumerate(self.pairs):
            a, b = pair.sphere, pair.other
            shapes = [plant.GetCollisionGeometriesForBody(body) for body in (a, b)]
            if not (shapes[0] and shapes[1]):
                continue
            if scene_graph is None:
                raise InputError('scene_graph', None, "{n[scene_graph]} is missing: pairs[%d]'s "
                                 "bodies %r and %r have collision geometry, and Drake's own "
                                 'contact would act beside the coupling: allowed the plant\'s '
                                 'SceneGraph (the pair is filtered out there)'
                                 % (index, a.name(), b.name()))
            scene_graph.collision_filter_manager().Apply(CollisionFilterDeclaration()
                                                         .ExcludeBetween(GeometrySet(shapes[0]),
                                                                         GeometrySet(shapes[1])))

    def _body(self, value, index):
        plant = self.plant
        if isinstance(value, str):
            if not plant.HasBodyNamed(value):
                raise InputError('pairs', value, '{n[pairs]}[%d] names {value}, which is no body '
                                 'of the plant: allowed the names of its bodies' % index)
            return plant.GetBodyByName(value)
        if hasattr(value, 'index') and hasattr(value, 'body_frame'):
            return value
        raise InputError('pairs', value, '{n[pairs]}[%d] = {value}: allowed a RigidBody or a '
                         'body name' % index)

    def _pair(self, row, index, scene_graph):
        """The ``_Pair`` of ``row``: (body, body, Contact) with the shapes from ``scene_graph``,
        or (body, body, Contact, radius, radius)."""
        if len(row) not in (3, 5):
            raise InputError('pairs', row, '{n[pairs]}[%d] = {value}: allowed (body, body, '
                             'Contact) or (body, body, Contact, radius, radius)' % index)
        a, b = self._body(row[0], index), self._body(row[1], index)
        contact = require_contact(row[2], 'pairs')
        plant = self.plant
        world = plant.world_body().index()
        if len(row) == 3:           # the shapes from the scene graph
            shapes = [body_shape(plant, scene_graph, body, index, self.floor_height,
                                 None if _moves(plant, body) else
                                 plant.EvalBodyPoseInWorld(self._context, body))
                      for body in (a, b)]
        else:
            shapes = [(require_nonnegative('pairs', r), np.zeros(3), (UP, self.floor_height))
                      for r in row[3:]]
            for body, (radius, *_) in zip((a, b), shapes):
                if radius == 0.0 and body.index() != world:
                    raise InputError('pairs', body.name(), '{n[pairs]}[%d]: body {value} has '
                                     'radius 0: allowed 0 for the world (its floor) only' % index)
        if shapes[0][0] == 0.0 and shapes[1][0] == 0.0:
            raise InputError('pairs', row[:2], '{n[pairs]}[%d] has no sphere: allowed a sphere '
                             'against the floor or another sphere' % index)
        moving = [body.index() != world and _moves(plant, body) for body in (a, b)]
        if not any(moving):
            raise InputError('pairs', row[:2], '{n[pairs]}[%d]: neither body has a degree of '
                             'freedom: allowed a pair that can move' % index)
        if shapes[0][0] == 0.0:     # the sphere first
            a, b, shapes, moving = b, a, shapes[::-1], moving[::-1]
        (r_s, centre_s, _), (r_o, centre_o, plane) = shapes
        sides = [self._free_body(body) for body in (a, b)]
        if sides[1] is None and not moving[1]:      # the world, or a body welded to it
            sides[1] = WORLD
        slots = []      # (its force object, the sign of its force, the side: 0 sphere, 1 other)
        for side, (body, sign) in enumerate(((a, 1.0), (b, -1.0))):
            if moving[side]:            # applied at its origin (the force and its moment)
                slots.append((len(self._applied), sign, side))
                self._applied.append(ExternallyAppliedSpatialForce())
                self._applied[-1].body_index = body.index()
                self._applied[-1].p_BoBq_B = _ZERO
        return _Pair(a, b, r_s, r_o, NormalCoupling(
            contact, host='continuous' if self.continuous else 'semi_implicit'),
            None if None in sides else tuple(sides), tuple(slots), _offset(centre_s),
            _offset(centre_o), None if plane is None else (tuple(float(c) for c in plane[0]),
                                                 float(plane[1])))

    def _free_body(self, body):
        """The body's ``FreeBody`` constants, or None when it is not a free body (a floating base
        with a quaternion, no body outboard of it, its centre of mass at its origin)."""
        plant = self.plant
        key = int(body.index())
        if key in self._free or key == int(plant.world_body().index()):
            return self._free.get(key)
        joints = [plant.get_joint(i) for i in plant.GetJointIndices()
                  if plant.get_joint(i).child_body().index() == body.index()]
        inertia = body.default_spatial_inertia()
        if not (body.is_floating_base_body() and body.has_quaternion_dofs() and len(joints) == 1
                and joints[0].type_name() == 'quaternion_floating'
                and joints[0].frame_on_parent().index() == plant.world_frame().index()
                and joints[0].frame_on_child().index() == body.body_frame().index()
                and list(plant.GetBodiesKinematicallyAffectedBy([joints[0].index()]))
                == [body.index()] and not np.any(inertia.get_com()) and inertia.get_mass() > 0.0):
            return None
        self._free[key] = FreeBody(body, plant.num_positions() + body.floating_velocities_start_in_v(),
                                inertia.get_mass(),
                                inertia.CalcRotationalInertia().CopyToFullMatrix3(),
                                plant.is_gravity_enabled(body.model_instance()))
        return self._free[key]

    @property
    def impacts(self):
        """Every impact of every pair so far (``CoupledImpact``), in time order."""
        return sorted((i for p in self.pairs for i in p.coupling.impacts), key=lambda i: i.time)

    def _output(self, context, output):
        t = float(context.get_time())
        if self.continuous:     # the step's linear force at t
            t0, rows = context.get_abstract_state(0).get_value()
            late = t - t0 - 0.5 * self.dt
            output.set_value([self._apply(slot, arm, [m + late * r for m, r in zip(mean, rate)])
                              for slot, arm, mean, rate in rows])
            return
        if self._memo[0] != t:
            self._memo = (t, [self._apply(slot, arm, mean) for slot, arm, mean, _
                              in self._forces(t, self._port.Eval(context))])
        output.set_value(self._memo[1])

    def _apply(self, slot, arm, force):
        """The side's ``ExternallyAppliedSpatialForce``: ``force`` (N, world) at ``arm`` (m,
        world) from the body's origin, as the force and its moment at the origin."""
        (ax, ay, az), (fx, fy, fz) = arm, force
        out = self._applied[slot]
        out.F_Bq_W = SpatialForce([ay * fz - az * fy, az * fx - ax * fz, ax * fy - ay * fx],
                                  [fx, fy, fz])
        return out

    def _update(self, context, state):
        """A continuous plant's step starts: plan its forces from the plant's state."""
        t = float(context.get_time())
        rows = self._forces(t, self._port.Eval(context))
        state.get_mutable_abstract_state(0).set_value((t, rows))

    def _forces(self, t, state):
        """(force object's slot, contact point from the body's origin (m, world), mean force N,
        force rate N/s) rows of the step from t (s) at the plant's state (plain floats: numpy
        costs more on 3-vectors)."""
        dt, mu = self.dt, self.friction
        if self._general:
            self.plant.SetPositionsAndVelocities(self._context, state)
        x = state.tolist()
        forces = []
        for index, pair in enumerate(self.pairs):
            sides, coupling = pair.sides, pair.coupling
            origin, (cx, cy, cz) = self._centre(pair.sphere, sides and sides[0], pair.c_s, x)
            if pair.r_o == 0.0:         # a plane: (unit normal, height along it)
                normal, height = pair.plane
                gap = dot(normal, (cx, cy, cz)) - height - pair.r_s
                origins = (origin, None)
            else:
                origin_o, other = self._centre(pair.other, sides and sides[1], pair.c_o, x)
                d = (cx - other[0], cy - other[1], cz - other[2])
                dist = math.sqrt(dot(d, d))
                normal, gap = (d[0] / dist, d[1] / dist, d[2] / dist), dist - pair.r_s - pair.r_o
                origins = (origin, origin_o)
            if gap > self.reach and not coupling.carrying:
                self._far.add(index)
                continue                # out of reach: no dynamics evaluated
            if index in self._far and gap < 0.0:
                refuse_tunnel(index, gap, self.reach)
            self._far.discard(index)
            nx, ny, nz = normal
            point = (cx - pair.r_s * nx, cy - pair.r_s * ny, cz - pair.r_s * nz)
            if sides is None:
                velocity, acceleration, inverse = self._terms(pair.sphere, pair.other, point)
            else:
                velocity, acceleration, inverse = free_terms(
                    sides, x, point, origins, self._gravity.gravity_vector().tolist())
            push = [dot(row, normal) for row in inverse]     # W n (W symmetric)
            step = coupling.step(t, gap, dot(normal, velocity), 1.0 / dot(normal, push),
                                 dot(normal, acceleration), dt)
            p = step.impulse
            if p == 0.0:
                continue
            impulse = [p * nx, p * ny, p * nz]
            free = [v + dt * a + p * w for v, a, w in zip(velocity, acceleration, push)]
            along = dot(free, normal)
            if mu > 0.0 and any(f - along * n for f, n in zip(free, normal)):   # it slides
                tangential = tangential_impulse(p, np.array(free), np.array(normal),
                                                np.array(inverse), mu).tolist()
                impulse = [i + f for i, f in zip(impulse, tangential)]
            rate = step.force_rate
            for slot, sign, side in pair.slots:
                forces.append((slot, [q - c for q, c in zip(point, origins[side])],
                               [sign * i / dt for i in impulse], [sign * rate * n for n in normal]))
        return forces

    def _centre(self, body, side, offset, x):
        """The body's origin and its sphere's centre in the world (m, lists): the centre at
        ``offset`` (m, the body's frame; None: the origin); from the state ``x`` (a list) for a
        free body."""
        if side:
            origin = x[side.q + 4:side.q + 7]
            if offset is None:
                return origin, origin
            return origin, (np.array(origin) + side.rotation(x) @ offset).tolist()
        pose = self.plant.EvalBodyPoseInWorld(self._context, body)
        origin = pose.translation().tolist()
        return origin, origin if offset is None else pose.multiply(offset).tolist()

    def _terms(self, sphere, other, point):
        """The plant's terms at the contact ``point`` (m, world) of a pair, from the context: its
        relative velocity (m/s), the rest of the system's acceleration J M⁻¹ (τ_g − C v) (m/s²)
        and the 3x3 inverse mass J M⁻¹ Jᵀ (1/kg), as lists."""
        plant, ctx = self.plant, self._context
        point = np.array(point)
        jac = self._jacobian(sphere, point) - self._jacobian(other, point)
        rhs = np.column_stack((plant.CalcGravityGeneralizedForces(ctx) - plant.CalcBiasTerm(ctx),
                               jac.T))
        solved = np.linalg.solve(plant.CalcMassMatrix(ctx), rhs)
        return ((jac @ plant.GetVelocities(ctx)).tolist(), (jac @ solved[:, 0]).tolist(),
                (jac @ solved[:, 1:]).tolist())

    def _jacobian(self, body, point):
        plant, ctx = self.plant, self._context
        if body.index() == plant.world_body().index():
            return np.zeros((3, plant.num_velocities()))
        world = plant.world_frame()
        return plant.CalcJacobianTranslationalVelocity(
            ctx, JacobianWrtVariable.kV, body.body_frame(),
            plant.CalcPointsPositions(ctx, world, point, body.body_frame()), world, world)

class _Pair:
    """A coupled pair: its bodies (the sphere first), radii (m), ``NormalCoupling``, its sides'
    ``FreeBody`` constants (or ``WORLD``; None: the plant context serves it) and the slots of
    the forces on its moving sides."""

    __slots__ = ('sphere', 'other', 'r_s', 'r_o', 'coupling', 'sides', 'slots', 'c_s', 'c_o',
                 'plane')

    def __init__(self, sphere, other, r_s, r_o, coupling, sides, slots, c_s, c_o, plane):
        self.sphere, self.other, self.r_s, self.r_o = sphere, other, r_s, r_o
        self.coupling, self.sides, self.slots = coupling, sides, slots
        self.c_s, self.c_o, self.plane = c_s, c_o, plane




def _offset(centre):
    """A sphere's centre in its body's frame (m), or None where it is the body's origin."""
    return None if centre is None or not np.any(centre) else np.array(centre, dtype=float)
_ZERO = np.zeros(3)


def _moves(plant, body):
    """Whether a joint with a degree of freedom (a free body's floating one included) moves
    the body."""
    joints = [i for i in plant.GetJointIndices() if plant.get_joint(i).num_velocities() > 0]
    return bool(joints) and body.index() in set(plant.GetBodiesKinematicallyAffectedBy(joints))

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
evaluates, in a plant context of its own: the gap and normal from the bodies' poses, the contact
point's relative velocity and translational Jacobian (``CalcJacobianTranslationalVelocity``),
the effective mass along the normal (``CalcMassMatrix``), the rest of the system's normal
acceleration J M⁻¹ (τ_g − C v) (``CalcGravityGeneralizedForces``, ``CalcBiasTerm``; J̇v left
out), then ``NormalCoupling.step`` and friction, and outputs impulse / dt as an
``ExternallyAppliedSpatialForce`` on each body (at a sphere's centre with the torque of the
contact point's lever, at the contact point on a plane's body).

The discrete plant steps the velocities with the applied forces and then the positions with
the new velocities (``NormalCoupling``'s ``'semi_implicit'`` host): the output is computed once
per plant step, keyed on the context's time.  A continuous plant (``time_step`` = 0) is coupled
at the ``period`` given: a periodic update at each period's start plans the step (the
``'continuous'`` host), and the output is the force linear in time over the period that brings
the plant's gap and velocity to the exact ones at its end (exact for an integrator of order 3
or more on a free body; the tangential impulse is held constant; a sphere's force is applied at
its centre with its torque about it held in the world, so a ball turning over the step keeps
its lever).  Drake's own contact between
a pair's collision geometries is filtered out in the ``scene_graph`` given (refused without
it).  Units: SI.
"""
import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.geometry import CollisionFilterDeclaration, GeometrySet
from pydrake.multibody.math import SpatialForce
from pydrake.multibody.plant import ExternallyAppliedSpatialForce
from pydrake.multibody.tree import BodyIndex, JacobianWrtVariable
from pydrake.systems.framework import LeafSystem

from contact_sim.coupling.core import NormalCoupling
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
        self.pairs = [self._pair(row, i, scene_graph) for i, row in enumerate(rows)]
        self._leave_drakes_contact(scene_graph)
        self._memo = (None, [])
        self._far = set()           # the pairs out of reach at the last step
        self.DeclareVectorInputPort('plant_state', plant.num_multibody_states())
        self.DeclareAbstractOutputPort(
            'applied_spatial_force',
            lambda: AbstractValue.Make([ExternallyAppliedSpatialForce()]), self._output)
        if self.continuous:     # the plan of a step, made at its start: (t₀, rows)
            self._plan = self.DeclareAbstractState(AbstractValue.Make((0.0, [])))
            self.DeclarePeriodicUnrestrictedUpdateEvent(self.dt, 0.0, self._update)

    def _leave_drakes_contact(self, scene_graph):
        """Filter Drake's own contact between each pair's collision geometries out."""
        plant = self.plant
        if not plant.geometry_source_is_registered():
            return
        for index, (a, b, *_) in enumerate(self.pairs):
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
        """(sphere body, other body, sphere radius, other radius (0: a plane), NormalCoupling,
        sphere centre in its body's frame, other centre in its body's frame, the plane's (unit
        normal, height along it) in the world)."""
        if len(row) not in (3, 5):
            raise InputError('pairs', row, '{n[pairs]}[%d] = {value}: allowed (body, body, '
                             'Contact) or (body, body, Contact, radius, radius)' % index)
        a, b = self._body(row[0], index), self._body(row[1], index)
        contact = require_contact(row[2], 'pairs')
        world = self.plant.world_body().index()
        if len(row) == 3:           # the shapes from the scene graph
            shapes = [body_shape(self.plant, scene_graph, body, index, self.floor_height,
                                 None if _moves(self.plant, body) else
                                 self.plant.EvalBodyPoseInWorld(self._context, body))
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
        free = [body.index() != world and _moves(self.plant, body) for body in (a, b)]
        if not any(free):
            raise InputError('pairs', row[:2], '{n[pairs]}[%d]: neither body has a degree of '
                             'freedom: allowed a pair that can move' % index)
        if shapes[0][0] == 0.0:     # the sphere first
            a, b, shapes = b, a, shapes[::-1]
        (r_s, centre_s, _), (r_o, centre_o, plane) = shapes
        return a, b, r_s, r_o, NormalCoupling(
            contact, host='continuous' if self.continuous else 'semi_implicit'), \
            centre_s, centre_o, plane

    @property
    def impacts(self):
        """Every impact of every pair so far (``CoupledImpact``), in time order."""
        return sorted((i for p in self.pairs for i in p[4].impacts), key=lambda i: i.time)

    def _output(self, context, output):
        t = float(context.get_time())
        if self.continuous:     # the step's linear force at t
            t0, rows = context.get_abstract_state(0).get_value()
            late = t - t0 - 0.5 * self.dt
            output.set_value([_force(body, p, mean + late * rate, lever)
                              for body, p, lever, mean, rate in rows])
            return
        if self._memo[0] != t:
            state = self.get_input_port().Eval(context)
            self._memo = (t, [_force(body, p, mean, lever) for body, p, lever, mean, _
                              in self._forces(t, state)])
        output.set_value(self._memo[1])

    def _update(self, context, state):
        """A continuous plant's step starts: plan its forces from the plant's state."""
        t = float(context.get_time())
        rows = self._forces(t, self.get_input_port().Eval(context))
        state.get_mutable_abstract_state(0).set_value((t, rows))

    def _forces(self, t, state):
        """(body index, point of application in the body's frame, lever from it to the contact
        point in the world m (None: 0), mean force N, force rate N/s) rows of the step from t
        (s) at the plant's state."""
        plant, ctx, dt = self.plant, self._context, self.dt
        plant.SetPositionsAndVelocities(ctx, state)
        dynamics = None
        forces = []
        for index, (sphere, other, r_s, r_o, coupling, c_s, c_o, plane) in enumerate(self.pairs):
            centre = plant.EvalBodyPoseInWorld(ctx, sphere).multiply(c_s)
            if r_o == 0.0:              # a plane: (unit normal, height along it)
                normal = plane[0]
                gap = float(normal @ centre) - plane[1] - r_s
            else:
                d = centre - plant.EvalBodyPoseInWorld(ctx, other).multiply(c_o)
                dist = float(np.linalg.norm(d))
                normal = d / dist
                gap = dist - r_s - r_o
            if gap > self.reach and not coupling.carrying:
                self._far.add(index)
                continue                # out of reach: no dynamics evaluated
            if index in self._far and gap < 0.0:
                refuse_tunnel(index, gap, self.reach)
            self._far.discard(index)
            if dynamics is None:
                mass_matrix = plant.CalcMassMatrix(ctx)
                v = plant.GetVelocities(ctx)
                smooth = np.linalg.solve(mass_matrix, plant.CalcGravityGeneralizedForces(ctx)
                                         - plant.CalcBiasTerm(ctx))
                dynamics = True
            point = centre - r_s * normal
            jac = self._jacobian(sphere, point) - self._jacobian(other, point)
            inverse = jac @ np.linalg.solve(mass_matrix, jac.T)
            w_n = float(normal @ inverse @ normal)
            velocity, acceleration = jac @ v, jac @ smooth
            step = coupling.step(t, float(gap), float(normal @ velocity), 1.0 / w_n,
                                 float(normal @ acceleration), dt)
            if step.impulse == 0.0:
                continue
            impulse = step.impulse * normal
            if self.friction > 0.0:     # Coulomb's, from the velocity without friction
                impulse = impulse + tangential_impulse(
                    step.impulse, velocity + dt * acceleration + inverse @ impulse, normal,
                    inverse, self.friction)
            rate = step.force_rate * normal
            for body, sign, own in ((sphere, 1.0, c_s), (other, -1.0, c_o)):
                if body.index() == plant.world_body().index():
                    continue
                pose = plant.EvalBodyPoseInWorld(ctx, body)
                if own is None:         # a plane's body: at the contact point
                    forces.append((int(body.index()), pose.inverse().multiply(point), None,
                                   sign * impulse / dt, sign * rate))
                else:   # at the sphere's centre, the lever to the contact point fixed in the
                    # world: a continuous plant's sphere turning over the step keeps its torque
                    forces.append((int(body.index()), own, point - pose.multiply(own),
                                   sign * impulse / dt, sign * rate))
        return forces

    def _jacobian(self, body, point):
        plant, ctx = self.plant, self._context
        if body.index() == plant.world_body().index():
            return np.zeros((3, plant.num_velocities()))
        pose = plant.EvalBodyPoseInWorld(ctx, body)
        return plant.CalcJacobianTranslationalVelocity(
            ctx, JacobianWrtVariable.kV, body.body_frame(), pose.inverse().multiply(point),
            plant.world_frame(), plant.world_frame())


def _force(body_index, point, force, lever=None):
    """The ``ExternallyAppliedSpatialForce`` of ``force`` (N, world) at ``point`` (body frame),
    with the torque lever × force about it (``lever``: m, world; None: no torque)."""
    out = ExternallyAppliedSpatialForce()
    out.body_index, out.p_BoBq_B = BodyIndex(body_index), point
    if lever is None:
        torque = np.zeros(3)
    else:       # plain arithmetic: numpy's cross costs tens of µs a call
        (x, y, z), (fx, fy, fz) = lever, force
        torque = np.array([y * fz - z * fy, z * fx - x * fz, x * fy - y * fx])
    out.F_Bq_W = SpatialForce(torque, force)
    return out


def _moves(plant, body):
    """Whether a joint with a degree of freedom (a free body's floating one included) moves
    the body."""
    joints = [i for i in plant.GetJointIndices() if plant.get_joint(i).num_velocities() > 0]
    return bool(joints) and body.index() in set(plant.GetBodiesKinematicallyAffectedBy(joints))

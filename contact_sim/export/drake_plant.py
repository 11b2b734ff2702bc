"""Drake run: a free sphere thrown at a half-space in pydrake's MultibodyPlant with point contact,
gravity off, at each speed: the e(v), contact duration and peak force Drake really gives.

Both geometries carry ``drake:point_contact_stiffness`` 2k and ``drake:hunt_crossley_dissipation``
d: Drake combines them in series, k = k1 k2 / (k1 + k2), and d = (k2 d1 + k1 d2) / (k1 + k2)
(``GetCombinedPointContactStiffness`` and ``GetCombinedHuntCrossleyDissipation`` in
multibody/plant/contact_properties.cc), so the pair gets k and d.  ``time_step`` 0 is the
continuous plant (Drake's default error-controlled integrator at accuracy 1e-8), otherwise the
discrete plant with Drake's default ``discrete_contact_approximation``, ``lagged``."""
import logging
import math

import numpy as np

DISCRETE_APPROXIMATION = 'lagged'   # Drake's default MultibodyPlantConfig
ACCURACY = 1e-8                     # the continuous plant's integrator target accuracy
CHUNKS_PER_CONTACT = 50             # continuous plant: the state is looked at this often
PHASES = 4                          # discrete plant: start offsets within one step, averaged


def _pydrake():
    import pydrake.all   # optional: pip install 'contact_sim[drake]' (about 420 MB)
    return pydrake.all


def importable():
    """True when pydrake imports here (Drake's e(v) is then measured)."""
    try:
        _pydrake()
    except ImportError:
        return False
    return True


def pair_properties(stiffness, dissipation):
    """Each geometry's (point_contact_stiffness, hunt_crossley_dissipation) for the pair to have
    ``stiffness`` k (N/m) and ``dissipation`` d (s/m) when both carry the same: (2k, d)."""
    return 2.0 * stiffness, dissipation


def ball_properties(stiffness, dissipation, ground_stiffness, ground_dissipation):
    """The ball's (point_contact_stiffness, hunt_crossley_dissipation) that give the pair k, d
    against a ground of its own ``ground_stiffness`` k2 > k (N/m) and ``ground_dissipation`` d2
    (s/m): Drake's series rule inverted, k1 = k k2 / (k2 - k), d1 = ((k1 + k2) d - k1 d2) / k2.

    Raises
    ------
    ValueError
        If k2 <= k (no ball stiffness gives the pair k) or d1 would be negative.
    """
    if ground_stiffness <= stiffness:
        raise ValueError(f'the ground stiffness {ground_stiffness:g} N/m must exceed the pair\'s '
                         f'{stiffness:g} N/m')
    k1 = stiffness * ground_stiffness / (ground_stiffness - stiffness)
    d1 = ((k1 + ground_stiffness) * dissipation - k1 * ground_dissipation) / ground_stiffness
    if d1 < 0.0:
        raise ValueError(f'the ground dissipation {ground_dissipation:g} s/m is too large for '
                         f'the pair\'s {dissipation:g} s/m')
    return k1, d1


def build(radius, mass, stiffness, dissipation, time_step, gravity=0.0):
    """(diagram, plant, ball body) of the throw: the ball over a half-space at z = 0, with
    ``gravity`` (m/s^2, default 0)."""
    d = _pydrake()
    builder = d.DiagramBuilder()
    config = d.MultibodyPlantConfig(time_step=time_step, contact_model='point',
                                    discrete_contact_approximation=DISCRETE_APPROXIMATION)
    plant, _ = d.AddMultibodyPlant(config, builder)
    ball = plant.AddRigidBody('ball', d.SpatialInertia.SolidSphereWithMass(mass, radius))
    k, dissipation = pair_properties(stiffness, dissipation)
    for body, shape, name in ((ball, d.Sphere(radius), 'ball'),
                              (plant.world_body(), d.HalfSpace(), 'ground')):
        properties = d.ProximityProperties()
        d.AddContactMaterial(dissipation=dissipation, point_stiffness=k,
                             friction=d.CoulombFriction(0.0, 0.0), properties=properties)
        plant.RegisterCollisionGeometry(body, d.RigidTransform(), shape, name, properties)
    plant.mutable_gravity_field().set_gravity_vector([0.0, 0.0, -gravity])
    plant.Finalize()
    return builder.Build(), plant, ball


def throw(system, radius, speed, gap, chunk, gravity=0.0, patience=1_000_000):
    """(e, contact duration in s, peak normal force in N) of one throw at ``speed`` (m/s) from
    ``gap`` (m) above the half-space, the state looked at every ``chunk`` (s): the duration
    counts the chunks that end with a contact force > 0.  With ``gravity`` (m/s^2), e is the
    separation speed over the impact speed at the plate (the free flight taken out), 0 if the
    ball has not left the plate ``patience`` chunks after it touched."""
    d = _pydrake()
    diagram, plant, ball = system
    simulator = d.Simulator(diagram)
    context = plant.GetMyMutableContextFromRoot(simulator.get_mutable_context())
    plant.SetFreeBodyPose(context, ball, d.RigidTransform([0.0, 0.0, radius + gap]))
    plant.SetFreeBodySpatialVelocity(context=context, body=ball,
                                     V_JpJc=d.SpatialVelocity([0.0] * 3, [0.0, 0.0, -speed]))
    if plant.time_step() == 0.0:
        simulator.get_mutable_integrator().set_target_accuracy(ACCURACY)
    simulator.Initialize()
    results = plant.get_contact_results_output_port()
    touching, peak, t, touched = 0, 0.0, 0.0, None
    impact = math.sqrt(speed * speed + 2.0 * gravity * gap)
    for step in range(10_000_000):
        t += chunk
        simulator.AdvanceTo(t)
        contacts = results.Eval(context)
        force = 0.0
        if contacts.num_point_pair_contacts():
            force = abs(float(contacts.point_pair_contact_info(0).contact_force()[2]))
            if force > 0.0:
                touching, peak = touching + 1, max(peak, force)
                touched = step if touched is None else touched
        z, vz = plant.GetPositions(context)[6], plant.GetVelocities(context)[5]
        if gravity == 0.0 and vz > 0.0 and z > radius + gap:
            return vz / speed, touching * chunk, peak
        if touched is not None and vz > 0.0 and z >= radius and force <= 0.0:   # lift-off
            rebound = math.sqrt(vz * vz + 2.0 * gravity * (z - radius))
            return rebound / impact, touching * chunk, peak
        if touched is not None and step - touched > patience:   # it stays on the plate
            return 0.0, touching * chunk, peak
    raise ArithmeticError(f'Drake did not rebound at {speed:g} m/s')   # never in tests


def measure(radius, mass, speeds, stiffness, dissipation, time_step, gravity=0.0,
            per_phase=False):
    """Drake's (e, duration, peak force) at each of ``speeds`` (m/s), an array (n, 3): the mean
    over ``PHASES`` start offsets within a step for the discrete plant, one throw for the
    continuous plant (``time_step`` 0); with ``gravity`` (m/s^2) as ``throw`` says; each
    throw, (n, PHASES or 1, 3), with ``per_phase``."""
    logger = logging.getLogger('drake')   # quiet the half-space's notice on deformable contact
    level = logger.level
    logger.setLevel(logging.ERROR)
    try:
        system = build(radius, mass, stiffness, dissipation, time_step, gravity)
        period = 2.0 * math.pi / math.sqrt(stiffness / mass)
        if time_step == 0.0:
            chunk = period / 2.0 / CHUNKS_PER_CONTACT
            rows = np.array([[throw(system, radius, v, 2.0 * chunk * v, chunk, gravity,
                                    int(50 * period / chunk))] for v in speeds])
        else:
            offsets = (np.arange(PHASES) + 0.5) / PHASES
            patience = int(50 * period / time_step) + 10
            rows = np.array([[throw(system, radius, v, f * v * time_step, time_step, gravity,
                                    patience) for f in offsets] for v in speeds])
        return rows if per_phase else rows.mean(axis=1)
    finally:
        logger.setLevel(level)


def version():
    """The installed Drake's version, or 'not installed'."""
    from importlib import metadata
    try:
        return metadata.version('drake')
    except metadata.PackageNotFoundError:
        return 'not installed'

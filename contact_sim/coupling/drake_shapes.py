"""The shapes of a Drake pair's bodies, read once from the scene graph for
``contact_sim.coupling.drake.CoupledContacts``: a body's one collision geometry, a ``Sphere``
(its radius and its centre in the body's frame, ``SceneGraphInspector.GetPoseInFrame``) or, on
the world or a body welded to it (an SDF's static ground), a ``HalfSpace`` (its outward unit
normal, the +z of its frame, and its height along that normal in the world: the boundary passes
through its frame's origin); the world with no collision geometry is the floor z =
``floor_height``.  Units: SI.
"""
import numpy as np
from pydrake.geometry import HalfSpace, Sphere

from contact_sim.validation import InputError

# the world's floor without geometry: the plane z = floor_height, normal +z
UP = np.array([0.0, 0.0, 1.0])

ALLOWED = ('allowed one collision geometry on a body: a Sphere, or on the world or a body '
           'welded to it a HalfSpace, or none on the world (the floor z = floor_height)')


def body_shape(plant, scene_graph, body, index, floor_height, fixed_pose):
    """The shape of ``body`` in pair ``index``: (radius m, centre in the body's frame m (3,),
    None) for a sphere, or (0.0, None, (unit normal (3,), height m)) for a half-space or the
    world's floor, normal and height in the world; ``fixed_pose`` is the body's pose in the
    world (``RigidTransform``) when no joint moves it, else None.

    Raises
    ------
    InputError
        Keyed ``pairs`` (no collision geometry on a body other than the world, several, a
        shape that is not a Sphere or, on a body that does not move, a HalfSpace) or ``scene_graph`` (missing or not the plant's,
        when a shape must be read).
    """
    world = body.index() == plant.world_body().index()
    ids = plant.GetCollisionGeometriesForBody(body)
    if not ids and world:
        return 0.0, None, (UP, float(floor_height))
    if len(ids) != 1:
        raise InputError('pairs', body.name(), '{n[pairs]}[%d]: body {value} has %d collision '
                         'geometries: %s; or radii given as (body, body, Contact, radius, '
                         'radius)' % (index, len(ids), ALLOWED))
    shape, pose = _shape(plant, scene_graph, ids[0], body, index)
    if isinstance(shape, Sphere) and shape.radius() > 0.0:
        return float(shape.radius()), np.array(pose.translation(), dtype=float), None
    if isinstance(shape, HalfSpace) and fixed_pose is not None:
        pose = fixed_pose.multiply(pose)
        normal = np.array(pose.rotation().matrix()[:, 2], dtype=float)
        return 0.0, None, (normal, float(normal @ pose.translation()))
    raise InputError('pairs', body.name(), '{n[pairs]}[%d]: body {value} has a %s: %s'
                     % (index, type(shape).__name__, ALLOWED))


def _shape(plant, scene_graph, geometry, body, index):
    """The shape of ``geometry`` and its pose in its body's frame, from ``scene_graph``."""
    if scene_graph is None:
        raise InputError('scene_graph', None, "{n[scene_graph]} is missing: pairs[%d]'s body %r "
                         'has collision geometry whose shape is in the scene graph: allowed the '
                         "plant's SceneGraph (of AddMultibodyPlantSceneGraph), or radii given as "
                         '(body, body, Contact, radius, radius)' % (index, body.name()))
    inspector = getattr(scene_graph, 'model_inspector', None)
    inspector = inspector() if callable(inspector) else None
    if inspector is None or not inspector.SourceIsRegistered(plant.get_source_id()):
        raise InputError('scene_graph', scene_graph, '{n[scene_graph]} = {value} is not the '
                         "plant's scene graph: allowed the SceneGraph the plant is registered "
                         'with (AddMultibodyPlantSceneGraph)')
    return inspector.GetShape(geometry), inspector.GetPoseInFrame(geometry)

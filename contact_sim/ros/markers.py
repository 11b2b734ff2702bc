"""``~/markers``: what RViz or Foxglove draws of the simulation (visualization_msgs/MarkerArray),
built from one tick's state.

Three markers in the node's ``frame_id`` (REP 103: z up, the plate's surface at rest at z = 0),
namespace ``contact_sim``, each replaced in place at every message (``Marker.ADD`` with a fixed
id, no lifetime):

* id 0, the sphere: a ``SPHERE`` of diameter 2 R1 centred at its height (p + R1 - z);
* id 1, the plate: a thin ``CUBE`` (``PLATE_SIZE`` wide, ``PLATE_THICKNESS`` thick) whose top is
  the plate's surface p, or for a second sphere (``plate_radius`` R2 > 0) a ``SPHERE`` of
  diameter 2 R2 whose top is at p;
* id 2, the contact force on the sphere: an ``ARROW`` from the contact point (z = p) up, of length
  ``FORCE_SCALE`` R1 per body weight (R1 F / (m g)): one radius when resting, zero in flight.
"""
import math

from geometry_msgs.msg import Point
from std_msgs.msg import ColorRGBA
from visualization_msgs.msg import Marker, MarkerArray

from .messages import time_msg

NAMESPACE = 'contact_sim'
PLATE_SIZE = 0.2         # m: the flat plate's side
PLATE_THICKNESS = 0.005  # m
FORCE_SCALE = 1.0        # sphere radii of arrow per body weight (m g) of force
SPHERE, PLATE, FORCE = 0, 1, 2   # the markers' ids
_GREY = ColorRGBA(r=0.7, g=0.7, b=0.75, a=1.0)
_DARK = ColorRGBA(r=0.3, g=0.3, b=0.35, a=1.0)
_RED = ColorRGBA(r=0.9, g=0.1, b=0.1, a=1.0)


def force_length(force, radius, weight):
    """m: the arrow's length for a contact force ``force`` (N) on a sphere of radius ``radius``
    (m) and weight ``weight`` (N, m g > 0): ``FORCE_SCALE`` radius force / weight (0 for F <= 0
    or no gravity).

    Examples
    --------
    >>> force_length(2.0, 0.01, 0.5)
    0.04
    """
    if not force > 0.0 or not weight > 0.0:
        return 0.0
    return FORCE_SCALE * radius * force / weight


def _marker(kind, ident, stamp, frame_id, colour):
    marker = Marker()
    marker.header.stamp = stamp
    marker.header.frame_id = frame_id
    marker.ns = NAMESPACE
    marker.id = ident
    marker.type = kind
    marker.action = Marker.ADD
    marker.pose.orientation.w = 1.0
    marker.color = colour
    return marker


def markers_msg(ns, frame_id, radius, height, plate_position, plate_radius, force, weight):
    """The MarkerArray of one tick.

    Parameters
    ----------
    ns : int
        Stamp, ns of simulated time.
    frame_id : str
        The plate frame.
    radius : float
        m: the sphere's radius R1.
    height : float
        m: the sphere centre's height (p + R1 - z).
    plate_position : float
        m: the plate's surface p.
    plate_radius : float
        m: R2 of a second sphere, inf for the flat plate.
    force : float
        N: the contact force on the sphere (>= 0).
    weight : float
        N: m g, the force scale of the arrow.

    Returns
    -------
    visualization_msgs.msg.MarkerArray
        The sphere, the plate and the force arrow (ids ``SPHERE``, ``PLATE``, ``FORCE``).

    Examples
    --------
    >>> array = markers_msg(10**9, 'plate', 0.01, 0.5, 0.0, math.inf, 1.0, 0.5)
    >>> [m.id for m in array.markers], array.markers[0].pose.position.z
    ([0, 1, 2], 0.5)
    """
    stamp = time_msg(ns)
    sphere = _marker(Marker.SPHERE, SPHERE, stamp, frame_id, _GREY)
    sphere.pose.position.z = float(height)
    sphere.scale.x = sphere.scale.y = sphere.scale.z = 2.0 * radius
    if math.isinf(plate_radius):
        plate = _marker(Marker.CUBE, PLATE, stamp, frame_id, _DARK)
        plate.pose.position.z = float(plate_position) - 0.5 * PLATE_THICKNESS
        plate.scale.x = plate.scale.y = PLATE_SIZE
        plate.scale.z = PLATE_THICKNESS
    else:
        plate = _marker(Marker.SPHERE, PLATE, stamp, frame_id, _DARK)
        plate.pose.position.z = float(plate_position) - plate_radius
        plate.scale.x = plate.scale.y = plate.scale.z = 2.0 * plate_radius
    arrow = _marker(Marker.ARROW, FORCE, stamp, frame_id, _RED)
    base = float(plate_position)
    arrow.points = [Point(z=base), Point(z=base + force_length(force, radius, weight))]
    arrow.scale.x = 0.2 * radius    # shaft diameter
    arrow.scale.y = 0.4 * radius    # head diameter
    arrow.scale.z = 0.0             # head length: RViz's default (a fraction of the length)
    return MarkerArray(markers=[sphere, plate, arrow])

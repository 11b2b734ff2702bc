"""``~/markers`` with real ROS: the package's node (``sim``, real time) in its own process, a
MarkerArray subscriber in this one. The sphere, the plate and the contact force as an arrow, in
the node's frame_id, finite, the arrow's length proportional to the force published on ~/wrench
at the same stamp.
"""
import math

import pytest

import rclpy  # noqa: E402,F401  (pinned: a missing install fails here)

from contact_sim.ros import markers as cs_markers  # noqa: E402
from contact_sim.ros import messages as cs_msgs  # noqa: E402
from visualization_msgs.msg import Marker, MarkerArray  # noqa: E402
from .harness import (  # noqa: E402
    DEEP, NODE, PROGRESS_TIMEOUT, SIM_TICK_NS, default_contact_and_mass, reset, stamp_ns)

RADIUS = 0.0127   # m: the default sphere


def test_markers_topic_is_registered_with_the_other_topics():
    assert [t.name for t in cs_msgs.VIEW_TOPICS] == ['~/markers', '/diagnostics']
    assert {t.name for t in cs_msgs.VIEW_TOPICS}.isdisjoint(t.name for t in cs_msgs.TOPICS)


def test_force_length_is_proportional_and_zero_without_force():
    one = cs_markers.force_length(1.0, RADIUS, 0.5)
    assert cs_markers.force_length(3.0, RADIUS, 0.5) == pytest.approx(3.0 * one)
    assert cs_markers.force_length(0.5, RADIUS, 0.5) == pytest.approx(RADIUS)   # F = m g
    assert cs_markers.force_length(0.0, RADIUS, 0.5) == 0.0
    assert cs_markers.force_length(math.nan, RADIUS, 0.5) == 0.0


def test_markers_show_the_sphere_plate_and_force_in_the_frame(sim, client):
    arrays = []
    client.node.create_subscription(MarkerArray, f'{NODE}/markers', arrays.append, DEEP)
    start = reset(client)   # a bounce, then the settling and the rest: forces 0 to above m g
    client.spin_until(lambda: any(stamp_ns(a.markers[0].header.stamp) > start + 4_000_000_000
                                  for a in arrays), '4 simulated s of markers after a reset',
                      PROGRESS_TIMEOUT)
    wrenches = client.messages[f'{NODE}/wrench']
    client.spin_until(lambda: stamp_ns(wrenches[-1].header.stamp) > start + 4_000_000_000,
                      '~/wrench to 4 simulated s after the reset', PROGRESS_TIMEOUT)
    _, mass = default_contact_and_mass()
    weight = mass * 9.81
    wrench = {stamp_ns(m.header.stamp): m.wrench.force.z for m in wrenches}
    compared, forces = 0, set()
    for array in arrays:
        sphere, plate, arrow = array.markers
        assert [m.id for m in array.markers] == [cs_markers.SPHERE, cs_markers.PLATE,
                                                 cs_markers.FORCE]
        assert (sphere.type, plate.type, arrow.type) == (Marker.SPHERE, Marker.CUBE, Marker.ARROW)
        assert {m.header.frame_id for m in array.markers} == {'plate'}
        assert len({stamp_ns(m.header.stamp) for m in array.markers}) == 1
        values = [sphere.pose.position.z, plate.pose.position.z, sphere.scale.x,
                  *(c for p in arrow.points for c in (p.x, p.y, p.z))]
        assert all(math.isfinite(v) for v in values)
        assert sphere.scale.x == pytest.approx(2 * RADIUS)
        assert sphere.pose.position.z > -RADIUS     # above the plate (within a deformation)
        assert arrow.points[0].z == pytest.approx(plate.pose.position.z
                                                  + 0.5 * cs_markers.PLATE_THICKNESS)
        length = arrow.points[1].z - arrow.points[0].z
        ns = stamp_ns(arrow.header.stamp)
        if ns in wrench:    # the tick's end is a ~/wrench sample of the same stamp
            force = wrench[ns]
            assert length == pytest.approx(RADIUS * force / weight, rel=1e-9, abs=1e-12)
            compared += 1
            forces.add(round(force / weight, 3))
    # a quarter of the window's ticks at least (4 s: 100 ticks of the shared node's 25 Hz; the
    # client lags, and a marker array whose tick end it has not got yet is not compared)
    assert compared >= 4_000_000_000 // SIM_TICK_NS // 4
    assert 0.0 in forces and 1.0 in forces   # flight (no force) and rest (F = m g) both seen

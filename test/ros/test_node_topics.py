"""The node's topics and services with real ROS: ``contact_sim_node`` runs as its own process
(the package's ``sim`` fixture, one node for all of ``test/ros/``), started through its console
entry point, and this test process talks to it through a separate rclpy client node. Tests that
change the node put it back.
"""
import math

import numpy as np
import pytest

import rclpy  # noqa: E402,F401  (pinned: a missing install fails here)

import contact_sim as cs  # noqa: E402
from contact_sim.ros import messages as cs_msgs  # noqa: E402
from rcl_interfaces.msg import Log, ParameterType  # noqa: E402
from .harness import (  # noqa: E402
    PROGRESS_TIMEOUT, NODE, SIM_TICK_NS, TOPICS, TYPE_NAMES, stamp_ns, stamp_s, impacts_after,
    default_contact_and_mass, reset)


def test_topics_and_services_have_the_declared_types(sim, client):
    def graph():
        return dict(client.node.get_topic_names_and_types())
    client.spin_until(lambda: all(t in graph() for t in TOPICS), 'all topics in the graph')
    topics = graph()
    for topic, type_name in TYPE_NAMES.items():
        assert topics[topic] == [type_name], topic
    services = dict(client.node.get_service_names_and_types())
    assert services[f'{NODE}/query_restitution'] == ['rcl_interfaces/srv/GetParameters']
    assert services[f'{NODE}/reset'] == ['std_srvs/srv/Trigger']


def test_stamps_are_simulated_time_monotonic_and_framed(sim, client):
    start = {topic: client.count(topic) for topic in TOPICS}
    client.spin_until(lambda: client.count(f'{NODE}/pose') >= start[f'{NODE}/pose'] + 100,
                      '100 more poses')
    for topic in TOPICS:
        new = client.messages[topic][start[topic]:]
        if topic.endswith('impact'):
            times = [m.data[0] for m in new]
            assert all(np.isfinite(m.data).all() or m.data[4] == math.inf for m in new)
        elif topic == '/clock':
            times = [stamp_ns(m.clock) for m in new]
        else:
            times = [stamp_ns(m.header.stamp) for m in new]
            assert {m.header.frame_id for m in new} == {'plate'}, topic
        assert all(b > a for a, b in zip(times, times[1:])), f'{topic} stamps not increasing'
    poses = client.messages[f'{NODE}/pose'][start[f'{NODE}/pose']:]
    # /clock = pose stamps: the client takes each topic in its own turn, so /clock may be some
    # messages behind ~/pose; wait until it has reached the last pose taken
    last = stamp_ns(poses[-1].header.stamp)
    client.spin_until(lambda: stamp_ns(client.messages['/clock'][-1].clock) >= last,
                      f'/clock to reach the last pose, {last * 1e-9:.3f} s')
    clocks = {stamp_ns(m.clock) for m in client.messages['/clock']}
    assert {stamp_ns(p.header.stamp) for p in poses} <= clocks
    for p in poses:
        assert math.isfinite(p.pose.position.z) and p.pose.orientation.w == 1.0


def test_reset_restarts_the_drop_and_time_keeps_running(sim, client):
    before = client.clock_seconds()
    t0 = reset(client)
    assert t0 >= cs_msgs.to_ns(before)
    client.spin_until(lambda: impacts_after(client, t0), 'the first impact after the reset')
    first = impacts_after(client, t0)[0]
    # released from rest 1 m above the plate: touches after sqrt(2 h / g) at sqrt(2 g h)
    assert first['time'] - t0 * 1e-9 == pytest.approx(math.sqrt(2 * 1.0 / 9.81), abs=1e-6)
    assert first['impact_speed'] == pytest.approx(math.sqrt(2 * 9.81 * 1.0), rel=1e-9)
    touch = cs_msgs.to_ns(first['time'])

    def falling(topic):
        return [m for m in client.messages[f'{NODE}/{topic}']
                if t0 < stamp_ns(m.header.stamp) < touch]
    # the topics are read in no common order: the poses of the fall are all in once one after
    # the touch is (the first impact can be read before a backlog of poses on a loaded machine)
    for topic in ('pose', 'twist'):
        client.spin_until(lambda: stamp_ns(client.messages[f'{NODE}/{topic}'][-1].header.stamp)
                          >= touch, f'~/{topic} past the touch')
    # every tick of the fall (40 ms apart: 11) is published, unless the node could not hold
    # real time on a loaded machine and skipped ahead, which it says in its log
    if len(falling('pose')) < (touch - t0 - 1) // SIM_TICK_NS:
        client.spin_until(lambda: 'cannot be held' in sim.output(),
                          f'the node to log that real time cannot be held '
                          f'({len(falling("pose"))} poses of the fall)')
    for p in falling('pose'):  # centre height R + h - g t^2 / 2 while falling
        t = (stamp_ns(p.header.stamp) - t0) * 1e-9
        assert p.pose.position.z == pytest.approx(0.0127 + 1.0 - 9.81 * t * t / 2, abs=1e-9)
    for m in falling('twist'):
        t = (stamp_ns(m.header.stamp) - t0) * 1e-9
        assert m.twist.linear.z == pytest.approx(-9.81 * t, abs=1e-9)  # up is +z


def test_wrench_shows_every_impact_with_its_peak(sim, client):
    t0 = reset(client)
    client.spin_until(lambda: len(impacts_after(client, t0)) >= 6, 'six impacts', PROGRESS_TIMEOUT)
    impacts = impacts_after(client, t0)
    last_end = impacts[-1]['time'] + impacts[-1]['contact_duration']
    for topic in (f'{NODE}/wrench', f'{NODE}/contact'):
        client.spin_until(lambda: stamp_s(client.messages[topic][-1].header.stamp) > last_end,
                          f'the {topic} samples of the last impact')
    # strictly after t0: the sample stamped t0 may be the end of the previous drop's last tick
    # (the ball at rest, F = m g = 0.66 N), published before the reset (a fresh-clone CI run)
    samples = [(stamp_ns(m.header.stamp), m.wrench.force.z) for m in
               client.messages[f'{NODE}/wrench'] if stamp_ns(m.header.stamp) > t0]
    stamps = np.array([s for s, _ in samples])
    forces = np.array([f for _, f in samples])
    assert np.all(forces >= 0.0) and np.all(np.isfinite(forces))
    covered = np.zeros(len(samples), dtype=bool)
    for i, impact in enumerate(impacts):
        lo = cs_msgs.to_ns(impact['time']) - 2
        hi = cs_msgs.to_ns(impact['time'] + impact['contact_duration']) + 2
        inside = (stamps >= lo) & (stamps <= hi)
        covered |= inside
        assert inside.sum() >= 5, f'impact {i}: only {inside.sum()} wrench samples'
        assert forces[inside].max() == pytest.approx(impact['peak_force'], rel=1e-9), \
            f'impact {i}: the wrench misses the peak'
        assert impact['restitution'] == pytest.approx(
            impact['rebound_speed'] / impact['impact_speed'], rel=1e-12)
        assert 0.0 < impact['restitution'] < 1.0
        assert 2e-5 < impact['contact_duration'] < 1e-3  # steel on iron: about 0.1 ms
    # no force outside the reported contacts, up to the end of the last one
    before_end = stamps <= cs_msgs.to_ns(last_end) + 2
    assert not np.any((forces > 0.0) & ~covered & before_end)
    # the speeds chain: a bounce starts at about the previous rebound speed, never faster (the
    # sphere lifts off slightly inside the undeformed surface and climbs out against gravity)
    for a, b in zip(impacts, impacts[1:]):
        assert b['impact_speed'] <= a['rebound_speed']
        assert b['impact_speed'] == pytest.approx(a['rebound_speed'], rel=1e-3)
    # the contact state follows the wrench: same stamps, in contact exactly while F > 0
    contact = {stamp_ns(m.header.stamp): m.vector for m in client.messages[f'{NODE}/contact']
               if stamp_ns(m.header.stamp) >= t0}
    for ns, force in samples:
        if ns <= cs_msgs.to_ns(last_end):
            assert contact[ns].z == (1.0 if force > 0 else 0.0)


def test_every_tick_is_published_on_the_real_time_factors_grid(sim, client):
    """In real time ticks are real_time_factor/publish_rate s of simulated time apart, and every
    tick reaches every state topic (the node skips ticks only when real time cannot be held, and
    then says so in its log). (As fast as possible, ticks are 1/publish_rate s apart: the
    recorded flat-out test checks every sample of every topic; this module's Python client is
    too slow a reader for a flat-out run.)"""
    pose = f'{NODE}/pose'
    factor = 2.0
    step_ns = int(factor * SIM_TICK_NS)
    try:
        (result,) = client.set_parameters(NODE, real_time_factor=factor)
        assert result.successful, result.reason
        t0 = reset(client)   # the new grid starts here
        start = client.count(pose)

        def after_reset():
            return np.array([ns for ns in (stamp_ns(m.header.stamp)
                                           for m in client.messages[pose][start:]) if ns > t0])
        # in simulated time: 100 ticks of the grid (8 s, 4 s of wall time at factor 2), however
        # many of them a loaded machine let the node publish
        client.spin_until(lambda: len(after_reset()) > 0
                          and after_reset()[-1] >= t0 + 100 * step_ns,
                          '8 s of simulated time after the reset', PROGRESS_TIMEOUT)
        after = after_reset()
        assert np.all((after - t0) % step_ns == 0)  # on the grid
        if np.any(np.diff(after) != step_ns):       # ticks left out: real time was not held,
            client.spin_until(lambda: 'cannot be held' in sim.output(),   # and the node says so
                              'the node to log that real time cannot be held')
        for topic in (f'{NODE}/twist', '/clock'):
            def stamps_of(topic=topic):
                return {stamp_ns(m.clock if topic == '/clock' else m.header.stamp)
                        for m in client.messages[topic]}
            client.spin_until(lambda: max(stamps_of() | {0}) >= after[-1], f'{topic}',
                              PROGRESS_TIMEOUT)
            assert set(after.tolist()) <= stamps_of(), topic  # every tick on every topic
        assert client.query(['1'])[0].type == ParameterType.PARAMETER_DOUBLE  # serving
    finally:
        (result,) = client.set_parameters(NODE, real_time_factor=1.0)
        assert result.successful, result.reason


def test_query_restitution_answers_a_batch_with_bad_names(sim, client):
    contact, mass = default_contact_and_mass()
    good = {'2.5': ('restitution', 2.5), 'restitution:0.5': ('restitution', 0.5),
            'contact_duration:1': ('contact_duration', 1.0), 'peak_force:1': ('peak_force', 1.0),
            'max_penetration:1': ('max_penetration', 1.0), ' 1e-2 ': ('restitution', 0.01)}
    bad = ['abc', '-1', '0', 'inf', 'nan', 'speed:1', 'restitution:', '', ':2']
    names = ['2.5', 'abc', 'restitution:0.5', '-1', 'contact_duration:1', '0', 'inf',
             'peak_force:1', 'nan', 'speed:1', 'max_penetration:1', 'restitution:', '', ':2',
             ' 1e-2 ']
    values = client.query(names)
    assert len(values) == len(names)
    for name, value in zip(names, values):
        if name in bad:
            assert value.type == ParameterType.PARAMETER_NOT_SET, name
            continue
        assert value.type == ParameterType.PARAMETER_DOUBLE, name
        quantity, speed = good[name]
        exact = getattr(cs.simulate_impact(contact, mass, speed), quantity)
        assert value.double_value == pytest.approx(exact, rel=1e-6), name
    # one warning per bad name, naming it, in the node's log (/rosout)
    def warned(name):
        return any(m.level == Log.WARN and m.name == 'contact_sim' and repr(name) in m.msg
                   for m in client.rosout)
    client.spin_until(lambda: all(warned(n) for n in bad), 'a warning for each bad name')
    assert not any(warned(n) for n in good)
    assert client.query([]) == []

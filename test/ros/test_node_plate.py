"""The node's plate with real ROS: the vibrating table (parameters) and ~/plate_command.
"""
import math
import time

import pytest
import yaml

import rclpy  # noqa: E402,F401  (pinned: a missing install fails here)

from .harness import (  # noqa: E402
    PROGRESS_TIMEOUT, NODE, stamp_ns, reset, PLATE_COMMAND_YAML, fill_message, rosout_has)


def _by_stamp(client, key, value, first=None):
    """{stamp (ns): value(message)} of ``key``'s messages from index ``first[key]`` on (those
    received since a test's start: a check over every message of the package would cost the
    client more than taking them)."""
    messages = client.messages[f'{NODE}/{key}'][(first or {}).get(key, 0):]
    return {stamp_ns(m.header.stamp): value(m) for m in messages}


def test_the_vibrating_table_moves_the_plate_at_once_and_stops(sim, client):
    # Gamma = 0.4: the resting ball is carried (a bouncing one would flood this Python client
    # with contact samples on a loaded machine)
    a, f = 0.001, 10.0
    plate_pose = f'{NODE}/plate_pose'
    try:
        (result,) = client.set_parameters(NODE, initial_height=0.0)   # the ball at rest
        assert result.successful, result.reason
        reset(client)
        first = {key: client.count(f'{NODE}/{key}') for key in (
            'pose', 'twist', 'plate_pose', 'plate_twist', 'wrench', 'plate_wrench')}
        (result,) = client.set_parameters(NODE, atomically=True, plate_amplitude=a,
                                          plate_frequency=f)
        assert result.successful, result.reason
        start = client.count(plate_pose)

        def moved():   # stamps (ns) of the poses off p = 0 since the reply
            return sorted(stamp_ns(m.header.stamp) for m in client.messages[plate_pose][start:]
                          if m.pose.position.z != 0.0)
        # the change's first tick: the first pose off p = 0 from there on (the plate rests at
        # exactly 0 before it; poses published before the change may still arrive after the
        # reply on a loaded machine, so the count alone can be early); then, counted in poses
        # after the bridge (one period, 0.1 s), however many ticks a loaded machine skipped
        client.spin_until(lambda: len(moved()) > 0 and sum(
            ns >= moved()[0] + 150_000_000 for ns in moved()) > 45,
            '45 plate poses after the bridge', PROGRESS_TIMEOUT)
        since = moved()[0]
        last = stamp_ns(client.messages[plate_pose][-1].header.stamp)
        for key in ('pose', 'twist', 'plate_twist'):     # the state topics: one per tick
            client.spin_until(lambda key=key: max(_by_stamp(client, key, lambda m: 0, first),
                                                  default=-1) >= last,
                              f'~/{key} up to the last plate pose', PROGRESS_TIMEOUT)
        # after the bridge (one period, 0.1 s): the table's motion
        bridged = since + 150_000_000
        plate = {ns: z for ns, z in _by_stamp(client, 'plate_pose',
                                              lambda m: m.pose.position.z, first).items()
                 if bridged <= ns <= last}
        plate_v = {ns: v for ns, v in _by_stamp(client, 'plate_twist',
                                                lambda m: m.twist.linear.z, first).items()
                   if bridged <= ns <= last}
        zs, vs = list(plate.values()), list(plate_v.values())
        assert len(zs) > 40 and len(vs) > 40
        assert max(zs) > 0.5 * a and min(zs) < -0.5 * a
        assert max(map(abs, zs)) <= a * (1 + 1e-9)
        assert max(map(abs, vs)) <= a * 2 * math.pi * f * (1 + 1e-9)
        # ~/pose and ~/twist are absolute, p + R1 - z and pdot - zdot: the carried ball moves
        # with the plate (z ~ 1.5e-7 m, its rate ~ 1e-6 m/s), 1 mm up and down
        pose = _by_stamp(client, 'pose', lambda m: m.pose.position.z, first)
        twist = _by_stamp(client, 'twist', lambda m: m.twist.linear.z, first)
        assert all(pose[ns] == pytest.approx(z + 0.0127, abs=1e-6) for ns, z in plate.items())
        assert all(twist[ns] == pytest.approx(v, abs=1e-4) for ns, v in plate_v.items())
        assert max(pose[ns] for ns in plate) - min(pose[ns] for ns in plate) > a

        # the reaction on the plate at every contact sample: -F (the sample topics may lag far
        # behind on a loaded machine: the stamps both have)
        def both():
            wrench = _by_stamp(client, 'wrench', lambda m: m.wrench.force.z, first)
            reaction = _by_stamp(client, 'plate_wrench', lambda m: m.wrench.force.z, first)
            return {ns: (wrench[ns], reaction[ns]) for ns in wrench.keys() & reaction.keys()
                    if since <= ns}
        client.spin_until(lambda: len(both()) >= 20, '20 samples on ~/wrench and ~/plate_wrench',
                          PROGRESS_TIMEOUT)
        assert all(reaction == -force and force > 0.0 for force, reaction in both().values())
        # refused, naming the parameter and its range; the table goes on
        for values, reason in [
                (dict(plate_amplitude=float('nan')), 'plate_amplitude'),
                (dict(plate_amplitude=-0.001), 'plate_amplitude'),
                (dict(plate_phase=7.0), 'plate_phase'),
                (dict(plate_frequency=200.0),
                 'plate_amplitude = 0.001 m at plate_frequency = 200 Hz shakes the plate at'),
                (dict(plate_amplitude=0.2), 'plate_amplitude'),
                (dict(plate_frequency=float('inf')), 'plate_frequency')]:
            (result,) = client.set_parameters(NODE, **values)
            assert not result.successful and reason in result.reason, (values, result.reason)
        assert client.get_parameters(NODE, ['plate_amplitude', 'plate_frequency']) == {
            'plate_amplitude': a, 'plate_frequency': f}
    finally:
        (result,) = client.set_parameters(NODE, atomically=True, plate_amplitude=0.0,
                                          plate_frequency=0.0)
        assert result.successful, result.reason
        # stopped: bridged to rest at p = 0 (within one period; the client may lag behind).
        # The ball still rests: a drop from 1 m (initial_height, restored after this) would
        # flood this client with contact samples, and on a loaded machine it would fall
        # behind the plate's poses for minutes (issue 16)
        try:
            client.spin_until(lambda: client.messages[plate_pose][-1].pose.position.z == 0.0
                              and client.messages[f'{NODE}/plate_twist'][-1].twist.linear.z
                              == 0.0, 'the plate at rest at 0', PROGRESS_TIMEOUT)
        finally:
            (result,) = client.set_parameters(NODE, initial_height=1.0)
            assert result.successful, result.reason
    assert sim.popen.poll() is None


def test_plate_command_moves_the_plate_and_reset_clears_it(sim, client):
    from trajectory_msgs.msg import JointTrajectory
    pub = client.node.create_publisher(JointTrajectory, f'{NODE}/plate_command', 10)
    client.spin_until(lambda: pub.get_subscription_count() > 0, 'the node to subscribe')
    plate_pose, plate_twist = f'{NODE}/plate_pose', f'{NODE}/plate_twist'
    command = fill_message(JointTrajectory(), yaml.safe_load(PLATE_COMMAND_YAML))

    def at(height):
        poses, twists = client.messages[plate_pose], client.messages[plate_twist]
        return (poses and poses[-1].pose.position.z == pytest.approx(height, abs=1e-12)
                and twists and twists[-1].twist.linear.z == pytest.approx(0.0, abs=1e-12))

    try:
        deadline = time.monotonic() + PROGRESS_TIMEOUT
        while not at(0.01):     # (a repeated command starts again from where the plate is)
            pub.publish(command)
            client.spin_until(lambda: at(0.01) or time.monotonic() > deadline, 'the plate',
                              PROGRESS_TIMEOUT + 5.0)
            assert time.monotonic() <= deadline, 'the plate never reached 1 cm'
        n = client.count(plate_pose)
        client.spin_until(lambda: client.count(plate_pose) >= n + 20, '20 more plate poses',
                          PROGRESS_TIMEOUT)
        assert at(0.01)         # and stays there: the command has ended, the plate rests
        # refusals: a warning naming the field; the plate stays where it is
        bad = fill_message(JointTrajectory(), yaml.safe_load(PLATE_COMMAND_YAML))
        bad.joint_names = ['paddle']
        pub.publish(bad)
        client.spin_until(lambda: rosout_has(client, "joint_names = ['paddle'] is invalid: "
                                              "allowed ['plate_z']"), 'the refusal')
        bad = fill_message(JointTrajectory(), yaml.safe_load(PLATE_COMMAND_YAML))
        bad.points[0].positions = [5.0]
        pub.publish(bad)
        client.spin_until(lambda: rosout_has(client, 'points[].positions reaches |positions| = 5 '
                                              'm: allowed -1 <= points[].positions <= 1 m'),
                          'the position refusal')
        past = fill_message(JointTrajectory(), yaml.safe_load(PLATE_COMMAND_YAML))
        past.header.stamp.nanosec = 1   # stamped 1 ns of simulated time, the point then: past
        past.points[0].time_from_start.sec = 0
        pub.publish(past)
        client.spin_until(lambda: rosout_has(client, 'no point after now'), 'the ignored one')
        assert at(0.01)
        # refused while the table runs
        (result,) = client.set_parameters(NODE, atomically=True, plate_amplitude=0.0005,
                                          plate_frequency=10.0)
        assert result.successful, result.reason
        pub.publish(command)
        client.spin_until(lambda: rosout_has(client, 'refused: the vibrating table runs '
                                              '(plate_amplitude = 0.0005, plate_frequency = 10 '
                                              '> 0)'), 'the refusal')
    finally:
        (result,) = client.set_parameters(NODE, atomically=True, plate_amplitude=0.0,
                                          plate_frequency=0.0)
        assert result.successful, result.reason
        client.node.destroy_publisher(pub)
    before = client.count(plate_pose)
    t0 = reset(client)   # the new drop's plate is the table's: fixed at 0 (the command cleared)

    def after_reset():
        return [m.pose.position.z for m in client.messages[plate_pose][before:]
                if stamp_ns(m.header.stamp) > t0]
    client.spin_until(lambda: len(after_reset()) >= 20, '20 plate poses after the reset',
                      PROGRESS_TIMEOUT)
    assert set(after_reset()) == {0.0}

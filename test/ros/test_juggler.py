"""examples/juggler.py against a real node.
"""
import math
import os
import re
import signal
import subprocess
import time
from pathlib import Path

import numpy as np
import pytest

import rclpy  # noqa: E402,F401  (pinned: a missing install fails here)

from geometry_msgs.msg import PoseStamped  # noqa: E402
from std_msgs.msg import Float64MultiArray  # noqa: E402
from std_srvs.srv import Trigger  # noqa: E402
from .harness import ROOT, TIMEOUT, DEEP, FIELDS, Process, assert_clean_exit, stamp_s  # noqa: E402


@pytest.mark.slow
def test_the_example_juggler_keeps_the_ball_bouncing_for_60_simulated_seconds(client, ros_env,
                                                                           workdir):
    """examples/juggler.py against a real node (its own process, named /juggled, at 3x real
    time): the ball starts at rest on the plate, is thrown, and keeps bouncing to the target."""
    import sys
    target, radius = 0.3, 0.0127
    node = Process('contact_sim_node', ['--ros-args', '-r', '__node:=juggled', '-p',
                                        'real_time_factor:=3.0', '-p', 'publish_clock:=false',
                                        '-p', 'initial_height:=0.0'], ros_env, workdir)
    log = Path(workdir) / f'juggler-{time.monotonic_ns()}.log'
    with open(log, 'w') as out:
        juggler = subprocess.Popen([sys.executable, str(ROOT / 'examples' / 'juggler.py'),
                                    '--ros-args', '-p', 'node:=/juggled', '-p',
                                    f'target_apex:={target}'], env=ros_env, stdout=out,
                                   stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                                   start_new_session=True, cwd=workdir)
    poses, impacts = [], []
    subs = [client.node.create_subscription(PoseStamped, '/juggled/pose', poses.append, DEEP),
            client.node.create_subscription(Float64MultiArray, '/juggled/impact',
                                            impacts.append, DEEP)]
    try:
        n = client.node
        client.spin_until(lambda: n.count_subscribers('/juggled/pose') >= 2
                          and n.count_publishers('/juggled/plate_command') >= 1
                          and n.count_subscribers('/juggled/plate_command') >= 1
                          or node.popen.poll() is not None or juggler.poll() is not None,
                          'the juggler and the node to discover each other', TIMEOUT)
        assert node.popen.poll() is None and juggler.poll() is None, log.read_text()
        response = client.call(Trigger, '/juggled/reset', Trigger.Request())
        assert response.success, response.message
        t0 = float(re.search(r'at t = ([0-9.]+) s', response.message).group(1))
        end = t0 + 80.0     # the throw within 20 s (discovery), then 60 s of bouncing

        def reached():
            return poses and stamp_s(poses[-1].header.stamp) >= end
        client.spin_until(lambda: reached() or juggler.poll() is not None, '80 simulated s',
                          240.0)
        assert juggler.poll() is None, log.read_text()
    finally:
        for sub in subs:
            client.node.destroy_subscription(sub)
        if juggler.poll() is None:
            os.killpg(juggler.pid, signal.SIGINT)
            juggler.wait(TIMEOUT)
        assert_clean_exit(node)
    assert 'Traceback' not in log.read_text(), log.read_text()
    records = [dict(zip(FIELDS, m.data)) for m in impacts if m.data[0] >= t0]
    bounces = [r for r in records if r['impact_speed'] > 0.5]
    logs = f'juggler:\n{log.read_text()}\nnode:\n{node.output()[-3000:]}'
    assert bounces and bounces[0]['time'] < t0 + 20.0, (records[:5], logs)  # thrown from rest
    first = bounces[0]['time']
    end = first + 60.0
    bounces = [r for r in bounces if r['time'] <= end]
    # impacts keep arriving through the whole window, never a permanent contact after the throw
    assert not [r for r in records if first <= r['time'] <= end
                and math.isinf(r['contact_duration'])]
    times = [first] + [r['time'] for r in bounces] + [end]
    assert max(b - a for a, b in zip(times, times[1:])) < 2.0, (times, logs)
    assert len(bounces) > 60, logs
    # the apex of each flight after the first 10 s: near the target
    heights = [(stamp_s(p.header.stamp), p.pose.position.z - radius) for p in poses]
    apexes = []
    for a, b in zip(times[1:], times[2:-1]):
        flight = [y for t, y in heights if a < t < b]
        if a > first + 10.0 and flight:
            apexes.append(max(flight))
    assert len(apexes) > 50
    assert float(np.median(apexes)) == pytest.approx(target, rel=0.05), apexes
    assert np.mean(np.abs(np.array(apexes) - target) < 0.1 * target) > 0.8, apexes

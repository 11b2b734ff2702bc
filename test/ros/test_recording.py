"""Lossless and crash-safe recording: a node and a recorder of their own, in a ROS domain of
their own (no package node there): a flat-out run recorded sample for sample, and a recorder
killed with SIGKILL whose bag is recovered.
"""
import os
import re
import signal
import subprocess
import time

import numpy as np
import pytest

import rclpy  # noqa: E402,F401  (pinned: a missing install fails here)

from contact_sim.ros import messages as cs_msgs  # noqa: E402
from contact_sim.ros import params as cs_params  # noqa: E402
from rclpy.qos import QoSProfile, ReliabilityPolicy  # noqa: E402
from rosgraph_msgs.msg import Clock  # noqa: E402
from std_srvs.srv import Trigger  # noqa: E402
from . import harness  # noqa: E402
from .domains import claim_domain  # noqa: E402
from .harness import (  # noqa: E402
    TIMEOUT, NODE, TOPICS, TYPE_NAMES, executable, clean_shm, Process, assert_clean_exit,
    stamp_ns, domain_node)


@pytest.fixture(scope='module')
def own_domain(ros_env):
    """Environment and a client context in another ROS domain (no module node there)."""
    env = {**ros_env, 'ROS_DOMAIN_ID': str(claim_domain())}
    context, node, executor = domain_node(int(env['ROS_DOMAIN_ID']), 'contact_sim_test_watch')
    clock = []
    node.create_subscription(Clock, '/clock', lambda m: clock.append(stamp_ns(m.clock)),
                             QoSProfile(depth=1, reliability=ReliabilityPolicy.BEST_EFFORT))
    acks = []    # the recorder's acknowledgements: simulated time (ns) it has recorded up to
    node.create_subscription(Clock, cs_msgs.PROGRESS.resolve(NODE),
                             lambda m: acks.append(stamp_ns(m.clock)), cs_msgs.PROGRESS.qos)

    def spin_until(condition, what, timeout=TIMEOUT):
        harness.spin_until(executor, condition, what, timeout)
    reset_client = node.create_client(Trigger, f'{NODE}/reset')

    def reset_drop():
        """~/reset; returns the simulated time (s) the new drop starts at, as the reply says."""
        spin_until(reset_client.service_is_ready, 'the reset service')
        while True:
            future = reset_client.call_async(Trigger.Request())
            retry = time.monotonic() + 3.0
            spin_until(lambda: future.done() or time.monotonic() > retry, 'a reset reply')
            if future.done():
                return float(re.search(r'at t = ([0-9.]+) s', future.result().message).group(1))
            reset_client.remove_pending_request(future)
    yield env, clock, spin_until, reset_drop, acks, node
    node.destroy_node()
    context.try_shutdown()


def read_bag(path):
    from rosbags.highlevel import AnyReader
    out = {}
    with AnyReader([path]) as reader:
        for connection, timestamp, raw in reader.messages():
            out.setdefault(connection.topic, []).append(
                (timestamp, reader.deserialize(raw, connection.msgtype)))
    return out


def replay(ticks, offset):
    """What the node publishes in ``ticks`` ticks of the default drop flat out (100 Hz) started
    by a ~/reset at simulated time ``offset``: the same engine, tick by tick. Returns
    {topic: [stamp ns]} and {stamp ns: wrench force}."""
    model = cs_params.build_model(dict(cs_params.DEFAULTS))
    sim = cs_params.make_simulation(model)
    samples, states, impacts, last = [], [], [], cs_msgs.to_ns(offset)
    for k in range(ticks):
        advance = sim.advance(0.0 + (k + 1) * 0.01)
        points, _ = cs_msgs.contact_samples(advance.samples, offset, last)
        samples += points
        last = points[-1][0] if points else last
        states.append(cs_msgs.to_ns(offset + float(advance.samples.time[-1])))
        impacts += [cs_msgs.to_ns(r.time + offset) for r in advance.impacts]
    sample_ns = [p[0] for p in samples]
    return ({f'{NODE}/wrench': sample_ns, f'{NODE}/contact': sample_ns, f'{NODE}/pose': states,
             f'{NODE}/twist': states, '/clock': states, f'{NODE}/impact': impacts,
             f'{NODE}/plate_pose': states, f'{NODE}/plate_twist': states,
             f'{NODE}/plate_wrench': sample_ns},
            {p[0]: p[3] for p in samples})


def stamps_in_bag(topic, items):
    if topic.endswith('impact'):
        return [cs_msgs.to_ns(m.data[0]) for _, m in items]
    return [stamp_ns(m.clock if topic == '/clock' else m.header.stamp) for _, m in items]


@pytest.mark.slow
def test_a_recorded_flat_out_run_holds_every_sample_of_every_topic(own_domain, workdir):
    """Flat out, the recorder's keep-all subscriptions and its ~/recorded acknowledgements make
    the node wait for it: from a ~/reset on, the bag holds every sample the node published (the
    same engine replayed here gives the stamps and values), for more than 60 simulated s."""
    env, clock, spin_until, reset_drop, _, _ = own_domain
    bag = workdir / 'flat_out'
    recorder = Process('contact_sim_record', ['-o', str(bag)], env, workdir)
    spin_until(lambda: 'recording' in recorder.output(), 'the recorder to start')
    node = Process('contact_sim_node', ['--ros-args', '-p', 'real_time_factor:=0.0'], env,
                   workdir)
    try:
        spin_until(lambda: all(f'receiving {t}' in recorder.output() for t in TOPICS
                               if not t.endswith('impact')), 'the recorder to receive')
        # paced from here on (before, the node may run ahead of what the recorder can take)
        spin_until(lambda: 'pacing 1 node(s)' in recorder.output(), 'the node to be paced')
        offset = reset_drop()   # a drop that bounces, recorded from its start
        ticks_before = round(offset * 100)
        assert offset == pytest.approx(ticks_before * 0.01, abs=1e-9)  # on the tick grid
        offset = 0.0 + ticks_before * 0.01
        # (the node runs up to pacing.LEAD_MESSAGES ahead of what the recorder has acknowledged)
        # (no bound on the speed here: a recorded flat-out run now and then falls to ~1x real
        # time, docs/ros.md; the wait is sized for 80 simulated s at 0.1x)
        spin_until(lambda: clock and clock[-1] > (offset + 80) * 1e9, '80 simulated seconds',
                   timeout=900)
    finally:
        try:
            assert_clean_exit(recorder)
        finally:
            assert_clean_exit(node)
    assert 'stopped before' not in recorder.output()
    recorded = read_bag(bag)
    assert set(recorded) == set(TYPE_NAMES)
    reset_ns = cs_msgs.to_ns(offset)
    end = max(max(stamps_in_bag(t, items)) for t, items in recorded.items())
    expected, forces = replay(int(round((end - reset_ns) * 1e-7)) + 1, offset)
    assert len(expected[f'{NODE}/impact']) > 30   # the bounces are in it
    for topic, items in recorded.items():
        got = stamps_in_bag(topic, items)
        assert [ts for ts, _ in items] == got  # bag time = simulated time
        got = [ns for ns in got if ns > reset_ns]
        want = [ns for ns in expected[topic] if ns <= got[-1]]
        missing = sorted(set(want) - set(got))
        assert got == want, (topic, len(got), len(want), missing[:3], missing[-3:],
                             reset_ns, got[-1])  # every sample, in order
        if not topic.endswith('impact'):
            assert got[-1] - reset_ns >= 60e9, topic  # >= 60 simulated seconds
    # the same values, and the sample topics end together at the stop
    wrench = [m for _, m in recorded[f'{NODE}/wrench'] if stamp_ns(m.header.stamp) > reset_ns]
    # (to round-off: the node evaluates rest and flight over arrays, where numpy's SIMD exp, sin
    # and cos may differ from the C library's in the last bit on some CPUs)
    assert all(m.wrench.force.z == pytest.approx(forces[stamp_ns(m.header.stamp)], rel=1e-12,
                                                 abs=0.0) for m in wrench)
    assert recorded[f'{NODE}/wrench'][-1][0] == recorded[f'{NODE}/contact'][-1][0]


@pytest.mark.slow
def test_a_recorder_killed_with_sigkill_loses_at_most_a_second_and_recovers(own_domain,
                                                                            workdir):
    env, clock, spin_until, _, acks, _ = own_domain
    bag = workdir / 'killed'
    clock.clear()   # (from an earlier node in this domain)
    acks.clear()
    node = Process('contact_sim_node', [], env, workdir)
    recorder = Process('contact_sim_record', ['-o', str(bag)], env, workdir)
    try:
        spin_until(lambda: 'receiving /contact_sim/pose' in recorder.output(), 'recording')
        spin_until(lambda: clock and clock[-1] < 30e9, "this node's /clock")  # (not stale)
        start = clock[-1]
        spin_until(lambda: clock[-1] > start + 3e9 and acks and acks[-1] > start + 2e9,
                   '3 more simulated seconds, recorded')
        os.killpg(recorder.popen.pid, signal.SIGKILL)
        # what the recorder had recorded by the kill, as it acknowledged it (this reader lags
        # it: it had recorded at least this); messages still on their way to it are not its loss
        killed_at = acks[-1]
        recorder.popen.wait(TIMEOUT)
        clean_shm(recorder.started)
    finally:
        if recorder.popen.poll() is None:   # the test failed before the kill
            recorder.stop()
        assert_clean_exit(node)
    assert not (bag / 'metadata.yaml').exists()
    out = subprocess.run([executable('contact_sim_record'), '--recover', str(bag)], env=env,
                         capture_output=True, text=True, timeout=TIMEOUT)
    assert out.returncode == 0, out.stderr
    assert out.stdout.startswith(f'recovered {bag}: ')
    recorded = read_bag(bag)
    poses = stamps_in_bag(f'{NODE}/pose', recorded[f'{NODE}/pose'])
    assert np.all(np.diff(poses) == 10_000_000)  # nothing missing up to the last flush
    assert poses[-1] >= killed_at - 1_000_000_000, (poses[-1], killed_at)
    # a second recovery is refused: the bag is complete
    again = subprocess.run([executable('contact_sim_record'), '--recover', str(bag)], env=env,
                           capture_output=True, text=True, timeout=TIMEOUT)
    assert again.returncode == 2 and 'metadata.yaml already' in again.stderr


@pytest.mark.slow
def test_a_flat_out_node_stopped_first_leaves_nothing_it_published_out_of_the_bag(own_domain,
                                                                                   workdir):
    """The recorder started first, a flat-out node, the node stopped first (issue 22: the bag
    ended 3 simulated s before the last tick the node had published). The bag holds every tick
    from the first (t = 0.01 s) to the last the node published, which the node names at its stop
    and which is at least the last /clock this test saw, on every per-tick topic."""
    env, clock, spin_until, _, _, _ = own_domain
    bag = workdir / 'node_first'
    clock.clear()
    recorder = Process('contact_sim_record', ['-o', str(bag)], env, workdir)
    spin_until(lambda: 'recording' in recorder.output(), 'the recorder to start')
    node = Process('contact_sim_node', ['--ros-args', '-p', 'real_time_factor:=.inf'], env,
                   workdir)
    try:
        spin_until(lambda: clock and clock[-1] > 20e9, '20 simulated seconds', timeout=300)
        assert_clean_exit(node)
        seen = clock[-1]     # published by the node: it reached at least this
    finally:
        try:
            assert_clean_exit(node)
        finally:
            assert_clean_exit(recorder)
    recorded = read_bag(bag)
    logs = f'recorder:\n{recorder.output()[-4000:]}\nnode:\n{node.output()[-4000:]}'
    assert set(recorded) == set(TYPE_NAMES), logs
    ends = {}
    for topic, items in recorded.items():
        stamps = stamps_in_bag(topic, items)
        assert [ts for ts, _ in items] == stamps   # bag time = simulated time
        if topic.endswith('impact'):
            continue
        ends[topic] = stamps[-1]
        assert stamps[-1] >= seen, (topic, stamps[-1], seen, logs)  # what this test saw published
        if cs_msgs.TOPIC[topic.rsplit('/', 1)[1]].kind in ('state', 'clock'):
            ticks = np.rint(np.array(stamps) / 1e7).astype(int)   # 100 Hz ticks from 0
            missing = sorted(set(range(1, ticks[-1] + 1)) - set(ticks.tolist()))
            assert not missing and len(ticks) == ticks[-1], (topic, missing[:5], len(missing),
                                                             logs)
    # and to the last tick the node published, as it says at its stop
    match = re.search(r'the recorder has every tick published, to t = ([0-9.]+) s',
                      node.output())
    assert match, node.output()
    assert set(ends.values()) == {cs_msgs.to_ns(float(match.group(1)))}, ends


@pytest.mark.slow
def test_a_killed_recorder_is_noticed_before_the_graph_forgets_it(own_domain, workdir):
    """Issue 33: after its recorder was killed, a flat-out node froze ~20 s (until the graph
    dropped the killed participant) and a node stopped then waited 10.7 s without a word. The
    recorder's liveliness lease (1.5 s) tells the node: it says the recorder is gone and runs on
    while the graph still shows the killed recorder, and its stop does not wait for it."""
    env, clock, spin_until, _, acks, watch = own_domain
    clock.clear()
    acks.clear()
    recorder = Process('contact_sim_record', ['-o', str(workdir / 'lost')], env, workdir)
    spin_until(lambda: 'recording' in recorder.output(), 'the recorder to start')
    node = Process('contact_sim_node', ['--ros-args', '-p', 'real_time_factor:=0.0'], env,
                   workdir)
    progress = cs_msgs.PROGRESS.resolve(NODE)
    try:
        spin_until(lambda: 'paced by a recorder' in node.output() and acks and acks[-1] > 1e9,
                   'the node paced by the recorder')
        os.killpg(recorder.popen.pid, signal.SIGKILL)
        recorder.popen.wait(TIMEOUT)
        clean_shm(recorder.started)
        spin_until(lambda: 'the recorder is gone' in node.output() and clock,
                   'the node to notice')
        killed_at = clock[-1]
        spin_until(lambda: clock[-1] > killed_at + 5e9, '5 more simulated seconds')
        assert watch.get_publishers_info_by_topic(progress), \
            'the graph forgot the recorder first: this test shows nothing'
    finally:
        if recorder.popen.poll() is None:
            recorder.stop()
        code, output = node.stop()
    assert code == 0 and 'Traceback' not in output, output
    assert 'stopping after' not in output and 'waiting for the recorder' not in output, output

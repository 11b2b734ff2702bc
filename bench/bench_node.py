"""CPU and throughput of contact_sim_node, read from /proc CPU times of the node process.

    python bench/bench_node.py            # every scenario (about 2 minutes)
    python bench/bench_node.py --quick    # shorter windows

Scenarios (the node is the installed console entry point, in its own process; each run gets its
own ROS_DOMAIN_ID):
  rest-100Hz     real time, 100 Hz, the ball at rest, no subscriber: CPU % of one core
  rest-1kHz      real time, 1 kHz, the ball at rest, a reliable subscriber on every topic
                 counting the messages: CPU %, ticks/s on each topic
  floor          µs per tick to encode and publish one tick on every per-tick topic of
                 messages.TOPICS (kinds sample, state, clock: wrench, contact, pose, twist, /clock,
                 ...), no simulation: the node's CDR encoders, and rclpy message objects for
                 comparison (measured in this process, no subscriber)
  flat-out       real_time_factor 0, 100 Hz, no subscriber: simulated s per wall s (from
                 ~/reset replies) and the node's CPU µs per tick, against the floor
  settle         real time, 100 Hz: the longest executor turn (CPU time of one timer callback)
                 over the first 5 s, which include the bouncing and the settling, in this process
The executor comparison (--executors) runs a bare 100 Hz / 1 kHz timer publishing five messages
under each executor.
"""
import argparse
import math
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from std_srvs.srv import Trigger

TICK = os.sysconf('SC_CLK_TCK')


def cpu_seconds(pid):
    """utime + stime of a process (all its threads), in s."""
    fields = Path(f'/proc/{pid}/stat').read_text().rsplit(')', 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / TICK


def executable(name):
    from ament_index_python.packages import get_package_prefix
    return str(Path(get_package_prefix('contact_sim')) / 'lib' / 'contact_sim' / name)


class NodeProcess:
    def __init__(self, params, workdir):
        args = [executable('contact_sim_node'), '--ros-args']
        for key, value in params.items():
            args += ['-p', f'{key}:={value}']
        self.log = open(Path(workdir) / f'node-{time.monotonic_ns()}.log', 'w+')
        self.popen = subprocess.Popen(args, stdout=self.log, stderr=subprocess.STDOUT,
                                      start_new_session=True)

    def cpu(self):
        return cpu_seconds(self.popen.pid)

    def stop(self):
        os.killpg(self.popen.pid, 2)
        self.popen.wait(20)
        self.log.seek(0)
        return self.log.read()


def measure_cpu(process, seconds, spin=None):
    """CPU % of one core used by ``process`` over ``seconds`` of wall time."""
    c0, w0 = process.cpu(), time.monotonic()
    while time.monotonic() - w0 < seconds:
        if spin is not None:
            spin(0.05)
        else:
            time.sleep(0.05)
    return 100.0 * (process.cpu() - c0) / (time.monotonic() - w0)


def wait_for_service(node, executor, name, timeout=20.0):
    client = node.create_client(Trigger, name)
    deadline = time.monotonic() + timeout
    while not client.service_is_ready():
        if time.monotonic() > deadline:
            raise RuntimeError(f'no service {name}')
        executor.spin_once(timeout_sec=0.1)
    return client


def call_reset(client, executor):
    """Reset the drop; returns the simulated time (s) the reply names."""
    while True:
        future = client.call_async(Trigger.Request())
        deadline = time.monotonic() + 5.0
        while not future.done() and time.monotonic() < deadline:
            executor.spin_once(timeout_sec=0.05)
        if future.done():
            return float(re.search(r'at t = ([0-9.]+) s', future.result().message).group(1))
        client.remove_pending_request(future)


def scenario_rest(rate, window, workdir, subscribe):
    from contact_sim.ros.messages import TOPICS
    process = NodeProcess({'publish_rate': f'{rate:.1f}'}, workdir)
    from rclpy.experimental.events_executor import EventsExecutor
    node = rclpy.create_node(f'bench_{int(rate)}')
    executor = EventsExecutor()   # (a subscriber that keeps up: raw messages, counted)
    executor.add_node(node)
    counts = {}
    if subscribe:
        qos = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=1000,
                         reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.VOLATILE)
        for topic in TOPICS:
            if topic.kind == 'impact':
                continue
            name = topic.resolve('/contact_sim')
            counts[name] = 0

            def count(_msg, name=name):
                counts[name] += 1
            node.create_subscription(topic.msg_type, name, count, qos, raw=True)
    wait_for_service(node, executor, '/contact_sim/reset')
    # the default drop comes to rest within 3 s of simulated time
    deadline = time.monotonic() + 4.0
    while time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.05)
    start = dict(counts)
    w0 = time.monotonic()
    cpu = measure_cpu(process, window, spin=lambda t: executor.spin_once(timeout_sec=t))
    wall = time.monotonic() - w0
    rates = {name: (counts[name] - start[name]) / wall for name in counts}
    log = process.stop()
    node.destroy_node()
    return cpu, rates, log


def floor(ticks=20000):
    """µs per tick to encode and publish one message on every per-tick topic of messages.TOPICS
    (kinds sample, state and clock; no subscriber), in CPU time of this process: with the node's
    CDR encoders, and with rclpy message objects for comparison. Returns (CDR µs, objects µs,
    topic keys)."""
    from contact_sim.ros import messages as m
    node = rclpy.create_node('bench_floor')
    topics = [t for t in m.TOPICS if t.kind in ('sample', 'state', 'clock')]
    pubs = [node.create_publisher(t.msg_type, f'/bench_floor/{t.key}', t.qos) for t in topics]
    enc = [t.template('plate').packer() for t in topics]   # as the node's
    values = [tuple(0.5 + i for i in range(len(t.fields))) for t in topics]
    rows = list(zip(pubs, enc, values))
    # CPU time of this process (all its threads, as the node's from /proc): not the machine's load
    t0 = time.process_time()
    for i in range(ticks):
        ns = 1_000_000_000 + i * 10_000_000
        for pub, encode, vals in rows:
            pub.publish(encode(ns, *vals))
    cdr = (time.process_time() - t0) / ticks * 1e6
    build = [_object_builder(t, 'plate') for t in topics]
    rows = list(zip(pubs, build, values))
    t0 = time.process_time()
    for i in range(ticks // 4):
        ns = 1_000_000_000 + i * 10_000_000
        for pub, make, vals in rows:
            pub.publish(make(ns, *vals))
    objects = (time.process_time() - t0) / (ticks // 4) * 1e6
    node.destroy_node()
    return cdr, objects, [t.key for t in topics]


def _object_builder(topic, frame_id):
    """An rclpy message object of ``topic`` stamped ns with its fields set to values."""
    from contact_sim.ros import messages as m

    def build(ns, *values):
        msg = topic.msg_type()
        for path, value in topic.constants:
            m._set(msg, path, value)
        if topic.kind == 'clock':
            msg.clock = m.time_msg(ns)
        else:
            msg.header.stamp = m.time_msg(ns)
            msg.header.frame_id = frame_id
        for path, value in zip(topic.fields, values):
            m._set(msg, path, float(value))
        return msg
    return build


def scenario_flat_out(window, workdir):
    process = NodeProcess({'real_time_factor': '0.0'}, workdir)
    node = rclpy.create_node('bench_flat')
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    client = wait_for_service(node, executor, '/contact_sim/reset')
    sim0, c0, w0 = call_reset(client, executor), process.cpu(), time.monotonic()
    deadline = w0 + window
    while time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.05)
    sim1, c1, w1 = call_reset(client, executor), process.cpu(), time.monotonic()
    log = process.stop()
    node.destroy_node()
    ticks = (sim1 - sim0) * 100.0
    return ((sim1 - sim0) / (w1 - w0), (sim1 - sim0) / (c1 - c0), 1e6 * (c1 - c0) / ticks,
            100.0 * (c1 - c0) / (w1 - w0), log)


def settle(seconds=5.0):
    """CPU time (s) of each timer callback of a node run in this process for ``seconds`` of wall
    time, with the simulated time it ended at and how far (s of wall time) the published ticks
    were behind real time then; and the default drop's permanent-contact and
    settle (closed-form rest) times."""
    from rclpy.experimental.events_executor import EventsExecutor
    from contact_sim.ros.node import ContactSimNode
    node = ContactSimNode()
    turns = []
    inner = node._turn

    def timed():   # CPU time of this thread: the turn's own cost, not the machine's load
        t0 = time.thread_time()
        inner()
        cpu = time.thread_time() - t0
        behind = (time.monotonic() - node._anchor_wall) / node._model.publish_rate ** -1 \
            - node._tick   # ticks due but not yet published
        turns.append((cpu, node._sim.time, behind / node._model.publish_rate))
    node._turn = timed
    executor = EventsExecutor()
    executor.add_node(node)
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.1)
    landed, settled = node._sim.permanent_contact_time, node._sim.settle_time
    executor.remove_node(node)
    node.destroy_node()
    return turns, landed, settled


def settle_summary(turns, landed, settled):
    """The longest turn overall, while bouncing (ending before the permanent contact) and in
    the settling (ending between the permanent contact and 0.1 s after the closed-form rest)."""
    longest = max(turns)
    mean = sum(t for t, _, _ in turns) / len(turns)
    bouncing = max((t for t, at, _ in turns if at < landed), default=math.nan)
    settling = [t for t, at, _ in turns if landed <= at <= settled + 0.1]
    behind = max(lag for _, _, lag in turns[1:])
    return (f'longest executor turn {longest[0] * 1e3:.1f} ms of CPU (ending at t = '
            f'{longest[1]:.3f} s), mean {mean * 1e3:.2f} ms over {len(turns)} turns; longest while '
            f'bouncing (t < {landed:.3f} s) {bouncing * 1e3:.1f} ms; settling (permanent contact '
            f'to the closed-form rest at t = {settled:.3f} s) over {len(settling)} turns, the '
            f'longest {max(settling, default=math.nan) * 1e3:.1f} ms, '
            f'{sum(settling) * 1e3:.1f} ms in all; the ticks published were at most '
            f'{behind * 1e3:.0f} ms behind real time')


def executors(window=5.0):
    """A bare timer publishing five messages per tick under each executor: CPU % and ticks/s."""
    code = r'''
import os, sys, time, rclpy
from rclpy.clock import Clock, ClockType
from geometry_msgs.msg import WrenchStamped
kind, rate, window = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
rclpy.init()
node = rclpy.create_node('bench_executor')
pubs = [node.create_publisher(WrenchStamped, f'~/w{i}', 10) for i in range(5)]
ticks = [0]
def tick():
    ticks[0] += 1
    for p in pubs:
        p.publish(WrenchStamped())
node.create_timer(1.0 / rate, tick, clock=Clock(clock_type=ClockType.STEADY_TIME))
if kind == 'events':
    from rclpy.experimental.events_executor import EventsExecutor as E
elif kind == 'multi':
    from rclpy.executors import MultiThreadedExecutor as E
else:
    from rclpy.executors import SingleThreadedExecutor as E
ex = E(); ex.add_node(node)
t0, c0 = time.monotonic(), os.times()
while time.monotonic() - t0 < window:
    ex.spin_once(timeout_sec=0.1)
c1, t1 = os.times(), time.monotonic()
print(f'{100 * (c1.user + c1.system - c0.user - c0.system) / (t1 - t0):.1f} {ticks[0] / (t1 - t0):.0f}')
'''
    rows = []
    for kind in ('single', 'multi', 'events'):
        for rate in (100.0, 1000.0):
            out = subprocess.run([sys.executable, '-c', code, kind, str(rate), str(window)],
                                 capture_output=True, text=True, timeout=60).stdout.split()
            rows.append((kind, rate, float(out[0]), float(out[1])))
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--quick', action='store_true', help='5 s windows instead of 10 s')
    parser.add_argument('--executors', action='store_true', help='also compare the executors')
    options = parser.parse_args()
    window = 5.0 if options.quick else 10.0
    os.environ.setdefault('ROS_DOMAIN_ID', str(1 + os.getpid() % 101))
    os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE'] = 'LOCALHOST'
    with tempfile.TemporaryDirectory(prefix='bench_node_') as workdir:
        os.environ['ROS_LOG_DIR'] = workdir
        if options.executors:
            print(f'executors: a bare timer publishing 5 messages per tick, {window:g} s')
            print('  executor  rate (Hz)  CPU (% of a core)  ticks/s')
            for kind, rate, cpu, ticks in executors(window):
                print(f'  {kind:8s} {rate:9.0f} {cpu:18.1f} {ticks:8.0f}')
        rclpy.init()
        try:
            cpu, _, log = scenario_rest(100.0, window, workdir, subscribe=False)
            print(f'rest-100Hz  real time, 100 Hz, at rest, no subscriber: {cpu:.1f} % of a core'
                  f' (target <= 5 %)')
            cpu, rates, log = scenario_rest(1000.0, window, workdir, subscribe=True)
            print(f'rest-1kHz   real time, 1 kHz, at rest, reliable subscriber on every topic: '
                  f'{cpu:.1f} % of a core (target <= 50 %); messages/s: '
                  + ', '.join(f'{name.rsplit("/", 1)[1]} {r:.0f}' for name, r in rates.items()))
            if 'cannot be held' in log:
                print('            node log: ' + next(line for line in log.splitlines()
                                                     if 'cannot be held' in line))
            print('settle      real time, 100 Hz, first 5 s (bouncing and settling): '
                  + settle_summary(*settle()))
            cdr, objects, keys = floor()
            print(f'floor       encode + publish one tick on {len(keys)} topics ({", ".join(keys)}),'
                  f' no subscriber: {cdr:.1f} us (CDR templates), {objects:.1f} us (rclpy message '
                  f'objects)')
            speed, per_cpu, per_tick, cpu, log = scenario_flat_out(window, workdir)
            print(f'flat-out    real_time_factor 0, 100 Hz, no subscriber: {speed:.0f} x real '
                  f'time in wall time ({cpu:.0f} % of a core: the rest of the time the node '
                  f'was runnable but not running), {per_cpu:.0f} simulated s per CPU s of the '
                  f'node, {per_tick:.1f} us of node CPU per tick ({per_tick / cdr:.2f} x the '
                  f'floor)')
        finally:
            rclpy.try_shutdown()


if __name__ == '__main__':
    from _table import run   # --markdown OUT: the table for the docs (bench/_table.py)
    run(main)

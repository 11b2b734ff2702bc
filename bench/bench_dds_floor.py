"""The middleware on one topic: how many messages a second one rclpy process can hand
to another through the ROS 2 middleware here (Fast DDS, rclpy, shared memory), with the node's
and the recorder's QoS and the recorder's pacing, and nothing else (no engine, no bag).

    python bench/bench_dds_floor.py [--messages 40000]

A publisher sends serialized ``geometry_msgs/PoseStamped`` (the node's state QoS, raw bytes as
the node's outbox does) at most the node's lead (``pacing.lead_messages``) beyond what a
subscriber (a second process: keep-all reliable, raw, by default the events executor; with
``--take waitset`` as ``contact_sim_record`` takes) has acknowledged
on a ``~/recorded``-like topic every ``recorder.ACK_EVERY`` messages. Printed: messages per wall
second, CPU µs per message of each process (user + system, its middleware threads included),
and what that rate allows a recorded node: at ``bench_recording``'s messages per simulated
second (8 a tick at rest at 100 Hz; 1458 bouncing), the real-time factor this one topic's rate
would be. It is not a ceiling for the node, whose messages go out on 9 topics: on 2026-12-02
this bench gave 44,000-57,000 messages a second while ``bench_recording`` carried
62,000-74,000. Run it as the node publishes: ``--publication-mode ASYNCHRONOUS --take waitset``.
"""
import argparse
import os
import resource
import subprocess
import sys
import time
from pathlib import Path

import rclpy
from geometry_msgs.msg import PoseStamped
from rclpy.experimental.events_executor import EventsExecutor
from rclpy.serialization import serialize_message
from rosgraph_msgs.msg import Clock

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from contact_sim.ros.messages import PROGRESS, RECORD_QOS, STATE_QOS  # noqa: E402
from contact_sim.ros.pacing import lead_messages  # noqa: E402
from contact_sim.ros.recorder import ACK_EVERY  # noqa: E402

TOPIC, ACK = '/bench_dds_floor/data', '/bench_dds_floor/recorded'
TAKE = ['events']    # how the subscriber takes (--take)
SUB_ENV = {}          # the subscriber's environment changes (--publication-mode: the publisher's only)
REST_MESSAGES = 800   # messages a simulated second at rest: 8 a tick at 100 Hz (loop.TICK_MESSAGES)
BOUNCING_MESSAGES = 1458   # bouncing: bench_recording's bag (the contact samples on 3 topics)
LEAD = []             # the publisher's lead: the node's (pacing.lead_messages) in its environment


def cpu_seconds():
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def subscriber(count, take='events'):
    """Take ``count`` messages raw; acknowledge every ACK_EVERY; print CPU µs a message."""
    node = rclpy.create_node('bench_dds_floor_sub')
    executor = EventsExecutor()
    executor.add_node(node)
    ack = node.create_publisher(Clock, ACK, PROGRESS.qos)
    got, start = [0], []

    def on_message(data):
        if not start:
            start.append(cpu_seconds())
        got[0] += 1
        if got[0] % ACK_EVERY == 0 or got[0] == count:
            msg = Clock()
            msg.clock.sec = got[0]
            ack.publish(msg)
    subscription = node.create_subscription(PoseStamped, TOPIC, on_message, RECORD_QOS, raw=True)
    print('ready', flush=True)
    if take == 'events':
        while got[0] < count:
            executor.spin_once(timeout_sec=0.1)
    else:   # a wait set of the one subscription; every message there taken at each wake-up
        from rclpy.impl.implementation_singleton import rclpy_implementation as _rclpy
        executor.remove_node(node)
        wait_set = _rclpy.WaitSet(1, 0, 0, 0, 0, 0, node.context.handle)
        handle, take_message = subscription.handle, subscription.handle.take_message
        while got[0] < count:
            wait_set.clear_entities()
            wait_set.add_subscription(handle)
            wait_set.wait(100_000_000)
            while (taken := take_message(PoseStamped, True)) is not None:
                on_message(taken[0])
    print(f'{(cpu_seconds() - start[0]) / count * 1e6:.1f}', flush=True)
    time.sleep(0.5)   # the last acknowledgement out


def publisher(count):
    """Start the subscriber, send ``count`` messages paced by it; (wall s, CPU µs a message of
    each side)."""
    env = {**os.environ, **SUB_ENV}
    sub = subprocess.Popen([sys.executable, __file__, '--role', 'sub', '--messages', str(count),
                            '--take', TAKE[0]],
                           stdout=subprocess.PIPE, text=True, env={k: v for k, v in env.items() if v})
    try:
        if sub.stdout.readline().strip() != 'ready':
            raise RuntimeError('the subscriber did not start')
        node = rclpy.create_node('bench_dds_floor_pub')
        executor = EventsExecutor()
        executor.add_node(node)
        publisher = node.create_publisher(PoseStamped, TOPIC, STATE_QOS)
        acked = [0]
        node.create_subscription(Clock, ACK, lambda m: acked.__setitem__(0, m.clock.sec),
                                 PROGRESS.qos)
        deadline = time.monotonic() + 30
        while publisher.get_subscription_count() == 0 or acked[0] < 0:
            if time.monotonic() > deadline:
                raise RuntimeError('the subscriber was not discovered within 30 s')
            executor.spin_once(timeout_sec=0.05)
        data = serialize_message(PoseStamped())
        publish = publisher.handle.publish_raw    # as the node's outbox publishes
        wall, cpu, own = time.monotonic(), cpu_seconds(), time.thread_time()
        for sent in range(1, count + 1):
            while sent - acked[0] > LEAD[0]:
                executor.spin_once(timeout_sec=1.0)
            publish(data)
            if sent % 8 == 0:
                executor.spin_once(timeout_sec=0)
        while acked[0] < count:
            executor.spin_once(timeout_sec=1.0)
        own = (time.thread_time() - own) / count * 1e6
        wall, cpu = time.monotonic() - wall, (cpu_seconds() - cpu) / count * 1e6
        return wall, cpu, own, float(sub.stdout.readline())
    finally:
        sub.wait(30)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--messages', type=int, default=40000)
    parser.add_argument('--publication-mode', choices=('SYNCHRONOUS', 'ASYNCHRONOUS'),
                        default=None, help='RMW_FASTRTPS_PUBLICATION_MODE of the publishing process'
                        ' only (default: as the environment says)')
    parser.add_argument('--take', choices=('events', 'waitset'), default='events',
                        help="the subscriber's take: a callback a message from the events executor,"
                        ' or a wait set and every message there taken at each wake-up (as'
                        ' contact_sim_record)')
    parser.add_argument('--role', choices=('pub', 'sub'), default='pub', help=argparse.SUPPRESS)
    options = parser.parse_args()
    TAKE[0] = options.take
    if options.publication_mode and options.role == 'pub':
        SUB_ENV['RMW_FASTRTPS_PUBLICATION_MODE'] = os.environ.get('RMW_FASTRTPS_PUBLICATION_MODE', '')
        os.environ['RMW_FASTRTPS_PUBLICATION_MODE'] = options.publication_mode
    if 'ROS_DOMAIN_ID' not in os.environ:
        os.environ['ROS_DOMAIN_ID'] = str(150 + os.getpid() % 80)
    rclpy.init()
    try:
        if options.role == 'sub':
            subscriber(options.messages, options.take)
            return
        load = os.getloadavg()[0]
        LEAD.append(lead_messages())
        wall, pub_us, own_us, sub_us = publisher(options.messages)
    finally:
        rclpy.try_shutdown()
    rate = options.messages / wall
    mode = os.environ.get('RMW_FASTRTPS_PUBLICATION_MODE', 'default')
    print(f'publisher RMW_FASTRTPS_PUBLICATION_MODE {mode}, take {options.take}: {options.messages} messages paced (lead {LEAD[0]}, acknowledged every '
          f'{ACK_EVERY}): {rate:.0f} messages/s; CPU {pub_us:.1f} us a message publishing '
          f'({own_us:.1f} in the publishing thread), '
          f'{sub_us:.1f} us taking; load average {load:.1f} before, {os.getloadavg()[0]:.1f} '
          'after')
    print(f'this rate on one topic is {rate / REST_MESSAGES:.0f}x real time for a node at rest '
          f'({REST_MESSAGES} messages a simulated s) and {rate / BOUNCING_MESSAGES:.0f}x bouncing '
          f'({BOUNCING_MESSAGES}); not a ceiling: the node publishes on 9 topics '
          '(bench_recording.py prints what they carry)')


if __name__ == '__main__':
    from _table import run   # --markdown OUT: the table for the docs (bench/_table.py)
    run(main)

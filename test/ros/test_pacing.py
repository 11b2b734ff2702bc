"""The node's side of the pacing protocol (``contact_sim.ros.pacing.RecorderPace``) without ROS:
a stand-in node whose subscription reports how many recorders publish ``~/recorded``, and a
clock the test moves (START_GRACE is wall time)."""
import math

import pytest

pytest.importorskip('rclpy')

from contact_sim.ros import pacing  # noqa: E402
from builtin_interfaces.msg import Time  # noqa: E402
from rosgraph_msgs.msg import Clock  # noqa: E402


class Subscription:
    def __init__(self):
        self.publishers = 0

    def get_publisher_count(self):
        return self.publishers


class Logger:
    def __init__(self):
        self.lines = []

    def info(self, text):
        self.lines.append(text)


class Node:
    def __init__(self):
        self.subscription, self.logger = Subscription(), Logger()

    def create_subscription(self, msg_type, name, callback, qos):
        self.callback = callback
        return self.subscription

    def get_logger(self):
        return self.logger


@pytest.fixture
def clock(monkeypatch):
    now = [1000.0]
    monkeypatch.setattr(pacing.time, 'monotonic', lambda: now[0])
    return now


def ack(node, ns):
    node.callback(Clock(clock=Time(sec=ns // 1_000_000_000, nanosec=ns % 1_000_000_000)))


def make(sent):
    node, rooms = Node(), []
    pace = pacing.RecorderPace(node, lambda: sent[0], lambda: rooms.append(True),
                               lead=pacing.LEAD_MESSAGES)
    return node, pace, rooms


def test_without_a_recorder_the_node_waits_the_grace_then_runs_unpaced(clock):
    node, pace, _ = make([0])
    assert pace.room() == 0
    clock[0] += pacing.START_GRACE + 0.01
    assert pace.room() == math.inf
    assert any('no recorder found' in line for line in node.logger.lines)
    assert pace.drained()


def test_a_recorder_found_paces_by_messages_and_releases_them_by_time(clock):
    sent = [0]
    node, pace, rooms = make(sent)
    node.subscription.publishers = 1
    assert pace.room() == 0                      # found, not ready yet: wait
    ack(node, pacing.READY_NS)
    assert pace.room() == pacing.LEAD_MESSAGES and rooms
    sent[0] = 200
    pace.mark(1_000_000_000)                     # 200 messages up to t = 1 s
    sent[0] = 300
    pace.mark(2_000_000_000)                     # 100 more up to t = 2 s
    assert pace.room() == pacing.LEAD_MESSAGES - 300 and not pace.drained()
    ack(node, 1_500_000_000)                     # releases the note at 1 s, not the one at 2 s
    assert pace.room() == pacing.LEAD_MESSAGES - 100
    ack(node, 2_000_000_000)
    assert pace.room() == pacing.LEAD_MESSAGES and pace.drained()


def test_a_recorder_found_again_after_it_was_missed_does_not_stall_the_node(clock):
    # reproduced: the first acknowledgement after a miss released nothing (no note covered what
    # went out meanwhile), so the node stayed paused for good
    sent = [0]
    node, pace, _ = make(sent)
    node.subscription.publishers = 1
    ack(node, pacing.READY_NS)
    clock[0] += pacing.START_GRACE + 0.01
    node.subscription.publishers = 0
    pace.watch()
    assert pace.room() == pacing.LEAD_MESSAGES   # one look without it: still paced by it
    for _ in range(pacing.MISSES - 1):
        pace.watch()
    assert pace.room() == math.inf               # missed: unpaced
    sent[0] = 5000                               # published meanwhile, without notes
    node.subscription.publishers = 1
    pace.watch()
    ack(node, 30_000_000_000)
    assert pace.room() == pacing.LEAD_MESSAGES
    assert sum('paced by a recorder' in line for line in node.logger.lines) == 2


def test_the_lead_is_larger_publishing_asynchronously():
    assert pacing.lead_messages({}) == pacing.LEAD_MESSAGES == 256
    assert pacing.lead_messages({'RMW_FASTRTPS_PUBLICATION_MODE': 'SYNCHRONOUS'}) == 256
    assert pacing.lead_messages({'RMW_FASTRTPS_PUBLICATION_MODE': 'ASYNCHRONOUS'}) \
        == pacing.ASYNC_LEAD_MESSAGES == 512
    # the variable means nothing to another middleware: the lead stays
    assert pacing.lead_messages({'RMW_FASTRTPS_PUBLICATION_MODE': 'ASYNCHRONOUS',
                                 'RMW_IMPLEMENTATION': 'rmw_cyclonedds_cpp'}) == 256

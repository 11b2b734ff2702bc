"""The node's side of the pacing protocol (``contact_sim.ros.pacing.RecorderPace``) without ROS:
a stand-in node whose subscription reports how many recorders publish ``~/recorded``, whose graph
and writers the test sets, and a clock the test moves (START_GRACE and MATCH_WAIT are wall time).
"""
import math
from types import SimpleNamespace

import pytest
from builtin_interfaces.msg import Time
from rclpy.qos import DurabilityPolicy, QoSProfile
from rosgraph_msgs.msg import Clock

from contact_sim.ros import messages as cs_msgs
from contact_sim.ros import pacing

RECORDER = ('/', 'contact_sim_record')


class Subscription:
    topic_name = '/contact_sim/recorded'

    def __init__(self):
        self.publishers = 0

    def get_publisher_count(self):
        return self.publishers


class Logger:
    def __init__(self):
        self.lines = []

    def info(self, text):
        self.lines.append(text)

    warning = info


class Writer:
    """One of the node's publishers: its topic and the readers it has matched."""

    def __init__(self, topic):
        self.topic_name, self.qos_profile, self.matched = topic.resolve('/contact_sim'), \
            topic.qos, 0

    def get_subscription_count(self):
        return self.matched


class Node:
    def __init__(self):
        self.subscription, self.logger = Subscription(), Logger()
        self.publishers = []    # the node's writers (Writer)
        self.readers = {}       # topic -> [(namespace, name, qos)] as the graph shows them

    def create_subscription(self, msg_type, name, callback, qos, event_callbacks=None):
        self.callback = callback
        self.liveliness = event_callbacks.liveliness
        return self.subscription

    def get_logger(self):
        return self.logger

    def get_fully_qualified_name(self):
        return '/contact_sim'

    def get_publishers_info_by_topic(self, topic):
        assert topic == self.subscription.topic_name
        return [SimpleNamespace(node_namespace=RECORDER[0], node_name=RECORDER[1])] \
            if self.subscription.publishers else []

    def get_subscriptions_info_by_topic(self, topic):
        return [SimpleNamespace(node_namespace=ns, node_name=name, qos_profile=qos)
                for ns, name, qos in self.readers.get(topic, [])]


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


def test_a_recorder_ready_waits_until_this_nodes_writers_have_matched_it(clock):
    """Issue 33: the recorder said ready once its readers had matched the node's writers, the
    node published a lead's worth, and its writers had not matched the readers yet: ticks 1-32
    never reached the bag. Now the node waits for its own writers to match what the graph shows
    on each recorded topic (the recorder's readers among them)."""
    sent = [0]
    node, pace, rooms = make(sent)
    writers = [Writer(topic) for topic in cs_msgs.TOPICS]
    node.publishers = writers
    node.subscription.publishers = 1
    ack(node, pacing.READY_NS)
    assert pace.room() == 0                      # the graph shows none of the recorder's readers
    for writer in writers:
        node.readers[writer.topic_name] = [(*RECORDER, cs_msgs.RECORD_QOS)]
    assert pace.room() == 0                      # shown, but no writer has matched them
    assert sorted(pace.unmatched()) == sorted(w.topic_name for w in writers)
    for writer in writers[:-1]:
        writer.matched = 1
    assert pace.unmatched() == [writers[-1].topic_name] and pace.room() == 0
    # another reader whose QoS cannot match (transient-local from a volatile writer) is not
    # waited for; one that can is
    wrench = writers[0]
    late = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
    node.readers[wrench.topic_name].append(('/', 'viewer', late))
    writers[-1].matched = 1
    assert pace.unmatched() == []
    node.readers[wrench.topic_name].append(('/', 'plotter', cs_msgs.RECORD_QOS))
    assert pace.unmatched() == [wrench.topic_name]
    wrench.matched = 2
    ack(node, pacing.READY_NS)
    assert pace.room() == pacing.LEAD_MESSAGES and rooms


def test_the_wait_for_matching_writers_is_bounded_and_said(clock):
    node, pace, _ = make([0])
    node.publishers = [Writer(cs_msgs.TOPIC['pose'])]
    node.subscription.publishers = 1
    ack(node, pacing.READY_NS)
    assert pace.room() == 0
    clock[0] += pacing.MATCH_WAIT + 0.01
    assert pace.room() == pacing.LEAD_MESSAGES
    assert any('has not matched /contact_sim/pose after' in line for line in node.logger.lines)


def test_a_recorder_whose_liveliness_is_lost_is_gone_at_once(clock):
    """Issue 33: a flat-out node froze ~20 s after its recorder was killed (the graph keeps a
    killed participant for its lease); the recorder's liveliness lease says so within 1.5 s."""
    sent = [0]
    node, pace, rooms = make(sent)
    node.subscription.publishers = 1
    ack(node, pacing.READY_NS)
    clock[0] += pacing.START_GRACE + 0.01
    sent[0] = 10_000                             # far past the lead: paused
    pace.mark(1_000_000_000)
    assert pace.room() <= 0 and not pace.drained() and pace.unacknowledged() == 10_000
    rooms.clear()
    node.liveliness(SimpleNamespace(alive_count=0, not_alive_count=1, alive_count_change=-1,
                                    not_alive_count_change=1))
    assert pace.recorders() == 0                 # though the graph still shows it
    assert rooms and pace.room() == math.inf and pace.drained()
    assert any('the recorder is gone' in line for line in node.logger.lines)

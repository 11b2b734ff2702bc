"""Pacing by a recorder, the node's side: a node running as fast as possible publishes no more
than ``LEAD_MESSAGES`` messages beyond what ``contact_sim_record`` has acknowledged recording.

The protocol (the recorder's side is ``recorder.Recorder.report``):

1. The recorder publishes on ``~/recorded`` (``rosgraph_msgs/Clock``, reliable, transient-local,
   depth 1) the simulated time up to which every per-tick topic it subscribes to with a matched
   publisher is recorded (``Topic.paced``: the sample and state topics and /clock). Before it
   has recorded something on each of them, but once every one has a matched publisher, it
   publishes ``READY_NS`` (0): "ready, nothing of yours yet". It acknowledges after every
   ``recorder.ACK_EVERY`` messages it records, and every ``recorder.REPORT_PERIOD`` s.
2. The node counts the messages it publishes on those topics and notes, after each engine call,
   (the last tick end published, the count so far). An acknowledgement of time t releases every
   note stamped at or before t; ``READY_NS`` releases everything published so far (what went out
   before the recorder matched is not the recorder's to acknowledge). The node publishes while
   fewer than ``LEAD_MESSAGES`` (``ASYNC_LEAD_MESSAGES`` publishing asynchronously) are
   unreleased, and pauses otherwise, until the next acknowledgement or until the recorder goes
   away. It publishes in engine calls of half the lead at most (``RecorderPace.call``:
   ``CALL_MESSAGES`` of the synchronous lead), counted as ``loop.TICK_MESSAGES`` a tick (contact
   points add 3 messages each, at most ``loop.TURN_STEP_BUDGET`` integrator steps' worth a
   call), one a turn of its executor, so that the acknowledgement of one call comes back while
   the next is computed and published: the two processes work at once (measured at rest,
   ``bench/bench_recording.py``: one call of the whole lead a turn of 20 ms let both wait about
   two thirds of the time). The first acknowledgement after the
   recorder was missed (not seen by ``watch``) releases everything too, like ``READY_NS``.
3. Why messages and not ticks: Fast DDS delivers between processes of one machine through a
   shared-memory port whose queue holds 512 messages by default; a burst larger than that is,
   most likely, dropped there and repaired by the reliable protocol only at a later heartbeat,
   and the node, waiting for an acknowledgement of what is being repaired, stalls (measured:
   a lead of 300 ticks, 2,400 messages at rest, ran at 1.2x real time with both processes
   under 6 % of a core; 30 ticks, 6.2x; docs/ros.md). A tick at rest is 8 messages, a tick of
   the settling up to ~2,700: only a count of messages bounds the burst.
4. At the start, a node running as fast as possible publishes nothing for ``START_GRACE`` s of
   wall time unless it has discovered a recorder (then it waits for its ``READY_NS``), so that a
   recorder started first records from t = 0. The recorder says ``READY_NS`` once its readers
   have matched the node's writers; the node's writers may match the readers later (DDS
   discovery goes both ways, each at its own pace), and a writer sends nothing to a reader it
   has not matched: what the node published meanwhile never reached the bag (ticks 1-32, a
   lead's worth, missing under load, issue 33). So a recorder found, the node also waits until
   its own writers have matched every subscription the graph shows on each topic it records
   (those whose QoS can match; the recorder's among them: ``unmatched``), at most
   ``MATCH_WAIT`` s (then it says which topics it gave up on and goes on).
5. At a stop of the node (``drained``), it publishes nothing more and waits until the recorder
   has acknowledged everything it published, so a node stopped first leaves nothing out of the
   bag. At a stop of the recorder, the recorder's acknowledgement stands still until it is gone
   (``recorder.Recorder.cut``).
6. A recorder killed is gone for the graph only after its participant's lease (about 20 s; the
   node froze that long): ``~/recorded`` has liveliness AUTOMATIC with a lease of
   ``messages.RECORDER_LEASE`` s, and the node counts a recorder whose liveliness is lost as gone
   at once (logged), within the lease.
"""
import math
import os
import time
from collections import deque

from rclpy.event_handler import SubscriptionEventCallbacks
from rclpy.qos import QoSCompatibility, qos_check_compatible

from .messages import PROGRESS, RECORDER_LEASE, TOPICS

LEAD_MESSAGES = 256   # unacknowledged messages on the paced topics (< the 512 of a shm port)
CALL_MESSAGES = LEAD_MESSAGES // 2   # messages of one engine call while paced (as ticks)
# Publishing asynchronously (startup.publication_mode), Fast DDS's sending thread sends what has
# queued together, several samples a shared-memory message, and the lead can be larger (still
# below the 1,000 samples the state topics' writers keep). Measured with
# bench/bench_recording.py --recorded-only --scenario bouncing, alternately, load 2.6-3.1:
# 10.7-13.0x with 512, 9.2-9.4x with 256.
ASYNC_LEAD_MESSAGES = 512
START_GRACE = 3.0     # s of wall time a flat-out node waits at its start for a recorder
READY_NS = 0          # an acknowledgement of nothing: the recorder is ready
MISSES = 2            # looks in a row without a recorder before it counts as gone
MATCH_WAIT = 10.0     # s of wall time a node waits for its writers to match a recorder found


def lead_messages(environ=os.environ):
    """The lead (messages): ``ASYNC_LEAD_MESSAGES`` when the process publishes asynchronously
    through Fast DDS (``RMW_FASTRTPS_PUBLICATION_MODE=ASYNCHRONOUS`` and the default or an
    ``rmw_fastrtps*`` ``RMW_IMPLEMENTATION``), else ``LEAD_MESSAGES``."""
    fast_dds = environ.get('RMW_IMPLEMENTATION', 'rmw_fastrtps_cpp').startswith('rmw_fastrtps')
    asynchronous = environ.get('RMW_FASTRTPS_PUBLICATION_MODE') == 'ASYNCHRONOUS'
    return ASYNC_LEAD_MESSAGES if asynchronous and fast_dds else LEAD_MESSAGES


class RecorderPace:
    """How far a node running as fast as possible may run ahead of its recorder.

    Parameters
    ----------
    node : rclpy.node.Node
        The node (the subscription to ``~/recorded`` is made on it).
    sent : callable
        () -> int: the messages published so far on the paced topics.
    on_room : callable
        Called (no arguments) when an acknowledgement makes room.
    lead : int, optional
        The messages it may publish beyond the acknowledged (default ``lead_messages()``).

    Attributes
    ----------
    lead : int
        As given.
    call : int
        Half the lead: the messages of one engine call while paced.

    Examples
    --------
    A node publishing flat out asks ``room()`` before each engine call, ``mark(ns)`` after it;
    without a recorder (after ``START_GRACE``) the room is infinite.
    """

    def __init__(self, node, sent, on_room, lead=None):
        self.lead = lead_messages() if lead is None else lead   # messages ahead at most
        self.call = self.lead // 2    # messages of one engine call while paced
        self._subscription = node.create_subscription(
            PROGRESS.msg_type, PROGRESS.name, self._on_ack, PROGRESS.qos,
            event_callbacks=SubscriptionEventCallbacks(liveliness=self._on_liveliness))
        self._node = node
        self._sent, self._on_room = sent, on_room
        self._logger = node.get_logger()
        self._not_alive = 0       # recorders matched whose liveliness is lost (killed)
        self._matched = False     # this node's writers have matched the recorder's readers
        self._match_since = None  # when the wait for them began (s, steady clock)
        self._marks = deque()     # (stamp ns, messages sent up to it), not yet acknowledged
        self._acked = 0           # messages sent that the recorder has acknowledged
        self.recorded_ns = None   # the recorder's last acknowledgement (ns); None: none yet
        self._started = time.monotonic()
        self._grace_until = self._started + START_GRACE
        self._present = False     # a recorder was there at the last looks (``watch``)
        self._missed = 0          # looks in a row without a recorder
        self._unpaced_said = False

    def recorders(self):
        """The number of recorders pacing this node: publishers of ``~/recorded``, less those
        whose liveliness is lost."""
        return max(0, self._subscription.get_publisher_count() - self._not_alive)

    def _on_liveliness(self, info):
        """A recorder's liveliness changed: one lost (killed) is gone at once (the graph keeps
        it for its participant's lease, ~20 s)."""
        self._not_alive = info.not_alive_count
        if info.not_alive_count_change > 0 and self._present and self.recorders() == 0:
            self._present, self._missed = False, MISSES
            self._logger.warning(
                f'the recorder is gone (no sign of life for {RECORDER_LEASE:g} s, killed?): '
                'publishing unpaced; what it had not acknowledged may be missing from its bag')
            self._on_room()

    def unmatched(self):
        """The topics recorded (``messages.TOPICS``) on which this node's writer has not yet
        matched every subscription the graph shows whose QoS can match, or on which the graph
        shows no subscription of the recorder yet (/clock excepted: ``--no-clock``).

        Returns
        -------
        list of str
            Full topic names (empty once every one is matched).
        """
        node = self._node
        recorders = {(i.node_namespace, i.node_name) for i in
                     node.get_publishers_info_by_topic(self._subscription.topic_name)}
        recorded = {topic.resolve(node.get_fully_qualified_name()) for topic in TOPICS}
        waiting = []
        for publisher in node.publishers:
            name = publisher.topic_name
            if name not in recorded:
                continue
            readers = node.get_subscriptions_info_by_topic(name)
            mine = any((i.node_namespace, i.node_name) in recorders for i in readers)
            can_match = sum(1 for i in readers if qos_check_compatible(
                publisher.qos_profile, i.qos_profile)[0] != QoSCompatibility.ERROR)
            if (not mine and name != '/clock') or publisher.get_subscription_count() < can_match:
                waiting.append(name)
        return waiting

    def _writers_matched(self):
        """Whether this node's writers have matched the recorder (``unmatched``), or the wait
        for them has run out (``MATCH_WAIT``, logged with the topics given up on)."""
        if self._matched:
            return True
        now = time.monotonic()
        if self._match_since is None:
            self._match_since = now
        waiting = self.unmatched()
        if waiting and now - self._match_since < MATCH_WAIT:
            return False
        self._matched = True
        if waiting:
            self._logger.warning(f'the recorder has not matched {", ".join(waiting)} after '
                                 f'{MATCH_WAIT:g} s: publishing; its bag may miss what goes out '
                                 'there before it does')
        return True

    def watch(self):
        """Look whether a recorder is there (a graph query, ~tens of us: done by a timer, every
        ``loop.WATCH_PERIOD``, and while waiting at the start, not before every engine call).
        A recorder found counts as gone after ``MISSES`` looks in a row without it, so that a
        graph query that misses it once does not let the node loose."""
        if self.recorders() > 0:
            self._present, self._missed = True, 0
        else:
            self._missed += 1
            self._present = self._present and self._missed < MISSES

    def room(self):
        """Messages the node may still publish: ``math.inf`` without a recorder (after the
        start's grace), 0 while a recorder has not said it is ready."""
        if not self._present and time.monotonic() < self._grace_until:
            self.watch()
        if not self._present:
            if self.recorded_ns is not None:   # the recorder went away: a next one starts afresh
                self.recorded_ns = None
                self._marks.clear()
            self._matched, self._match_since = False, None
            if time.monotonic() < self._grace_until:
                return 0
            if not self._unpaced_said:
                self._unpaced_said = True
                self._logger.info(f'no recorder found within {START_GRACE:g} s: publishing '
                                  'unpaced (a recorder started now records from where it joins)')
            return math.inf
        if self.recorded_ns is None or not self._writers_matched():
            return 0
        return self.lead - (self._sent() - self._acked)

    def mark(self, stamp_ns):
        """After an engine call: the tick ends sent so far reach ``stamp_ns`` (ns). (Contact
        samples of a tick begun are counted with it: released up to one engine call early, but
        an acknowledgement of the tick ends, which every per-tick topic reaches, always comes.)"""
        if self.recorded_ns is not None:
            self._marks.append((stamp_ns, self._sent()))

    def drained(self):
        """True when no recorder waits for anything this node has published."""
        return self.recorders() == 0 or self.recorded_ns is None or self._acked >= self._sent()

    def unacknowledged(self):
        """Messages published that a recorder has not acknowledged yet (0 without one)."""
        return 0 if self.drained() else self._sent() - self._acked

    def _on_ack(self, msg):
        ns = PROGRESS.stamp_ns(msg)
        self._present = True
        if self.recorded_ns is None:
            self._logger.info(f'paced by a recorder (its first acknowledgement '
                              f'{time.monotonic() - self._started:.2f} s after the start)')
            self._matched, self._match_since = False, None   # a new recorder: match it first
        if ns == READY_NS or self.recorded_ns is None:
            # ready; or a recorder found again after it was missed (what went out meanwhile has
            # no note to release it: waiting for one would stall the node for good)
            self._marks.clear()
            self._acked = self._sent()
        marks = self._marks
        while marks and marks[0][0] <= ns:
            self._acked = marks.popleft()[1]
        self.recorded_ns = ns
        if self.room() > 0:
            self._on_room()

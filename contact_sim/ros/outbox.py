"""The node's outbox: a publisher per topic of ``messages.TOPICS`` with its CDR encoder, the
publishing of the engine's results (``DropSimulation.advance_ticks`` batches) on them, and the
wait for reliable readers.

What is published. Each engine call's contact points and tick ends go, in time order, on
~/wrench, ~/contact and ~/plate_wrench (-F); each completed impact on ~/impact; each tick's end on
~/pose, ~/twist (absolute: p + R1 - z, pdot - zdot), ~/plate_pose, ~/plate_twist and /clock.
Stamps strictly increase per topic; nothing non-finite is published (it is counted and logged).

Waiting for readers. A reliable reader that falls behind makes the middleware refuse a publish
once the writer's history is full of samples it has not acknowledged; the outbox then keeps that
message and the rest of its tick (``pending``), and the node publishes them, in order, at its
next turn (``send_pending``): it waits for its readers instead of dropping samples (best-effort
readers, such as ``ros2 topic hz``, are not waited for).
"""
import math

import numpy as np
import rclpy
from rclpy.duration import Duration
from rclpy.impl.implementation_singleton import rclpy_implementation as _rclpy
from rclpy.serialization import serialize_message

from contact_sim.drop import sphere_motion

from .messages import TOPICS, contact_samples, impact_msg, impact_ok, sample_columns, to_ns, \
    to_ns_array

SMALL_BATCH = 8          # up to this many ticks without contact points are published one by one


class Outbox:
    """The node's publishers and what waits for a reliable reader's room.

    Parameters
    ----------
    node : rclpy.node.Node
        The node the publishers belong to (its context and logger are used).
    frame_id : str
        The frame of every stamped message.
    publish_clock : bool
        Whether /clock is published.

    Attributes
    ----------
    pending : list of (str, bytes)
        (topic key, serialized message) a reliable reader has not had room for yet, in order.
    sent : int
        Messages handed to the per-tick topics (samples, states, /clock) so far, waiting ones
        included (what a recorder's acknowledgement counts: ``pacing.RecorderPace``).
    """

    def __init__(self, node, frame_id, publish_clock):
        self._context = node.context
        self._logger = node.get_logger()
        self._last_sample_ns = -1
        self._last_state_ns = -1
        self._pub, self._encode, self._raw = {}, {}, {}
        for topic in TOPICS:
            if topic.kind == 'clock' and not publish_clock:
                continue
            self._pub[topic.key] = node.create_publisher(topic.msg_type, topic.name, topic.qos)
            # serialized bytes straight to the publisher's handle: rclpy's Publisher.publish
            # adds about 8 us a message of Python (its type checks and the handle's guard)
            self._raw[topic.key] = self._pub[topic.key].handle.publish_raw
            if topic.fields or topic.kind == 'clock':
                self._encode[topic.key] = topic.template(frame_id).packer()
        self.pending = []
        self.sent = 0

    @property
    def tick_ns(self):
        """The stamp (ns) of the last tick end published (on every per-tick topic); -1 before
        any. (The sample topics may be further on, inside the next tick.)"""
        return self._last_state_ns

    @property
    def publishes_clock(self):
        """Whether this outbox publishes /clock."""
        return 'clock' in self._pub

    def stop_clock(self, node):
        """Stop publishing /clock (another node publishes it): its publisher is destroyed and
        the clock messages waiting for a reader are dropped."""
        self.pending = [(key, data) for key, data in self.pending if key != 'clock']
        self._encode.pop('clock', None)
        self._raw.pop('clock', None)
        node.destroy_publisher(self._pub.pop('clock'))

    def wait_for_readers(self, key, timeout):
        """Wait at most ``timeout`` s until every reliable reader of ``key`` has acknowledged
        what it was sent (the middleware's own acknowledgement: used at a stop); whether they
        all have (True without a reader)."""
        publisher = self._pub.get(key)
        if publisher is not None and publisher.get_subscription_count():
            return publisher.wait_for_all_acked(Duration(seconds=timeout))
        return True

    def pending_count(self):
        """Messages waiting for a reliable reader's room (``pending``)."""
        return len(self.pending)

    def send(self, key, data):
        """Publish, or keep ``data`` for the next turn if a reliable reader has had no room for
        this topic's samples within the middleware's blocking time (the writer's history is
        full of samples it has not acknowledged): the node waits for its readers."""
        if self.pending:
            self.pending.append((key, data))
            return
        try:
            self._raw[key](data)
        except _rclpy.RCLError:
            if not rclpy.ok(context=self._context):
                raise
            self.pending.append((key, data))

    def send_pending(self):
        """Publish what waits, in order; True when all of it went out."""
        pending, self.pending = self.pending, []
        for i, (key, data) in enumerate(pending):
            try:
                self._raw[key](data)
            except _rclpy.RCLError:
                if not rclpy.ok(context=self._context):
                    raise
                self.pending = pending[i:]
                return False
        return True

    def publish_batch(self, batch, offset, radius):
        """Publish one engine call: on the sample topics every contact point passed and each
        tick's end, in time order; each completed impact; each tick's end on the state topics
        and /clock. Stamps strictly increase per topic; nothing non-finite is published.

        Parameters
        ----------
        batch : contact_sim.drop.TickBatch
            What one ``DropSimulation.advance_ticks`` call passed.
        offset : float
            s: the stamp of the drop's time 0 (simulated time = offset + the drop's time).
        radius : float
            m: the sphere's radius (its height is p + radius - z).
        """
        n, points = batch.ticks, batch.points
        if not points.time.size and not batch.impacts and n <= SMALL_BATCH:
            self._publish_few(batch, offset, radius)
            return
        if points.time.size:
            key = np.concatenate([2 * batch.point_tick, 2 * np.arange(n) + 1])
            order = np.argsort(key, kind='stable')
            columns = [np.concatenate([getattr(points, f), getattr(batch, f)[:n]])[order]
                       for f in ('time', 'penetration', 'penetration_rate', 'force')]
        else:
            columns = [batch.time, batch.penetration, batch.penetration_rate, batch.force]
        ns, z, zdot, force, skipped = sample_columns(*columns, offset, self._last_sample_ns)
        if ns:
            self._publish_samples(ns, z, zdot, force)
        for record in batch.impacts:
            message = impact_msg(record, offset)
            if impact_ok(message):
                self.send('impact', serialize_message(message))
            else:
                skipped += 1
        if n:
            end_ns = to_ns_array(offset + batch.time)
            finite = np.isfinite(batch.time) & np.isfinite(batch.penetration) & np.isfinite(
                batch.penetration_rate)
            keep = finite & (end_ns > self._last_state_ns)
            if not keep.all() or np.any(end_ns[1:] <= end_ns[:-1]):
                keep = self._increasing(end_ns, keep)
            if keep.any():
                p, pv = batch.plate_position[keep], batch.plate_velocity[keep]
                height, velocity = sphere_motion(radius, batch.penetration[keep],
                                                 batch.penetration_rate[keep], p, pv)
                self._publish_states(end_ns[keep].tolist(), height.tolist(), velocity.tolist(),
                                     p.tolist(), pv.tolist())
        self._warn_skipped(skipped)

    def _publish_few(self, batch, offset, radius):
        """``publish_batch`` of a few ticks without contact points (flight, rest), element by
        element: numpy's per-call cost exceeds the work there."""
        samples, skipped = contact_samples(batch, offset, self._last_sample_ns)
        if samples:
            self._publish_samples(*zip(*samples))
        states, last = [], self._last_state_ns
        for t, z, zdot, p, pv in zip(batch.time.tolist(), batch.penetration.tolist(),
                                     batch.penetration_rate.tolist(),
                                     batch.plate_position.tolist(), batch.plate_velocity.tolist()):
            if math.isfinite(t + z + zdot):
                ns = to_ns(offset + t)
                if ns > last:
                    states.append((ns, *sphere_motion(radius, z, zdot, p, pv), p, pv))
                    last = ns
        if states:
            self._publish_states(*zip(*states))
        self._warn_skipped(skipped)

    def _publish_samples(self, ns, z, zdot, force):
        """Contact samples (stamps ns increasing past the last published; z, zdot, F) on
        ~/wrench, ~/contact and ~/plate_wrench (the reaction -F)."""
        self._last_sample_ns = ns[-1]
        self._publish_many('wrench', ns, force)
        self._publish_many('contact', ns, z, zdot, [1.0 if f > 0.0 else 0.0 for f in force])
        self._publish_many('plate_wrench', ns, [-f for f in force])

    def _publish_states(self, ns, height, velocity, plate_position, plate_velocity):
        """Tick ends (stamps ns increasing past the last published): the sphere's absolute
        height and velocity, the plate's, and /clock."""
        self._last_state_ns = ns[-1]
        self._publish_many('pose', ns, height)
        self._publish_many('twist', ns, velocity)
        self._publish_many('plate_pose', ns, plate_position)
        self._publish_many('plate_twist', ns, plate_velocity)
        if 'clock' in self._encode:
            self._publish_many('clock', ns)

    def _warn_skipped(self, skipped):
        if skipped:
            self._logger.warning(f'skipped {skipped} non-finite values',
                                      throttle_duration_sec=5.0)

    def _increasing(self, stamps, keep):
        """``keep`` narrowed to stamps strictly increasing past the last state published."""
        last = self._last_state_ns
        out = np.zeros_like(keep)
        for i, (ns, ok) in enumerate(zip(stamps.tolist(), keep.tolist())):
            if ok and ns > last:
                out[i], last = True, ns
        return out

    def _publish_many(self, key, *columns):
        """Encode and publish one message per row of ``columns`` (stamp ns, values) on ``key``;
        from the first refusal by a reliable reader on, keep the rest for the next turn (in
        order, after what already waits: see ``send``)."""
        encode = self._encode[key]
        self.sent += len(columns[0])
        rows = zip(*columns)
        pending = self.pending
        if pending:
            pending.extend((key, encode(*row)) for row in rows)
            return
        publish = self._raw[key]
        for row in rows:
            data = encode(*row)
            try:
                publish(data)
            except _rclpy.RCLError:
                if not rclpy.ok(context=self._context):
                    raise
                pending.append((key, data))
                pending.extend((key, encode(*rest)) for rest in rows)
                return


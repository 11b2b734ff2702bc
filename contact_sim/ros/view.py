"""The node's topics for viewers (``messages.VIEW_TOPICS``): ``~/markers`` (``markers``) at the
ticks it publishes and ``/diagnostics`` (``diagnostics``) once a wall second.

Markers: in real time one MarkerArray per tick, from the tick's end (the publish rate); as fast as
possible the last tick of an engine call, at most ``publish_rate`` a wall second (more than a
viewer draws would only slow the run). A viewer that falls behind loses old arrays: a refused
publish is dropped, never waited for (the samples of record are on the other topics). Without a
subscriber no array is built (the topic is volatile: a viewer that comes later gets the next
one either way): building and converting one costs about 0.3-1 ms, measured with cProfile of a
flat-out node recorded while bouncing (``bench/bench_recording.py``'s setting), some 10 % of
its CPU at 100 arrays a second.
"""
import math
import time

import rclpy

from contact_sim.drop import sphere_motion

from .diagnostics import PERIOD, Progress, Schedule, diagnostics_msg, mode_of, rates
from .markers import markers_msg
from .messages import VIEW_TOPICS, to_ns
from .rclpy_private import RCLError


class View:
    """Publishers of ``~/markers`` and ``/diagnostics`` for ``ContactSimNode``.

    Parameters
    ----------
    node : rclpy.node.Node
        Creates the publishers and the diagnostics timer; its name is the status's.
    clock : rclpy.clock.Clock
        The steady clock of the diagnostics timer.
    loop : loop.TickLoop
        What the diagnostics report, read through its public attributes: ``sim`` (the running
        ``DropSimulation``), ``offset`` (s), ``settings`` (``params.LoopSettings``), ``lag()``
        and ``paced()``.
    """

    def __init__(self, node, clock, loop):
        self._node, self._loop = node, loop
        self._pub = {topic.key: node.create_publisher(topic.msg_type, topic.name, topic.qos)
                     for topic in VIEW_TOPICS}
        self._last_wall = -math.inf
        self.ticks = 0        # ticks published since the start
        self.steps = 0        # integrator steps of the drops before the running one
        self._before = None   # the progress at the last diagnostics (None: before the start)
        self._schedule = None  # when /diagnostics is due (made at the start, ``begin``)
        # the timer for a node that does not tick (paused); the loop asks after each engine
        # call too (``publish_batch``): flat out, rclpy's events executor delivers this timer
        # late and in bursts (28 in 0.75 s, then none for 12 s; issue 33). Both go by
        # ``_schedule``. (A timer of PERIOD / 10 here stalled every timer of a flat-out node
        # after its start, measured: keep it at PERIOD.)
        node.create_timer(PERIOD, self._diagnostics_if_due, clock=clock)

    def _publish(self, key, msg):
        try:
            self._pub[key].publish(msg)
        except RCLError:
            if not rclpy.ok(context=self._node.context):
                raise

    def publish_batch(self, batch, offset, model, settings):
        """The markers of an engine call's ticks (``DropSimulation.advance_ticks``), stamped
        ``offset`` + the drop's time, drawn from ``model`` (``params.Model``: frame_id, the
        radii, the weight) at the pace of ``settings`` (``params.LoopSettings``), and
        /diagnostics if due."""
        self._diagnostics_if_due()
        n = batch.ticks
        if not n:
            return
        if settings.fast:
            now = time.monotonic()
            if now - self._last_wall < 1.0 / settings.publish_rate:
                return
            self._last_wall = now
            ticks = [n - 1]
        else:
            ticks = range(n)
        if not self._pub['markers'].get_subscription_count():
            return
        weight = model.mass * model.gravity
        for i in ticks:
            t, z, zdot, force = (float(batch.time[i]), float(batch.penetration[i]),
                                 float(batch.penetration_rate[i]), float(batch.force[i]))
            p, pv = float(batch.plate_position[i]), float(batch.plate_velocity[i])
            if not all(math.isfinite(v) for v in (t, z, zdot, force, p, pv)):
                continue
            height = sphere_motion(model.radius, z, zdot, p, pv)[0]
            self._publish('markers', markers_msg(to_ns(offset + t), model.frame_id, model.radius,
                                                 height, p, model.plate_radius, force, weight))

    def begin(self):
        """The loop has started: the diagnostics count from now (called once, by the loop)."""
        if self._before is None:
            self._before = self._progress()
            self._schedule = Schedule(self._before.wall)

    def reset(self, old_sim):
        """A new drop (~/reset): its integrator steps count on from the old one's."""
        self.steps += old_sim.total_steps

    def _progress(self):
        loop = self._loop
        return Progress(time.monotonic(), loop.offset + loop.sim.time,
                        self.steps + loop.sim.total_steps, self.ticks)

    def _diagnostics_if_due(self):
        if self._schedule is not None and self._schedule.due(time.monotonic()):
            self.publish_diagnostics()

    def publish_diagnostics(self):
        """/diagnostics over the wall time since the last one."""
        loop = self._loop
        if self._before is None:
            return    # the loop has not started
        after = self._progress()
        achieved, steps, ticks = rates(self._before, after)
        period = after.wall - self._before.wall
        self._before = after
        settings = loop.settings
        target = math.inf if settings.fast else settings.real_time_factor
        self._publish('diagnostics', diagnostics_msg(
            to_ns(after.simulated), self._node.get_fully_qualified_name(), target, achieved,
            loop.lag(), steps, ticks, mode_of(loop.sim), loop.paced(), period))

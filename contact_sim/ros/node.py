"""``contact_sim_node``: simulates a sphere dropped on a plate and publishes its contact wrench, state
and impacts, stamped with simulated time.

Data flows one way:

    parameters --params.build_model--> Model --make_simulation--> cs.DropSimulation
        --advance--> samples and impact records --messages.TOPICS encoders--> topics

Frames and signs (REP 103, SI units): the plate frame (``frame_id``, default ``plate``) has z up
and the plate's surface (the top of the lower sphere, for two spheres) at z = 0. The sphere moves
along that z axis only. Penetration z > 0 means the undeformed bodies overlap; its rate ż > 0 means
approach. README.md documents every topic, service and parameter.

The plate. ``plate_amplitude`` and ``plate_frequency`` > 0 vibrate it
(``plate.table_transition`` bridges every change); ``~/plate_command``
(trajectory_msgs/JointTrajectory, joint ``plate_z``) drives it otherwise: the node only
translates the message (``read_plate_command``), the rules are ``plate.command_motion``'s;
both go to the engine through ``DropSimulation.set_plate``. ~/pose and ~/twist are absolute
(p + R1 - z, pdot - zdot); ~/plate_pose, ~/plate_twist (once per tick) and ~/plate_wrench (-F, at
every contact sample) show the plate.

The loop. Simulated time is cut into ticks of ``dt`` = real_time_factor / publish_rate s
(1 / publish_rate s when running as fast as possible), counted from an anchor (the start, a
~/reset or a change of real_time_factor). A steady-clock timer (period 1/publish_rate, at least
``WAKE_PERIOD``; 0 when running as fast as possible) runs ``_on_timer``, which works through
every tick that is due: in real time, those whose wall time has come (a late timer costs no
tick: it publishes the missed ones at once; at 100 Hz each wake publishes two ticks, since a
wake of the executor costs about 0.2 ms of CPU); as fast as possible, as many as fit in
``FAST_TURN`` s of wall time. Each tick publishes, on ~/wrench and ~/contact, every contact point
the engine passed and the tick's end; each completed impact; and the tick's end on ~/pose,
~/twist and /clock. The ticks of a turn are advanced together, up to ``BATCH_TICKS`` per engine
call (``DropSimulation.advance_ticks``: flight and rest evaluated over arrays), and each call's
messages are encoded and published topic by topic from its arrays. An engine call takes at most
``TURN_STEP_BUDGET`` integrator steps, and a turn ends when its wall budget is spent (the tick
goes on at the next turn): ``FAST_TURN`` as fast as possible; in real time ``TURN_BASE`` +
``TURN_PER_TICK`` per tick due (at most ``REAL_TURN`` of the period), so that a tick with much
work, such as the settling (about 800 integrator steps and 900 contact points between permanent
contact and the closed-form rest for the default drop), is spread over several turns of the
size of a bouncing one while the node stays within about 0.1 s of real time, and services stay
live. Real time that cannot be held
(more than ``MAX_LAG`` s behind) is logged once, with the tick rate achieved, and the node skips
ahead (the states of the skipped ticks are not published; the contact points are).

Waiting for readers. A reliable reader that falls behind makes the middleware refuse a publish
once the writer's history is full of samples it has not acknowledged; the node then keeps that
message and the rest of its tick and publishes them, in order, at its next turn: it waits for its
readers instead of dropping samples (best-effort readers, such as ``ros2 topic hz``, are not
waited for). DDS acknowledgements alone are too coarse to pace a node running as fast as possible
(Fast DDS acknowledges on its heartbeats: ``Publisher.wait_for_all_acked`` took 1-2 s after as few
as 10 samples), so ``contact_sim_record`` also acknowledges itself: it publishes on ``~/recorded``
(``rosgraph_msgs/Clock``) the simulated time up to which it has recorded every topic, and the
node, running as fast as possible, publishes no tick more than ``LEAD_TICKS`` ticks beyond it
while a recorder is there (it pauses its timer and resumes when the recorder catches up or goes
away). The recorder's subscriptions are keep-all, so nothing is dropped on its side either.
"""
import math
import time

import numpy as np
import rclpy
import rclpy.logging
from rcl_interfaces.msg import ParameterType, ParameterValue, SetParametersResult
from rcl_interfaces.srv import GetParameters
from rclpy.clock import Clock, ClockType
from rclpy.exceptions import ParameterException
from rclpy.executors import ExternalShutdownException
from rclpy.experimental.events_executor import EventsExecutor
from rclpy.impl.implementation_singleton import rclpy_implementation as _rclpy
from rclpy.node import Node
from rclpy.serialization import serialize_message
from std_srvs.srv import Trigger
from trajectory_msgs.msg import JointTrajectory

from contact_sim.drop import command_motion, sphere_motion
from contact_sim.validation import InputError

from .messages import PROGRESS, TOPICS, contact_samples, impact_msg, impact_ok, sample_columns, \
    to_ns, to_ns_array
from .params import DEFAULTS, NODE_NAME, PARAMETER_NAMES, PARAMETERS, build_model, \
    check_running, descriptor, make_simulation, refusal, table_motion
from .query import answer_queries

TURN_STEP_BUDGET = 20    # integrator steps per engine call (~10 ms); then the wall budget is checked
BATCH_TICKS = 256        # ticks per batched engine call (advance_ticks), then the budgets are checked
SMALL_BATCH = 8          # up to this many ticks without contact points are published one by one
FAST_TURN = 0.02         # s of wall time per executor turn when running as fast as possible
REAL_TURN = 0.75         # of the timer period: wall time per turn at most in real time
# In real time a turn's wall budget is TURN_BASE + TURN_PER_TICK per tick due (at most REAL_TURN
# of the period): a tick with much work (the settling's ~1000 contact points) is spread over
# turns, and a node behind real time gets a larger budget to catch up.
TURN_BASE = 0.002        # s
TURN_PER_TICK = 0.0005   # s
WAKE_PERIOD = 0.02       # s: in real time the node wakes at most every 20 ms (50 Hz)
MAX_LAG = 2.0            # s behind real time before the node skips ahead (and says so, once)
LEAD_TICKS = 300         # ticks ahead of a recorder's acknowledgement (< state history 1000)
WATCH_PERIOD = 0.5       # s: a paused node checks this often whether its recorder has gone
PLATE_JOINT = 'plate_z'  # the one joint of ~/plate_command: prismatic, m, up
# the core's fields of a plate command (plate.command_motion) as the message spells them
COMMAND_FIELDS = {'times': 'points[].time_from_start (after header.stamp)',
                  'positions': 'points[].positions', 'velocities': 'points[].velocities'}


class StartupError(Exception):
    """The initial parameters are invalid: the node cannot start."""


class ContactSimNode(Node):
    """Simulates a sphere dropped on a plate and publishes its contact wrench, state and impacts."""

    def __init__(self, **kwargs):
        super().__init__(NODE_NAME, **kwargs)
        try:
            for spec in PARAMETERS:
                self.declare_parameter(spec.name, spec.default, descriptor(spec))
            self._model = build_model(self._values())
        except (ParameterException, ValueError) as error:
            raise StartupError(str(error)) from None
        self._warn_unknown_overrides()
        self._sim = make_simulation(self._model)
        self._offset = 0.0        # s: stamp = offset + simulator time; grows at each ~/reset
        self._last_sample_ns = -1
        self._last_state_ns = -1
        self._steady = Clock(clock_type=ClockType.STEADY_TIME)  # pacing ignores use_sim_time

        frame = self._model.frame_id  # read-only
        self._pub, self._encode = {}, {}
        for topic in TOPICS:
            if topic.kind == 'clock' and not self._model.publish_clock:
                continue
            self._pub[topic.key] = self.create_publisher(topic.msg_type, topic.name, topic.qos)
            if topic.fields or topic.kind == 'clock':
                self._encode[topic.key] = topic.template(frame).packer()
        self.create_service(GetParameters, '~/query_restitution', self._on_query)
        self.create_service(Trigger, '~/reset', self._on_reset)
        self._commanded = False   # the plate follows ~/plate_command (until ~/reset or a table)
        self.create_subscription(JointTrajectory, '~/plate_command', self._on_plate_command, 10)
        self.add_on_set_parameters_callback(self._on_set_parameters)
        self.add_post_set_parameters_callback(self._on_parameters_set)
        self._recorded_ns = None  # the recorder's acknowledgement, see PROGRESS
        self._progress = self.create_subscription(PROGRESS.msg_type, PROGRESS.name,
                                                  self._on_recorded, PROGRESS.qos)
        self._paused = False
        self.create_timer(WATCH_PERIOD, self._resume_if_free, clock=self._steady)
        self._lag_logged = False
        self._pending = []        # (topic key, bytes) a reliable reader has not had room for yet
        self._timer = None
        self._start_loop()
        self.get_logger().info(self._model.summary())

    # ---- parameters ------------------------------------------------------------------------

    def _values(self, changes=()):
        values = {name: self.get_parameter(name).value for name in PARAMETER_NAMES}
        values.update({p.name: p.value for p in changes})
        return values

    def _warn_unknown_overrides(self):
        unknown = sorted(name for name in getattr(self, '_parameter_overrides', {})
                         if not self.has_parameter(name))
        if unknown:
            self.get_logger().warning(f'ignoring unknown parameters: {", ".join(unknown)} '
                                      f'(known: {", ".join(PARAMETER_NAMES)})')

    def _on_set_parameters(self, parameters):
        """Validate a parameter change as a whole; nothing changes unless all of it is valid."""
        ours = [p for p in parameters if p.name in DEFAULTS]
        if not ours:
            return SetParametersResult(successful=True)
        try:
            values = self._values(ours)
            model = build_model(values)
            # a new contact acts from the next contact phase of the running drop
            check_running(self._sim, model, values, self._model)
        except Exception as error:  # any failure rejects the change, never the node
            names = ', '.join(p.name for p in ours)
            return SetParametersResult(successful=False, reason=f'rejected {names}: {error}')
        return SetParametersResult(successful=True)

    def _on_parameters_set(self, parameters):
        """Apply an accepted change: the contact at once (engine: from the next contact)."""
        if not any(p.name in DEFAULTS for p in parameters):
            return
        old = self._model
        try:
            new = build_model(self._values())
        except Exception as error:  # validated already: should not happen; keep running
            self.get_logger().error(f'could not apply the accepted parameters: {error}')
            return
        self._model = new
        log = self.get_logger()
        if new.contact != old.contact:
            self._sim.set_contact(new.contact)
            log.info(f'contact changed, from the next contact phase: {new.summary()}')
        if (new.mass, new.gravity, new.height, new.velocity, new.drag) != \
                (old.mass, old.gravity, old.height, old.velocity, old.drag):
            log.info(f'mass, gravity, drag or initial conditions changed, from the next ~/reset: '
                     f'{new.summary()}')
        if new.table != old.table:
            self._set_table(old.table, new.table)
        if new.real_time_factor != old.real_time_factor:
            self._start_loop()
            log.info(f'real_time_factor = {new.real_time_factor:g}'
                     + (' (as fast as possible)' if new.fast else ''))

    # ---- the plate: vibrating table, ~/plate_command -----------------------------------------

    def _set_table(self, old, new):
        """The table's parameters changed: bridge the plate from where it is (C1, one period;
        ``plate.table_transition``, one period or longer); a running table takes the plate over
        from ~/plate_command."""
        sim, log = self._sim, self.get_logger()
        try:
            sim.set_plate(table_motion(sim, old, new))
        except ValueError as error:  # validated already (check_running): keep running
            log.error(f'could not change the vibrating table: {error}')
            return
        if new is not None and self._commanded:
            self._commanded = False
            log.info('the vibrating table takes the plate over from ~/plate_command')
        log.info('vibrating table ' + (f'a = {new.amplitude:g} m, f = {new.frequency:g} Hz, '
                                       f'phi = {new.phase:g} rad' if new is not None
                                       else 'stopped (the plate comes to rest at p = 0)')
                 + f' from t = {self._offset + sim.time:.6f} s, bridged C1')

    def _on_plate_command(self, msg):
        """A trajectory for the plate (README, "Commanded plate"): translated here, the rules are
        ``plate.command_motion``'s; a refusal is a warning and changes nothing."""
        log, sim = self.get_logger(), self._sim
        table = self._model.table
        if table is not None:
            log.warning(f'~/plate_command refused: the vibrating table runs (plate_amplitude = '
                        f'{table.amplitude:g}, plate_frequency = {table.frequency:g} > 0); '
                        'allowed only with plate_amplitude = 0 or plate_frequency = 0',
                        throttle_duration_sec=5.0)
            return
        try:
            times, positions, velocities = read_plate_command(msg, sim.time, self._offset)
            state = sim.state
            command = command_motion(sim.time, state.plate_position, state.plate_velocity,
                                     times, positions, velocities)
            if command.dropped:
                log.warning(f'~/plate_command: dropped {command.dropped} point(s) at or before '
                            f'now (t = {self._offset + sim.time:.6f} s)',
                            throttle_duration_sec=5.0)
            if command.motion is None:
                log.warning('~/plate_command ignored: no point after now (t = '
                            f'{self._offset + sim.time:.6f} s)', throttle_duration_sec=5.0)
                return
        except InputError as error:
            log.warning(f'~/plate_command refused: {error.render(COMMAND_FIELDS)}',
                        throttle_duration_sec=1.0)
            return
        except ValueError as error:
            log.warning(f'~/plate_command refused: {error}', throttle_duration_sec=1.0)
            return
        try:
            sim.set_plate(command.motion)
        except InputError as error:   # the drop's own limits (the depth check, gravity)
            why = refusal(error, self._values())
            if error.field in ('stiffness', 'damping'):
                why = ('the commanded motion (points[].velocities, peak plate speed '
                       f'{command.motion.speed_bound():.6g} m/s) is too fast for the running '
                       f'drop: {why}')
            log.warning(f'~/plate_command refused: {why}', throttle_duration_sec=1.0)
            return
        self._commanded = True

    # ---- simulation loop -------------------------------------------------------------------

    def _start_loop(self):
        """(Re)start the loop timer and anchor tick 0 at the current simulated and wall time."""
        model = self._model
        self._anchor_wall, self._anchor_sim, self._tick = time.monotonic(), self._sim.time, 0
        self._dt = 1.0 / model.publish_rate if model.fast \
            else model.real_time_factor / model.publish_rate
        if self._timer is not None:
            self.destroy_timer(self._timer)
        self._paused = False
        period = 0.0 if model.fast else max(1.0 / model.publish_rate, WAKE_PERIOD)
        self._period = period
        self._timer = self.create_timer(period, self._on_timer, clock=self._steady)

    def _ticks_due(self, now):
        """Ticks (since the anchor) whose wall time has come; every one when running flat out."""
        if self._model.fast:
            return math.inf
        return int((now - self._anchor_wall) * self._model.publish_rate)

    def _on_timer(self):
        try:
            self._turn()
        except Exception:
            if rclpy.ok(context=self.context):
                raise
            # Ctrl-C shut the context down during the turn (rclpy's handler runs in its own
            # thread): the publishers are gone; spin() returns next

    def _turn(self):
        if self._pending and not self._send_pending():
            return   # a reliable reader still has no room: the next turn tries again
        start = time.monotonic()
        fast = self._model.fast
        due = self._ticks_due(start)
        deadline = start + (FAST_TURN if fast else min(
            REAL_TURN * self._period, TURN_BASE + TURN_PER_TICK * max(due - self._tick, 0)))
        if fast:
            due = min(due, self._ticks_allowed())
            if due <= self._tick:   # a recorder is behind: wait for it (see _on_recorded)
                self._timer.cancel()
                self._paused = True
                return
        elif due - self._tick > MAX_LAG * self._model.publish_rate:
            self._skip_ahead(due, start)
        while self._tick < due:
            if not self._run_ticks(min(due, self._tick + BATCH_TICKS), deadline):
                return    # out of wall time inside the tick: the next turn goes on with it
            if self._pending or time.monotonic() > deadline:
                return

    def _send(self, key, data):
        """Publish, or keep ``data`` for the next turn if a reliable reader has had no room for
        this topic's samples within the middleware's blocking time (the writer's history is
        full of samples it has not acknowledged): the node waits for its readers."""
        if self._pending:
            self._pending.append((key, data))
            return
        try:
            self._pub[key].publish(data)
        except _rclpy.RCLError:
            if not rclpy.ok(context=self.context):
                raise
            self._pending.append((key, data))

    def _send_pending(self):
        """Publish what waits, in order; True when all of it went out."""
        pending, self._pending = self._pending, []
        for i, (key, data) in enumerate(pending):
            try:
                self._pub[key].publish(data)
            except _rclpy.RCLError:
                if not rclpy.ok(context=self.context):
                    raise
                self._pending = pending[i:]
                return False
        return True

    def _ticks_allowed(self):
        """Ticks (since the anchor) a recorder lets the node publish: LEAD_TICKS beyond what it
        has acknowledged; unlimited without a recorder or before its first acknowledgement."""
        if self._recorded_ns is None or self._progress.get_publisher_count() == 0:
            return math.inf
        recorded = self._recorded_ns * 1e-9 - self._offset - self._anchor_sim
        return max(0, math.floor(recorded / self._dt + 1e-6)) + LEAD_TICKS

    def _on_recorded(self, msg):
        self._recorded_ns = PROGRESS.stamp_ns(msg)
        if self._paused and self._ticks_allowed() > self._tick:
            self._resume()

    def _resume_if_free(self):
        if self._paused and self._ticks_allowed() > self._tick:
            self._resume()

    def _resume(self):
        self._paused = False
        self._timer.reset()

    def _skip_ahead(self, due, now):
        """Real time cannot be held: say so once, with the rate achieved, and jump to ``due``."""
        if not self._lag_logged:
            self._lag_logged = True
            achieved = self._tick / max(now - self._anchor_wall, 1e-9)
            self.get_logger().warning(
                f'publish_rate {self._model.publish_rate:g} Hz at real_time_factor '
                f'{self._model.real_time_factor:g} cannot be held: {achieved:.0f} ticks/s achieved;'
                f' skipping ahead (the states of skipped ticks are not published; logged once)')
        self._tick = due - 1

    def _run_ticks(self, upto, deadline):
        """Advance through ticks up to ``upto`` (since the anchor) in batched engine calls
        (``DropSimulation.advance_ticks``, ``TURN_STEP_BUDGET`` integrator steps each) and
        publish them; False if the wall budget ran out first (what was integrated so far is
        published; the rest goes on at the next turn)."""
        sim = self._sim
        times = self._anchor_sim + np.arange(self._tick + 1, upto + 1) * self._dt
        done = 0
        while done < times.size:
            try:
                batch = sim.advance_ticks(times[done:], max_steps=TURN_STEP_BUDGET)
            except Exception as error:  # keep the node alive and the last good state
                target = float(times[done])
                self.get_logger().error(f'simulation step to t = {target:.9f} s failed: {error}',
                                        throttle_duration_sec=5.0)
                self._tick += 1
                return True
            self._publish_batch(batch)
            done += batch.ticks
            self._tick += batch.ticks
            if done < times.size and time.monotonic() > deadline:
                return False
        return True

    def _publish_batch(self, batch):
        """Publish one engine call: on the sample topics every contact point passed and each
        tick's end, in time order; each completed impact; each tick's end on the state topics
        and /clock. Stamps strictly increase per topic; nothing non-finite is published."""
        offset = self._offset
        n, points = batch.ticks, batch.points
        if not points.time.size and not batch.impacts and n <= SMALL_BATCH:
            self._publish_few(batch)
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
                self._send('impact', serialize_message(message))
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
                height, velocity = sphere_motion(self._model.radius, batch.penetration[keep],
                                                 batch.penetration_rate[keep], p, pv)
                self._publish_states(end_ns[keep].tolist(), height.tolist(), velocity.tolist(),
                                     p.tolist(), pv.tolist())
        self._warn_skipped(skipped)

    def _publish_few(self, batch):
        """``_publish_batch`` of a few ticks without contact points (flight, rest), element by
        element: numpy's per-call cost exceeds the work there."""
        offset = self._offset
        samples, skipped = contact_samples(batch, offset, self._last_sample_ns)
        if samples:
            self._publish_samples(*zip(*samples))
        states, last, radius = [], self._last_state_ns, self._model.radius
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
            self.get_logger().warning(f'skipped {skipped} non-finite values',
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
        order, after what already waits: see ``_send``)."""
        encode = self._encode[key]
        rows = zip(*columns)
        pending = self._pending
        if pending:
            pending.extend((key, encode(*row)) for row in rows)
            return
        publish = self._pub[key].publish
        for row in rows:
            data = encode(*row)
            try:
                publish(data)
            except _rclpy.RCLError:
                if not rclpy.ok(context=self.context):
                    raise
                pending.append((key, data))
                pending.extend((key, encode(*rest)) for rest in rows)
                return

    # ---- services --------------------------------------------------------------------------

    def _on_query(self, request, response):
        model = self._model
        answers = answer_queries(list(request.names), model.contact, model.mass)
        values = []
        for name, (value, reason) in zip(request.names, answers):
            if value is None:
                self.get_logger().warning(f'query_restitution: cannot answer {name!r}: {reason}')
                values.append(ParameterValue(type=ParameterType.PARAMETER_NOT_SET))
            else:
                values.append(ParameterValue(type=ParameterType.PARAMETER_DOUBLE,
                                             double_value=value))
        response.values = values
        return response

    def _on_reset(self, request, response):
        model = self._model
        try:
            sim = make_simulation(model)
        except Exception as error:
            response.success = False
            response.message = f'reset failed: {error}'
            return response
        reached = self._sim.time
        if reached > self._anchor_sim + self._tick * self._dt:
            # a tick half done (its turn ran out of wall time inside it): the new drop starts
            # at that tick's end, so its ticks stay on the grid
            reached = max(reached, self._anchor_sim + (self._tick + 1) * self._dt)
        self._offset += reached
        self._sim = sim
        self._commanded = False     # the new drop's plate: the table's, or fixed
        self._start_loop()
        response.success = True
        response.message = f'drop restarted at t = {self._offset:.9f} s: {model.summary()}'
        self.get_logger().info(response.message)
        return response


def read_plate_command(msg, now, offset):
    """A ``trajectory_msgs/JointTrajectory`` as (times, positions, velocities or None) in the
    drop's time (s): point time = stamp + time_from_start, the stamp in simulated time (the
    node's /clock: ``offset`` + the drop's time), stamp 0 = ``now`` (receipt).  Accelerations and
    efforts are ignored.  ValueError naming the field for a wrong joint or a malformed point."""
    names = list(msg.joint_names)
    if names != [PLATE_JOINT]:
        raise ValueError(f'joint_names = {names!r} is invalid: allowed [{PLATE_JOINT!r}] (one '
                         'prismatic joint, m, up)')
    stamp = msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9
    base = now if stamp == 0.0 else stamp - offset
    times, positions, velocities = [], [], []
    for i, point in enumerate(msg.points):
        if len(point.positions) != 1:
            raise ValueError(f'points[{i}].positions has {len(point.positions)} values: allowed '
                             f'1 ({PLATE_JOINT})')
        if len(point.velocities) not in (0, 1):
            raise ValueError(f'points[{i}].velocities has {len(point.velocities)} values: '
                             f'allowed 0 (estimated) or 1 ({PLATE_JOINT})')
        times.append(base + point.time_from_start.sec + point.time_from_start.nanosec * 1e-9)
        positions.append(point.positions[0])
        velocities.append(point.velocities[0] if len(point.velocities) else None)
    if not times:
        raise ValueError('points is empty: allowed at least one point')
    given = [v is not None for v in velocities]
    if any(given) and not all(given):
        raise ValueError('points[].velocities are given for some points only: allowed on every '
                         'point or on none (then estimated)')
    return times, positions, (velocities if all(given) else None)


def spin(node, executor):
    """Spin until the context shuts down (Ctrl-C, SIGTERM), one turn at a time.

    (``EventsExecutor.spin()`` in rclpy 9.1 does not return when the context shuts down; a turn
    of ``spin_once`` raises ExternalShutdownException then.)
    """
    while rclpy.ok(context=node.context):
        executor.spin_once(timeout_sec=0.5)


def main(args=None):
    """``contact_sim_node``: run until SIGINT/SIGTERM (exit code 0; 2 on bad parameters)."""
    rclpy.init(args=args)
    node = None
    try:
        node = ContactSimNode()
        executor = EventsExecutor(context=node.context)
        executor.add_node(node)
        spin(node, executor)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    except StartupError as error:
        rclpy.logging.get_logger(NODE_NAME).fatal(f'invalid parameters: {error}')
        return 2
    finally:
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()
    return 0


if __name__ == '__main__':
    import sys
    sys.exit(main())

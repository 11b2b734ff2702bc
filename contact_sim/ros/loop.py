"""The node's loop: simulated time cut into ticks, advanced by the engine and published at the
pace of real time (or as fast as possible, and no faster than a recorder records).

Simulated time is cut into ticks of ``dt`` = real_time_factor / publish_rate s
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
live. Real time that cannot be held (more than ``MAX_LAG`` s behind) is logged once, with the
tick rate achieved, and the node skips ahead (the states of the skipped ticks are not published;
the contact points are).

Pacing by a recorder (``pacing.RecorderPace``, the protocol is described there). Running as fast
as possible while ``contact_sim_record`` is there, the node publishes no more than
``RecorderPace.lead`` messages (``pacing.lead_messages``) beyond what the recorder has
acknowledged: before each engine call it asks for room, and sizes the call to it and to half the
lead (``RecorderPace.call``), counted as 8 messages a tick (a tick's contact points add 3 messages
each, at most ``TURN_STEP_BUDGET`` steps' worth in a call), one call a turn, so that the
recorder's acknowledgements are taken between calls and it records one call while the node
computes the next; without room the node pauses its timer, and resumes at the next
acknowledgement (or when the recorder has gone: checked every ``WATCH_PERIOD``). At a stop (``drain``) it finishes its tick, publishes what waits and
waits until the recorder has acknowledged all of it.
"""
import math
import time

import numpy as np
import rclpy

from .pacing import RecorderPace
from .view import View

TURN_STEP_BUDGET = 20    # integrator steps per engine call (~10 ms); then the wall budget is checked
BATCH_TICKS = 256        # ticks per batched engine call (advance_ticks), then the budgets are checked
FAST_TURN = 0.02         # s of wall time per executor turn when running as fast as possible
REAL_TURN = 0.75         # of the timer period: wall time per turn at most in real time
# In real time a turn's wall budget is TURN_BASE + TURN_PER_TICK per tick due (at most REAL_TURN
# of the period): a tick with much work (the settling's ~1000 contact points) is spread over
# turns, and a node behind real time gets a larger budget to catch up.
TURN_BASE = 0.002        # s
TURN_PER_TICK = 0.0005   # s
WAKE_PERIOD = 0.02       # s: in real time the node wakes at most every 20 ms (50 Hz)
MAX_LAG = 2.0            # s behind real time before the node skips ahead (and says so, once)
TICK_MESSAGES = 8        # messages of a tick without contact points (3 sample, 4 state, /clock)
IMPACT_WAIT = 2.0        # s: at a stop, the wait for reliable readers' acknowledgements of ~/impact
DRAIN_TIMEOUT = 8.0      # s: at a stop, the wait for readers and a recorder, at most (then a warning)
WATCH_PERIOD = 0.5       # s: a paused node checks this often whether its recorder has gone


class TickLoop:
    """The tick loop of ``ContactSimNode``: it advances the drop it is given and publishes it.

    Everything it reads is given to it: the node (for timers, the logger and the recorder's
    acknowledgements), the ``outbox.Outbox``, the steady clock, and at each
    ``start`` the drop (``DropSimulation``), the ``params.LoopSettings`` (publish_rate,
    real_time_factor), the ``params.Model`` (the sphere's radius) and the stamp offset (s: the
    stamp of the drop's time 0). It owns the anchor (``_anchor_wall``, ``_anchor_sim``), the
    ticks published since it (``_tick``), their length ``_dt`` (s), the loop timer and the
    pause for a recorder (``pacing.RecorderPace``), and its ``view`` (``view.View``: ~/markers
    and /diagnostics, which reads this loop's public attributes).

    Parameters
    ----------
    node : rclpy.node.Node
        Creates the timers and the recorder's subscription; its logger is used.
    out : outbox.Outbox
        The publishers of the recorded topics.
    clock : rclpy.clock.Clock
        The steady clock of the timers (pacing ignores use_sim_time).
    """

    def __init__(self, node, out, clock):
        self._node, self._out, self._steady = node, out, clock
        self.view = View(node, clock, self)   # ~/markers and /diagnostics, of this loop
        self._pace = RecorderPace(node, lambda: self._out.sent, self._resume_if_free)
        self._paused = False
        self._stopping = False
        node.create_timer(WATCH_PERIOD, self._watch, clock=clock)
        self._lag_logged = False
        self._timer = None
        self.sim = self.settings = self.model = None
        self.offset = 0.0

    def start(self, sim, settings, model, offset):
        """(Re)start the loop on the drop ``sim`` (its time 0 stamped ``offset`` s) with
        ``settings`` (``params.LoopSettings``) and ``model`` (``params.Model``), anchoring
        tick 0 at the drop's current time and the wall time now (at the start, ~/reset or a
        change of real_time_factor)."""
        self.sim, self.settings, self.model, self.offset = sim, settings, model, offset
        self._anchor_wall, self._anchor_sim, self._tick = time.monotonic(), sim.time, 0
        self._dt = settings.dt
        if self._timer is not None:
            self._node.destroy_timer(self._timer)
        self._paused = False
        self._period = 0.0 if settings.fast else max(1.0 / settings.publish_rate, WAKE_PERIOD)
        self._timer = self._node.create_timer(self._period, self._on_timer, clock=self._steady)
        self.view.begin()

    def lag(self):
        """s of simulated time a real-time run is behind its schedule (0 as fast as possible)."""
        if self.settings.fast:
            return 0.0
        due = (time.monotonic() - self._anchor_wall) * self.settings.real_time_factor
        return max(0.0, due - (self.sim.time - self._anchor_sim))

    def paced(self):
        """A recorder paces the loop (``contact_sim_record`` is there)."""
        return self._pace.recorders() > 0

    def reached_on_grid(self):
        """The drop's time (s) reached, where a new drop (~/reset) starts: if a tick is half done
        (its turn ran out of wall time inside it), that tick's end, so that the new drop's ticks
        stay on the grid."""
        reached = self.sim.time
        if reached > self._anchor_sim + self._tick * self._dt:
            reached = max(reached, self._anchor_sim + (self._tick + 1) * self._dt)
        return reached

    def _ticks_due(self, now):
        """Ticks (since the anchor) whose wall time has come; every one when running flat out."""
        if self.settings.fast:
            return math.inf
        return int((now - self._anchor_wall) * self.settings.publish_rate)

    def _on_timer(self):
        try:
            self._turn()
        except Exception:
            if rclpy.ok(context=self._node.context):
                raise
            # Ctrl-C shut the context down during the turn (rclpy's handler runs in its own
            # thread): the publishers are gone; spin() returns next

    def _turn(self):
        if self._out.pending and not self._out.send_pending():
            return   # a reliable reader still has no room: the next turn tries again
        start = time.monotonic()
        fast = self.settings.fast
        due = self._ticks_due(start)
        deadline = start + (FAST_TURN if fast else min(
            REAL_TURN * self._period, TURN_BASE + TURN_PER_TICK * max(due - self._tick, 0)))
        paced = False   # paced: one engine call a turn (acknowledgements are taken between
        # turns, and the recorder records the last call meanwhile)
        if fast:
            room = self._pace.room()
            paced = room != math.inf
            if room <= 0 and not self._mid_tick():
                # a recorder is behind: wait for it (RecorderPace; never inside a tick, whose
                # end is what it acknowledges)
                self._pause()
                return
        elif due - self._tick > MAX_LAG * self.settings.publish_rate:
            self._skip_ahead(due, start)
        while self._tick < due:
            if not self._run_ticks(self._calls_ticks(min(due, self._tick + BATCH_TICKS)),
                                   deadline, one_call=paced):
                return    # out of wall time inside the tick: the next turn goes on with it
            if paced or self._out.pending or time.monotonic() > deadline:
                return

    def _mid_tick(self):
        """A tick is begun and not finished (its turn ran out inside it)."""
        return self.sim.time > self._anchor_sim + self._tick * self._dt

    def _pause(self):
        self._timer.cancel()
        self._paused = True

    def _watch(self):
        self._pace.watch()
        self._resume_if_free()

    def _resume_if_free(self):
        if self._paused and not self._stopping and self._pace.room() > 0:
            self._paused = False
            self._timer.reset()

    def _calls_ticks(self, upto):
        """``upto`` cut to what a recorder has room for (at least one tick)."""
        if not self.settings.fast:
            return upto
        room = self._pace.room()
        if room == math.inf:
            return upto
        return min(upto, self._tick + max(1, min(int(room), self._pace.call) // TICK_MESSAGES))

    def drain(self):
        """At a stop: tick no more, finish the tick begun, and return a predicate that holds
        once everything published is out and a recorder has acknowledged it, or once
        ``DRAIN_TIMEOUT`` s have passed (``startup.spin_until_signal``'s ``drain``). Each thing
        it waits for is logged once, when the wait for it begins, and a wait given up is a
        warning naming what is missing: a stop never waits silently."""
        self._stopping = True
        self._timer.cancel()
        if self._mid_tick():
            self._run_ticks(self._tick + 1, math.inf)
        log, said = self._node.get_logger(), set()
        give_up = time.monotonic() + DRAIN_TIMEOUT

        def say(what, text):
            if what not in said:
                said.add(what)
                log.info(f'stopping: {text} (at most {DRAIN_TIMEOUT:g} s in all; Ctrl-C again '
                         'to stop now)')

        def done():
            if time.monotonic() > give_up:
                log.warning(f'stopping after {DRAIN_TIMEOUT:g} s of waiting: '
                            f'{self._out.pending_count()} messages not sent to a reliable '
                            f'reader, {self._pace.unacknowledged()} not acknowledged by the '
                            f'recorder (published to t = {self._out.tick_ns * 1e-9:.3f} s)')
                return True
            if self._out.pending and not self._out.send_pending():
                say('readers', f'waiting for a reliable reader to have room for '
                    f'{self._out.pending_count()} messages')
                return False
            if not self._pace.drained():
                say('recorder', f'waiting for the recorder to acknowledge '
                    f'{self._pace.unacknowledged()} messages, to t = '
                    f'{self._out.tick_ns * 1e-9:.3f} s')
                return False
            if not self._out.wait_for_readers('impact', 0.0):
                say('impact', f'waiting up to {IMPACT_WAIT:g} s for the readers of ~/impact to '
                    'acknowledge it')
                if not self._out.wait_for_readers('impact', IMPACT_WAIT):
                    log.warning('stopping: a reader of ~/impact did not acknowledge every '
                                f'impact within {IMPACT_WAIT:g} s')
            if self._pace.recorded_ns is not None and self._pace.recorders() > 0:
                log.info(f'stopping: the recorder has every tick published, to t = '
                         f'{self._out.tick_ns * 1e-9:.3f} s')
            return True
        return done

    def _skip_ahead(self, due, now):
        """Real time cannot be held: say so once, with the rate achieved, and jump to ``due``."""
        if not self._lag_logged:
            self._lag_logged = True
            achieved = self._tick / max(now - self._anchor_wall, 1e-9)
            self._node.get_logger().warning(
                f'publish_rate {self.settings.publish_rate:g} Hz at real_time_factor '
                f'{self.settings.real_time_factor:g} cannot be held: {achieved:.0f} ticks/s achieved;'
                f' skipping ahead (the states of skipped ticks are not published; logged once)')
        self._tick = due - 1

    def _run_ticks(self, upto, deadline, one_call=False):
        """Advance through ticks up to ``upto`` (since the anchor) in batched engine calls
        (``DropSimulation.advance_ticks``, ``TURN_STEP_BUDGET`` integrator steps each) and
        publish them; False if the wall budget ran out first, or after one call if
        ``one_call`` (what was integrated so far is published; the rest goes on at the next
        turn)."""
        sim = self.sim
        times = self._anchor_sim + np.arange(self._tick + 1, upto + 1) * self._dt
        done = 0
        while done < times.size:
            try:
                batch = sim.advance_ticks(times[done:], max_steps=TURN_STEP_BUDGET)
            except Exception as error:  # keep the node alive and the last good state
                target = float(times[done])
                self._node.get_logger().error(f'simulation step to t = {target:.9f} s failed: {error}',
                                        throttle_duration_sec=5.0)
                self._tick += 1
                return True
            self._out.publish_batch(batch, self.offset, self.model.radius)
            self.view.publish_batch(batch, self.offset, self.model, self.settings)
            self.view.ticks += batch.ticks
            self._pace.mark(self._out.tick_ns)
            done += batch.ticks
            self._tick += batch.ticks
            if done < times.size and (one_call or time.monotonic() > deadline):
                return False    # (a paced turn is one call: the room is asked before the next)
        return True


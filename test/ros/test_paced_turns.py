"""The node's loop while a recorder paces it (``loop.TickLoop._turn``), without ROS: one engine
call a turn, of ``pacing.CALL_MESSAGES`` counted as ticks at rest, so that the recorder's acknowledgements are
taken between calls (a turn that used the whole lead left both processes waiting)."""
import math
from types import SimpleNamespace

import pytest


from contact_sim.ros import loop, pacing  # noqa: E402

DT = 0.01


class Sim:
    """Ticks at rest: each engine call reaches every tick end asked for."""

    def __init__(self):
        self.time, self.calls = 0.0, []

    def advance_ticks(self, times, max_steps):
        self.calls.append(len(times))
        self.time = float(times[-1])
        return SimpleNamespace(ticks=len(times))


class Outbox:
    def __init__(self):
        self.sent, self.pending, self.tick_ns = 0, [], -1

    def publish_batch(self, batch, offset, radius):
        self.sent += loop.TICK_MESSAGES * batch.ticks


class Pace:
    """A recorder that has acknowledged ``acked`` of the messages sent."""

    lead, call = pacing.LEAD_MESSAGES, pacing.CALL_MESSAGES

    def __init__(self, out, recorder=True):
        self.out, self.acked, self.recorder = out, 0, recorder

    def room(self):
        if not self.recorder:
            return math.inf
        return self.lead - (self.out.sent - self.acked)

    def mark(self, ns):
        pass


class Loop(loop.TickLoop):
    def __init__(self, recorder=True):
        # what TickLoop.start is given: the settings, the model, the drop, the offset
        self.settings = SimpleNamespace(fast=True, publish_rate=1 / DT, real_time_factor=0.0)
        self.model = SimpleNamespace(radius=0.01)
        self.sim, self._out, self.offset = Sim(), Outbox(), 0.0
        self.view = SimpleNamespace(publish_batch=lambda batch, offset, model, settings: None,
                                    ticks=0)
        self._pace = Pace(self._out, recorder)
        self._anchor_wall, self._anchor_sim, self._tick, self._dt = 0.0, 0.0, 0, DT
        self._stopping, self._paused = False, False
        self._timer = SimpleNamespace(cancel=lambda: None, reset=lambda: None)

    def _pause(self):
        self._paused = True


@pytest.mark.parametrize('frozen', [False, True])
def test_a_paced_turn_is_one_engine_call_of_half_the_lead_in_ticks(frozen, monkeypatch):
    if frozen:   # a coarse clock (15.6 ms on some systems) that a quick call does not move
        monkeypatch.setattr(loop.time, 'monotonic', lambda: 1000.0)
    node = Loop()
    node._turn()
    assert node.sim.calls == [pacing.CALL_MESSAGES // loop.TICK_MESSAGES]
    assert node._out.sent <= pacing.CALL_MESSAGES < pacing.LEAD_MESSAGES
    node._turn()                      # no acknowledgement yet: the rest of the lead
    assert node._out.sent <= pacing.LEAD_MESSAGES and not node._paused
    node._turn()                      # the lead is used up: the node waits
    assert node._paused and len(node.sim.calls) == 2
    node._pace.acked = node._out.sent  # everything acknowledged: room again
    node._paused = False
    node._turn()
    assert len(node.sim.calls) == 3


def test_an_unpaced_turn_runs_many_ticks():
    node = Loop(recorder=False)
    node._turn()
    assert node._out.sent > pacing.LEAD_MESSAGES

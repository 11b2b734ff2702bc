"""Bouncing: flights and contact phases on the fixed plate, a vibrating table (a
``SinusoidalPlate``, ``PlateMotion.table``) or a plate through set-points (a ``CommandedPlate``,
``PlateMotion.pieces``), or a switch to either once it is passed (``PlateMotion.motion_from``),
in vacuum, many bounces a call, in compiled code (``compiled_train.run_train``).

The same motion as the modes it strings together (``Flight`` -> ``touch`` -> ``Contact`` ->
``lift_off`` -> ``Flight`` ..., and ``Contact`` -> ``knot`` -> ``Contact`` where a commanded
plate's forcing changes: the same functions, in the same order), without returning to Python
between bounces.  It ends with one of its own events: ``landed`` (the running phase became
permanent: a ``Contact`` over it goes on, ``event.after``), ``touch`` or ``knot`` (the next phase
is too stiff for the compiled integrator: ``transitions.impact`` or ``go_on`` starts it on the
Python path), ``carried`` (``CarryWatch`` found the sphere carried) or ``handed_over`` (the
default engine is no longer the compiled one: its current flight or phase goes on as a
``Flight`` or ``Contact``, ``event.after``).  A change from outside (``set_plate``,
``set_contact``) first takes the train's current flight or phase as a ``Flight`` or ``Contact``
(``Mode.handed_over``), whose transitions then apply.
"""
import math

import numpy as np

from contact_sim.drop import compiled_train as ct
from contact_sim.drop.mode import NO_POINTS, Event, Mode, Move
from contact_sim.drop.mode_carried import CHUNK
from contact_sim.drop.mode_contact import Contact
from contact_sim.drop.mode_flight import Flight, ballistic
from contact_sim.drop.plate.flights import no_exit
from contact_sim.drop.records import ImpactRecord
from contact_sim.phase import (COMPILED_STIFF_DAMPING, CompiledPhase, constant_parameters,
                               force_can_vanish_inside, get_engine, lift_off_energy, lift_off_of,
                               phase_storage, results_of, step_too_small)

POINT_ROWS = 1024         # the points buffer to start with (it grows for a long phase)
RECORD_ROWS = 256         # impact records a kernel call may make before Python reads them
_TESTED = (ct.TIME_REACHED, ct.BUDGET_SPENT, ct.ENERGY_BELOW)
_NO_PIECES = np.zeros((4, 1))   # ``run_train``'s pieces where the plate is not commanded
_enabled = True


def trains_enabled(flag=None):
    """Whether new flights that ``takes`` accepts become trains (``Bouncing``); with
    ``flag``, set it and return the previous value (``False``: every bounce through the Python
    modes, the reference the trains are tested against)."""
    global _enabled
    previous = _enabled
    if flag is not None:
        _enabled = bool(flag)
    return previous


def takes(sim, flight):
    """True if ``flight`` of ``sim`` can go on as a train: the fixed plate, or a plate whose
    motion from the flight's start on (``PlateMotion.motion_from``: a switch to a table passed)
    is a table for ever (``PlateMotion.table``) or a plate through set-points
    (``PlateMotion.pieces``); vacuum, g > 0, the compiled engine, no contact waiting, a touch
    ahead."""
    plate = sim.plate_motion
    motion = plate.motion_from(flight.start)
    return (_enabled and (not plate.moving or motion.table is not None
                          or motion.pieces is not None)
            and sim.drag_rates is None
            and sim.gravity > 0.0 and sim.pending_contact is None
            and get_engine() == 'compiled' and math.isfinite(flight.contact_time))


class Bouncing(Mode):
    """Bounces of ``sim`` (a ``DropSimulation``) from its planned ``flight`` on, in compiled code
    (module docstring).  ``tr``, (st, K, F, par), ``pts``, ``imp``: the kernel's train state,
    phase storage, points and impact records (``compiled_train``)."""

    carried = False

    def __init__(self, sim, flight):
        self._sim = sim
        self.contact, self.mass, self.gravity = sim.contact, sim.mass, sim.gravity
        self.plate = plate = sim.plate_motion
        law = self.contact.law
        forcing = plate.forcing_piece(flight.start)[0]
        self.par = constant_parameters(self.contact, sim.mass, sim.rtol, sim.rtol * 1e-2,
                                       2 if force_can_vanish_inside(law, sim.gravity, forcing)
                                       else 1)
        self.st, self.K, self.F = phase_storage()
        tr = self.tr = np.zeros(ct.NTR)
        tr[ct.TR_FLIGHT] = 1.0
        tr[ct.TR_START], tr[ct.TR_Y0], tr[ct.TR_V0] = flight.start, flight.y0, flight.v0
        tr[ct.TR_TOUCH], tr[ct.TR_GRAVITY] = flight.contact_time, sim.gravity
        tr[ct.TR_FLOOR] = (lift_off_energy(self.contact, sim.mass, sim.gravity)
                           if not plate.moving else -math.inf)
        tr[ct.TR_STIFF] = COMPILED_STIFF_DAMPING
        tr[ct.TR_K], tr[ct.TR_LAM], tr[ct.TR_MASS] = (self.contact.stiffness,
                                                      self.contact.damping, sim.mass)
        tr[ct.TR_N], tr[ct.TR_P], tr[ct.TR_Q] = law.n, law.p, law.q
        self.pc = _NO_PIECES
        if plate.moving:
            motion = plate.motion_from(flight.start)      # its flights' own plate and bound
            if motion.table is not None:
                tr[ct.TR_MOVING] = ct.TABLE
                tr[ct.TR_AMP], tr[ct.TR_OMEGA], tr[ct.TR_PHASE] = motion.table
                tr[ct.TR_FORCE_AMP] = forcing.acceleration_amplitude
            else:
                tr[ct.TR_MOVING] = ct.COMMANDED
                self.pc = motion.pieces
            tr[ct.TR_BOUND] = sim.gravity + motion.acceleration_bound()
            tr[ct.TR_CHUNK] = CHUNK
        tr[ct.TR_VANISHES] = float(law.force_vanishes_inside)
        self.pts = np.empty((POINT_ROWS, 4))
        self.imp = np.empty((RECORD_ROWS, ct.NREC))
        self._view = None           # the Contact over the running phase (``_contact``)
        self._handed = False

    # -- what the engine asks of a mode ----------------------------------------------------
    @property
    def in_flight(self):
        return self.tr.item(ct.TR_FLIGHT) != 0.0

    @property
    def in_contact(self):
        return not self.in_flight

    @property
    def until(self):
        return self.tr.item(ct.TR_TOUCH) if self.in_flight else -math.inf

    @property
    def steps(self):
        """Steps of the running phase (none once handed over: its ``Contact`` has them)."""
        return 0 if self._handed or self.in_flight else int(results_of(self.st)[2])

    def state(self, t):
        if self.in_flight:
            tr = self.tr
            y, v = ballistic(tr.item(ct.TR_Y0), tr.item(ct.TR_V0), self.gravity,
                             t - tr.item(ct.TR_START))
            p, pv, _ = self.plate.state(t)
            return p - y, pv - v                    # as Flight.state
        return self._contact().state(t)

    def states(self, t):
        if not self.in_flight:
            return None
        plate = self.plate.states(t)
        if plate is None:
            return None
        tr = self.tr
        y, v = ballistic(tr.item(ct.TR_Y0), tr.item(ct.TR_V0), self.gravity,
                         t - tr.item(ct.TR_START))
        return plate[0] - y, plate[1] - v           # as Flight.states

    def handed_over(self, sim):
        """The train's current flight (a ``Flight``) or phase (a ``Contact``), which goes on in
        its place; the train stops here."""
        self._handed = True
        if not self.in_flight:
            return self._contact()
        tr = self.tr
        return Flight.planned(sim.plate_motion, self.gravity, tr.item(ct.TR_START),
                              tr.item(ct.TR_Y0), tr.item(ct.TR_V0), tr.item(ct.TR_TOUCH))

    def advance(self, sim, t_end, budget, points):
        if get_engine() != 'compiled':      # the engine changed: the Python modes go on
            return Move(Event('handed_over', sim.time, after=self.handed_over(sim)), sim.time,
                        budget)
        tr = self.tr
        tr[ct.TR_KEEP] = 0.0 if points is NO_POINTS else 1.0
        while True:
            steps = ct.MAX_STEPS if math.isinf(budget) else int(budget)
            reason, taken = ct.run_train(tr, self.st, self.K, self.F, self.par, self.pts,
                                         self.imp, self.pc, float(t_end), steps)
            budget -= taken
            self._report(sim, points, t_end)
            if reason == ct.BUFFER_FULL:
                self._make_room()
                continue
            if reason == ct.STEP_TOO_SMALL:
                raise step_too_small()
            time = tr.item(ct.TR_TIME)
            if reason == ct.CARRY_TEST:             # as Contact.advance before a run
                contact = self._contact()
                event = contact.watch.before_run(sim, contact)
                if event is not None:
                    return Move(event, event.time, budget)
                continue
            if reason == ct.NO_EXIT_FOUND:
                raise no_exit(tr.item(ct.TR_START))
            if reason == ct.STIFF_PHASE:
                return Move(Event('touch', time, tr.item(ct.TR_Z), tr.item(ct.TR_RATE)), time,
                            budget)
            if reason == ct.STIFF_KNOT:         # the phase ended, its steps reported
                self._handed = True
                return Move(Event('knot', time, tr.item(ct.TR_Z), tr.item(ct.TR_RATE),
                                  record=self._record()), time, budget)
            if (reason in _TESTED and tr.item(ct.TR_RAN) and not self.plate.moving
                    and not self.in_flight and not lift_off_of(self.st)[0]):
                contact = self._contact()
                phase = contact.integrator
                if contact.watch.lands(sim, phase, phase.energy_above_rest()):
                    contact.watch.after_run(sim, contact)     # as after the Contact's own run
                    self._handed = True
                    return Move(Event('landed', time, after=contact), time, budget)
                if reason == ct.ENERGY_BELOW:
                    continue
            return Move(None, time, budget)

    # -- the kernel's output ---------------------------------------------------------------
    def _report(self, sim, points, t_end):
        """Hand the kernel's output to the drop: the impact records and apexes, the steps of
        the phases ended, the points up to ``t_end`` (s) not handed out yet (in a contact
        phase, up to its knot at the latest, as ``Contact.take_points``)."""
        tr, recorder = self.tr, sim.recorder
        n = int(tr.item(ct.TR_NIMP))
        if n:
            rows = self.imp[:n].tolist()
            recorder.impacts.extend([ImpactRecord(*row[:ct.REC_APEX]) for row in rows])
            recorder.apex_heights.extend([row[ct.REC_APEX] for row in rows
                                          if not math.isnan(row[ct.REC_APEX])])
            tr[ct.TR_NIMP] = 0.0
        recorder.steps += int(tr.item(ct.TR_STEPS))
        tr[ct.TR_STEPS] = 0.0
        start, used = int(tr.item(ct.TR_EMITTED)), int(tr.item(ct.TR_NPTS))
        if used > start:
            if not self.in_flight:
                t_end = min(t_end, tr.item(ct.TR_KNOT))
            stop = start + int(np.searchsorted(self.pts[start:used, 0], t_end, side='right'))
            if stop > start and points is not NO_POINTS:
                points.extend(self.pts[start:stop].tolist())
            tr[ct.TR_EMITTED] = stop

    def _make_room(self):
        """Drop the rows handed out that the running phase does not need; grow the buffer if
        the rows left fill half of it (the kernel needs 4 free rows to go on)."""
        tr = self.tr
        used = int(tr.item(ct.TR_NPTS))
        keep = int(tr.item(ct.TR_EMITTED))
        if not self.in_flight:
            keep = min(keep, int(tr.item(ct.TR_PHASE_ROW)))
        rows = used - keep
        if 2 * rows >= self.pts.shape[0]:
            grown = np.empty((2 * self.pts.shape[0], 4))
            grown[:rows] = self.pts[keep:used]
            self.pts = grown
        elif keep:
            self.pts[:rows] = self.pts[keep:used].copy()
        for slot in (ct.TR_NPTS, ct.TR_PHASE_ROW, ct.TR_EMITTED):
            tr[slot] = max(tr[slot] - keep, 0.0)

    def _contact(self):
        """The ``Contact`` over the running phase, its storage shared: made once a phase, then
        brought up to date (the points the kernel added since, the phase's results), so that a
        test for the carried state every ``CHUNK`` steps costs what those steps added."""
        tr, pts = self.tr, self.pts
        first, used = int(tr.item(ct.TR_PHASE_ROW)), int(tr.item(ct.TR_NPTS))
        view = self._view
        if view is None or view.integrator.start_time != pts.item(first, 0):
            phase = CompiledPhase.adopt(self.contact, self.mass, self.par, self.st, self.K,
                                        self.F, [tuple(row) for row in
                                                 pts[first:used].tolist()])
            view = self._view = Contact(self._sim, phase.start_time, 0.0, 0.0,
                                        record=self._record(), integrator=phase)
        else:
            phase = view.integrator
            phase.caught_up([tuple(row) for row in
                             pts[first + len(phase.points):used].tolist()])
        view.emitted = int(tr.item(ct.TR_EMITTED)) - first
        return view

    def _record(self):
        """The running contact's record (``Contact``'s: its first point (t, z, ż, F), the peak
        force (N) and depth (m) before its phase's last restart at a knot)."""
        tr = self.tr
        return ((tr.item(ct.TR_T0), tr.item(ct.TR_Z0), tr.item(ct.TR_RATE0), tr.item(ct.TR_F0)),
                tr.item(ct.TR_REC_PEAK), tr.item(ct.TR_REC_DEPTH))

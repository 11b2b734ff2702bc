"""One contact phase in compiled code: the ``compiled`` kernels behind the phase interface.

The same mathematics as the reference (``reference.PhaseIntegrator``): DOP853 with scipy's step
control, the 7th-order dense output and Brent event location, all in numba, so that ``run``
takes any number of steps in one call.
"""
import math

import numpy as np

from contact_sim.phase import compiled
from contact_sim.phase.compiled_start import (constant_parameters, energy_stop, phase_state_at,
                                              phase_storage, start_phase, step_too_small)
from contact_sim.phase.lift_off import force_can_vanish_inside
from contact_sim.phase.scales import DEFAULT_ATOL, DEFAULT_RTOL, PhaseScales, phase_scales


class CompiledPhase:
    """One contact phase integrated in compiled code (``compiled``): the same interface and the
    same mathematics as ``PhaseIntegrator`` (DOP853 with scipy's step control, the 7th-order dense
    output, Brent event location), but ``run`` takes any number of steps in one call.

    ``points``, ``peak_force``, ``max_penetration``, ``steps``, ``lifted_off`` and ``end`` are
    plain attributes, brought up to date after every ``step``/``run``.  With
    ``keep_points=False`` only the first point is kept (a caller that wants the outcome alone).
    ``forcing`` (a ``Forcing``) adds forcing terms to gravity.
    """

    def __init__(self, contact, mass, gravity, start_time, penetration, penetration_rate,
                 rtol=DEFAULT_RTOL, atol=DEFAULT_ATOL, scales=None, keep_points=True,
                 forcing=None):
        sc = scales if scales is not None else phase_scales(
            contact, mass, gravity, penetration, penetration_rate)
        # the layout of compiled.P_*; the forcing: gravity, and the terms of ``forcing``
        par = constant_parameters(contact, mass, rtol, atol,
                                  2 if force_can_vanish_inside(contact.law, gravity, forcing)
                                  else 1)
        if forcing is not None:
            par[compiled.P_AMPLITUDE:compiled.P_DRAG2 + 1] = forcing.dimensionless(
                mass, sc, start_time)
        st, k, f = phase_storage()
        peak = start_phase(par, st, k, f, start_time, penetration, penetration_rate, sc.length,
                           sc.time, sc.gravity, sc.damping)
        self._adopt(contact, mass, sc, par, st, k, f, keep_points,
                    [(start_time, penetration, penetration_rate, peak)])

    @classmethod
    def adopt(cls, contact, mass, par, st, k, f, points, keep_points=True):
        """The phase whose compiled storage is (``par``, st, K, F), started and run by someone
        else (the drop's compiled bounce loop): its points so far ``points`` (rows (t, z, ż, F),
        the first one its start), its scales and results read from the storage, which it then
        owns."""
        phase = cls.__new__(cls)
        sc = PhaseScales(par[compiled.P_LENGTH], par[compiled.P_TIME], par[compiled.P_GRAVITY],
                         par[compiled.P_ZETA])
        phase._adopt(contact, mass, sc, par, st, k, f, keep_points, points)
        phase._read_state()
        return phase

    def caught_up(self, points):
        """An adopted phase (``adopt``) after the kernel that drives it took more steps: its
        new ``points`` (rows (t, z, ż, F)) appended, its results read again from the storage."""
        self.points.extend(points)
        self._read_state()

    def _adopt(self, contact, mass, scales, par, st, k, f, keep_points, points):
        self.contact, self.mass, self.scales = contact, mass, scales
        self.start_time = points[0][0]
        self._par, self._st, self._k, self._f = par, st, k, f
        self._buffer = np.empty((compiled.POINT_BUFFER, 4))
        self._keep_points = keep_points
        self.lifted_off = False
        self.steps = 0
        self.peak_force = points[0][3]
        self.max_penetration = points[0][1]
        self.end = None  # (t, z, ż) at lift-off
        self.points = points

    def run(self, t_stop=math.inf, max_steps=None, stop_energy=-math.inf):
        """Step until lift-off, until ``time >= t_stop`` (s), for ``max_steps`` steps, or until a
        step that did not lift off ends with ``energy_above_rest() < stop_energy`` (J) (the
        compiled test uses a margin of 1e-12 of the phase's kinetic energy scale, so it may stop
        a step before the caller's own test agrees, never after).  Returns the steps taken."""
        budget = compiled.MAX_STEPS if max_steps is None else int(min(max_steps, compiled.MAX_STEPS))
        stop = energy_stop(stop_energy, self._par)
        st, buf = self._st, self._buffer
        taken = 0
        while True:
            reason, npts, n = compiled.run(st, self._k, self._f, self._par, buf, float(t_stop),
                                           budget - taken, stop)
            taken += n
            if npts and self._keep_points:
                self.points.extend(map(tuple, buf[:npts].tolist()))
            if reason != compiled.BUFFER_FULL:
                break
        self._read_state()
        if reason == compiled.STEP_TOO_SMALL:
            raise step_too_small()
        return taken

    def _read_state(self):
        """The results of the steps taken, from the compiled state."""
        values = self._st.tolist()
        self.steps = int(values[compiled.S_STEPS])
        self.peak_force = values[compiled.S_PEAK]
        self.max_penetration = values[compiled.S_DEPTH]
        if values[compiled.S_LIFTED]:
            self.lifted_off = True
            self.end = (values[compiled.S_END_T], values[compiled.S_END_Z],
                        values[compiled.S_END_RATE])

    def step(self):
        """Take one integrator step; locate peak, maximum penetration and lift-off in it."""
        self.run(max_steps=1)

    @property
    def time(self):
        """Time (s) reached by the integrator (the end of its last step)."""
        s = self._st[compiled.S_S]
        return self.start_time + self.scales.time * s * s

    def _dimensional(self, s, x, u):
        sc = self.scales
        return self.start_time + sc.time * s * s, x * sc.length, u * sc.length / sc.time

    @property
    def state(self):
        st = self._st
        return self._dimensional(st[compiled.S_S], st[compiled.S_X], st[compiled.S_U])[1:]

    def state_at(self, t):
        """(z, ż) at a time t within the last step, from the dense output."""
        return phase_state_at(self._st, self._k, self._f, self._par, t)

    def energy_above_rest(self):
        """Mechanical energy (J) above static equilibrium at the integrator's current state
        (``energy_above_rest``, evaluated in compiled code)."""
        return compiled.energy_above_rest(self._st, self._par)

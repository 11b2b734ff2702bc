"""The engine switch: which integrator takes a contact phase.

Two engines integrate a phase with the same mathematics: ``CompiledPhase`` (the default) and
``PhaseIntegrator`` (the scipy reference).  The reference integrates stiff phases (ζ >
STIFF_DAMPING that creep: into rest under gravity, or out to the surface,
``lift_off.is_stiff``) with Radau; the compiled engine keeps DOP853 up to
COMPILED_STIFF_DAMPING and hands the phases above to ``PhaseIntegrator`` and Radau.
``use_engine("scipy")`` (or CONTACT_SIM_ENGINE=scipy in the environment) makes the reference
path the default.
"""
import contextlib
import math
import os

import numpy as np

from contact_sim.phase import compiled
from contact_sim.phase.compiled_phase import (TABLE_ROWS, CompiledPhase, constant_parameters,
                                              phase_storage, start_phase, start_scaled)
from contact_sim.phase.energy import lift_off_energy
from contact_sim.phase.forcing import NO_FORCING_TERMS
from contact_sim.phase.lift_off import pulls_out
from contact_sim.phase.reference import PhaseIntegrator
from contact_sim.phase.scales import DEFAULT_ATOL, DEFAULT_RTOL, phase_scales

# The compiled DOP853 keeps phases up to this ζ: its steps grow like ζ² on the stiff creep into
# rest, but at a few µs each it beats scipy's Radau (~1 s a drop) by far up to here, and stays
# within a few thousand steps a phase (python bench/bench_peers.py --stiff).
COMPILED_STIFF_DAMPING = 200.0
ENGINES = ('compiled', 'scipy')

_engine = os.environ.get('CONTACT_SIM_ENGINE', 'compiled')


def _check_engine(name):
    if name not in ENGINES:
        raise ValueError(f'engine = {name!r} is unknown: allowed one of {", ".join(ENGINES)}')
    return name


def get_engine():
    """The default engine of contact phases: 'compiled' or 'scipy' (the reference path)."""
    return _check_engine(_engine)


def set_engine(name):
    """Make ``name`` ('compiled' or 'scipy') the default engine; returns the previous one."""
    global _engine
    previous, _engine = _engine, _check_engine(name)
    return previous


@contextlib.contextmanager
def use_engine(name):
    """``with use_engine('scipy'): ...`` runs the block on that engine."""
    previous = set_engine(name)
    try:
        yield
    finally:
        set_engine(previous)


def contact_phase(contact, mass, gravity, start_time, penetration, penetration_rate,
                  rtol=DEFAULT_RTOL, atol=DEFAULT_ATOL, engine=None, keep_points=True,
                  forcing=None, scales=None):
    """The integrator of one contact phase (see ``PhaseIntegrator`` for the arguments;
    ``keep_points=False`` lets the compiled phase skip its point list; ``scales``, the phase's
    ``phase_scales`` of these arguments if the caller has them already).

    ``forcing`` (a ``Forcing`` beyond gravity) needs the compiled engine, which then integrates
    the phase with DOP853 even when it is stiff.

    ``engine`` ('compiled' or 'scipy', default ``get_engine()``) picks ``CompiledPhase`` or
    ``PhaseIntegrator``; a heavily damped phase that creeps (ζ > COMPILED_STIFF_DAMPING, stiff:
    ``lift_off.is_stiff``) always gets ``PhaseIntegrator`` and its Radau method.  (The choice of
    ``PhaseFactory(contact, mass, gravity, rtol, atol).start``.)
    """
    return PhaseFactory(contact, mass, gravity, rtol, atol).start(
        start_time, penetration, penetration_rate, engine=engine, keep_points=keep_points,
        forcing=forcing, scales=scales)


class PhaseFactory:
    """The contact phases of one ``contact``, ``mass`` (kg), ``gravity`` (m/s²) and tolerances,
    as ``contact_phase`` makes them, with what holds for every one of them found once: the
    compiled engine's constant parameters, whether a phase may creep (stiff), and the energy
    below which the sphere can never leave the plate (``energy_floor``).  A drop makes its
    phases here, one a bounce.  Its phases share one points buffer: one thread at a time.
    """

    def __init__(self, contact, mass, gravity, rtol=DEFAULT_RTOL, atol=DEFAULT_ATOL):
        self.contact, self.mass, self.gravity, self.rtol, self.atol = (contact, mass, gravity,
                                                                      rtol, atol)
        law = contact.law
        self._scale_args = (contact.stiffness, contact.damping, mass, gravity, law.n, law.p,
                            law.q)
        self._vanishes_inside = law.force_vanishes_inside
        self._creeps = gravity > 0.0 or not self._vanishes_inside    # lift_off.is_stiff
        self._parameters = [None, None, None]   # constant_parameters by lift-off events (1, 2)
        # the points buffer of the compiled runs, shared by this factory's phases (a run copies
        # out what it wrote before it returns)
        self._buffer = np.empty((compiled.POINT_BUFFER, 4))
        self._floor = None

    @property
    def energy_floor(self):
        """``lift_off_energy`` of the contact (J; -inf without gravity): below this energy above
        rest the force can never vanish again."""
        if self._floor is None:
            self._floor = (lift_off_energy(self.contact, self.mass, self.gravity)
                           if self.gravity > 0.0 else -math.inf)
        return self._floor

    def start(self, start_time, penetration, penetration_rate, engine=None, keep_points=True,
              forcing=None, scales=None):
        """``contact_phase`` of this factory's contact from (z, ż) (m, m/s) at ``start_time``
        (s), with its ``engine``, ``keep_points``, ``forcing`` and ``scales``."""
        engine = _engine if engine is None else engine
        if engine not in ENGINES:
            _check_engine(engine)
        contact, mass, gravity = self.contact, self.mass, self.gravity
        if forcing is not None and forcing.active:
            if engine != 'compiled':
                raise ValueError(f'forcing = {forcing!r} needs the compiled engine: allowed '
                                 f"engine = 'compiled' (not {engine!r}) or no forcing")
            return self._compiled(start_time, penetration, penetration_rate, keep_points,
                                  forcing, scales)
        if engine == 'compiled':
            if scales is not None:
                if not (self._creeps and scales.zeta > COMPILED_STIFF_DAMPING):
                    return self._compiled(start_time, penetration, penetration_rate, keep_points,
                                          None, scales)
            else:
                phase = self._compiled(start_time, penetration, penetration_rate, keep_points,
                                       None, None)
                if phase is not None:
                    return phase
        return PhaseIntegrator(contact, mass, gravity, start_time, penetration, penetration_rate,
                               rtol=self.rtol, atol=self.atol)

    def _compiled(self, start_time, penetration, penetration_rate, keep_points, forcing,
                  scales):
        """A ``CompiledPhase`` started on a copy of the constant parameters made once, its
        ``scales`` found in the same compiled call if not given; ``None`` where an unforced
        phase is stiff (``is_stiff``: ``PhaseIntegrator``'s)."""
        lift_events = 2 if (self._vanishes_inside or forcing is not None and pulls_out(
            self.gravity, forcing.acceleration_amplitude)) else 1
        par = self._parameters[lift_events]
        if par is None:
            par = self._parameters[lift_events] = constant_parameters(
                self.contact, self.mass, self.rtol, self.atol, lift_events)
        par = par.copy()
        st, k, f = storage = phase_storage()
        table = np.empty((TABLE_ROWS, 4)) if keep_points else self._buffer
        terms = NO_FORCING_TERMS if forcing is None else forcing.terms
        if scales is None:
            peak, length, time, gamma, zeta = start_scaled(par, st, k, f, table, start_time,
                                                           penetration, penetration_rate,
                                                           self.gravity, *terms)
            if not length > 0.0:     # no motion and no gravity: phase_scales refuses it
                phase_scales(self.contact, self.mass, self.gravity, penetration,
                             penetration_rate)
            if forcing is None and self._creeps and zeta > COMPILED_STIFF_DAMPING:
                return None
            scales = (length, time, gamma, zeta)
        else:
            peak = start_phase(par, st, k, f, table, start_time, penetration, penetration_rate,
                               scales.length, scales.time, scales.gamma, scales.zeta, *terms)
        phase = CompiledPhase.__new__(CompiledPhase)
        phase._started(self.contact, self.mass, par, storage, start_time, penetration,
                       penetration_rate, peak, scales, table if keep_points else None,
                       self._buffer)
        return phase

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
import os

from contact_sim.phase.compiled_phase import CompiledPhase
from contact_sim.phase.lift_off import is_stiff
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
    ``lift_off.is_stiff``) always gets ``PhaseIntegrator`` and its Radau method.
    """
    engine = get_engine() if engine is None else _check_engine(engine)
    if forcing is not None and forcing.active:
        if engine != 'compiled':
            raise ValueError(f'forcing = {forcing!r} needs the compiled engine: allowed '
                             f"engine = 'compiled' (not {engine!r}) or no forcing")
        return CompiledPhase(contact, mass, gravity, start_time, penetration, penetration_rate,
                             rtol=rtol, atol=atol, scales=scales, keep_points=keep_points,
                             forcing=forcing)
    if engine == 'compiled':
        if scales is None:
            scales = phase_scales(contact, mass, gravity, penetration, penetration_rate)
        if not is_stiff(contact.law, gravity, scales.damping, COMPILED_STIFF_DAMPING):
            return CompiledPhase(contact, mass, gravity, start_time, penetration,
                                 penetration_rate, rtol=rtol, atol=atol, scales=scales,
                                 keep_points=keep_points)
    return PhaseIntegrator(contact, mass, gravity, start_time, penetration, penetration_rate,
                           rtol=rtol, atol=atol)

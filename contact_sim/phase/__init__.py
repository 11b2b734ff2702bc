"""One contact phase: from touch to lift-off (or rest), integrated exactly.

``integrator`` holds the phase's time scales, the plate forcing, the scipy reference integrator,
the compiled phase and the engine switch; ``compiled`` the numba kernels (DOP853 with dense
output and located events); ``_dop853_coefficients`` the generated tableau.
"""
from contact_sim.phase.integrator import (COMPILED_STIFF_DAMPING, DEFAULT_ATOL, DEFAULT_RTOL,
                                          ENGINES, STIFF_DAMPING, CompiledPhase, Forcing,
                                          PhaseIntegrator, PhaseScales, contact_phase,
                                          energy_above_rest, get_engine, lift_off_energy,
                                          phase_scales, set_engine, use_engine)

__all__ = ['COMPILED_STIFF_DAMPING', 'DEFAULT_ATOL', 'DEFAULT_RTOL', 'ENGINES', 'STIFF_DAMPING',
           'CompiledPhase', 'Forcing', 'PhaseIntegrator', 'PhaseScales', 'contact_phase',
           'energy_above_rest', 'get_engine', 'lift_off_energy', 'phase_scales', 'set_engine',
           'use_engine']

"""One contact phase, integrated exactly: from the instant the force switches on to lift-off.

The phase is solved in dimensionless form.  With a length scale Z and a time scale T,
x = z / Z and τ = t / T turn  m z̈ = m g - k zⁿ - λ zᵖ ż|ż|^(q-1)  into

    x'' = γ - xⁿ - ζ xᵖ x'|x'|^(q-1),    γ = g T² / Z,   ζ = λ Z^(p+q-1) T^(2-q) / m,

with T = √(m Z^(1-n) / k) so that the spring term has unit coefficient.  Z is the penetration at
which the spring would store the phase's kinetic energy (or the static deflection under gravity,
whichever is larger), so x and x' are of order one and tolerances mean the same at every speed.

√z is not smooth in t at touch (z ≈ v t, so the damping force of the new law grows like √t and z
carries a t^(5/2) term): a high-order integrator loses its order there.  Integrating in σ = √τ
instead makes every term a power series in σ (z ≈ v σ², σ⁵, σ⁷, ...), so DOP853 keeps its 8th
order from the first step.  Lift-off is the first instant the clamped force returns to zero:
x = 0 or φ = x^(n-p) + ζ x'|x'|^(q-1) = 0 (the force is xᵖ φ and φ is smooth where the force
is not); both are located on the dense output to machine precision.  The root of φ is tested
only where the force can vanish inside (n > p, or a forcing that pulls: ``lift_off``); with
n = p φ only decays towards zero, and a root of it would be round-off.

Modules, one job each: ``scales`` (Z, T, γ, ζ of a phase, the tolerances, the force at its
start), ``forcing`` (plate motion and drag beyond gravity), ``energy`` (the energy above rest and
the lift-off bound), ``lift_off`` (which roots end a phase, and when its end is a stiff
creep), ``reference`` (``PhaseIntegrator``: scipy's DOP853 or Radau stepped from
Python, the reference path), ``compiled_phase`` (``CompiledPhase``, the default engine, and its
start) over ``compiled`` (the numba kernels: DOP853 with dense output and located events) and
``_dop853_coefficients`` (the generated tableau), ``brent`` (Brent's method one iteration at a
time, for the compiled root searches here and in the drop's flights), ``engines`` (the engine
switch and ``contact_phase``, which picks one; ``PhaseFactory``, its choices for one contact made
once).
"""
from contact_sim._lazy import lazy_exports

# where each public name lives, imported on first use (``contact_sim._lazy``): the scales and
# the forcing without numba and scipy's integrators
_EXPORTS = {
    'brent': ('brent_evaluated', 'brent_next', 'brent_start'),
    'compiled_phase': ('CompiledPhase',),
    'energy': ('energy_above_rest', 'lift_off_energy', 'potential_at'),
    'engines': ('COMPILED_STIFF_DAMPING', 'ENGINES', 'PhaseFactory', 'contact_phase', 'get_engine',
                'set_engine', 'use_engine'),
    'forcing': ('Forcing',),
    'lift_off': ('force_can_vanish_inside',),
    'reference': ('STIFF_DAMPING', 'PhaseIntegrator'),
    'scales': ('DEFAULT_ATOL', 'DEFAULT_RTOL', 'PhaseScales', 'phase_scales'),
}
__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)

__all__ = ['COMPILED_STIFF_DAMPING', 'DEFAULT_ATOL', 'DEFAULT_RTOL', 'ENGINES', 'STIFF_DAMPING',
           'CompiledPhase', 'Forcing', 'PhaseFactory', 'PhaseIntegrator', 'PhaseScales',
           'brent_evaluated',
           'brent_next', 'brent_start', 'contact_phase', 'energy_above_rest',
           'force_can_vanish_inside', 'get_engine', 'lift_off_energy', 'phase_scales',
           'potential_at', 'set_engine', 'use_engine']

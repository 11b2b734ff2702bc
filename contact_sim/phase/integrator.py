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
is not); both are located on the dense output to machine precision.

Two engines integrate a phase with the same mathematics: ``CompiledPhase`` (the default: DOP853,
dense output and event location in numba, ``compiled``) and ``PhaseIntegrator`` (scipy's DOP853
stepped from Python: the reference path the tests compare against).  Heavily damped phases
under gravity are stiff: the reference integrates them with scipy's Radau above ζ =
STIFF_DAMPING, the compiled engine keeps DOP853 up to COMPILED_STIFF_DAMPING and hands the
phases above to ``PhaseIntegrator`` and Radau.
``contact_phase`` picks one; ``use_engine("scipy")`` (or CONTACT_SIM_ENGINE=scipy in the
environment) makes the reference path the default.
"""
import contextlib
import functools
import math
import os
from dataclasses import dataclass

import numpy as np
from scipy.integrate import DOP853, Radau
from scipy.optimize import brentq

from contact_sim.phase import compiled
from contact_sim.validation import require_nonnegative, require_real

DEFAULT_RTOL = 1e-12
DEFAULT_ATOL = 1e-14
FIRST_STEP = 0.05
STIFF_DAMPING = 30.0   # ζ above which a phase is integrated by Radau instead of DOP853
# The compiled DOP853 keeps phases up to this ζ: its steps grow like ζ² on the stiff creep into
# rest, but at a few µs each it beats scipy's Radau (~1 s a drop) by far up to here, and stays
# within a few thousand steps a phase (python bench/bench_peers.py --stiff).
COMPILED_STIFF_DAMPING = 200.0
ENGINES = ('compiled', 'scipy')


@dataclass(frozen=True)
class PhaseScales:
    """Length Z (m), time T (s) and the dimensionless gravity γ and damping ζ of one phase."""

    length: float
    time: float
    gravity: float
    damping: float


def phase_scales(contact, mass, gravity, penetration, penetration_rate):
    """Scales for a phase starting at (z, ż): see the module docstring."""
    law, k = contact.law, contact.stiffness
    n, p, q = law.n, law.p, law.q
    z = max(penetration, 0.0)
    energy_speed_sq = penetration_rate ** 2 + 2.0 * k * z ** (n + 1.0) / ((n + 1.0) * mass)
    length = (mass * energy_speed_sq / k) ** (1.0 / (n + 1.0))
    if gravity > 0.0:
        length = max(length, (mass * gravity / k) ** (1.0 / n))
    if not length > 0.0:
        raise ValueError('a contact phase needs motion or gravity: penetration_rate = 0, '
                         'penetration <= 0 and gravity = 0 give no contact')
    time = math.sqrt(mass * length ** (1.0 - n) / k)
    return PhaseScales(length, time, gravity * time ** 2 / length,
                       contact.damping * length ** (p + q - 1.0) * time ** (2.0 - q) / mass)


@dataclass(frozen=True)
class Forcing:
    """Forcing of a contact phase besides gravity and the contact force, for the compiled engine:

        m z̈ = m g + m A sin(Ω t + ϕ) - c₁ ż - c₂ ż|ż| - F(z, ż)

    with A the amplitude of an extra acceleration along +z (m/s²; a plate vibrating as
    z_p = a sin(Ω t + ϕ) along +z gives A = a Ω² in the plate's frame), Ω its angular frequency
    (rad/s), ϕ its phase at t = 0 (rad), c₁ a linear drag (N·s/m) and c₂ a quadratic drag
    (N·s²/m²) on ż.  The energy tests of the drop and of ``simulate_impact`` assume gravity
    alone: a caller that adds forcing decides itself when the sphere rests.
    """

    acceleration_amplitude: float = 0.0
    angular_frequency: float = 0.0
    phase: float = 0.0
    linear_drag: float = 0.0
    quadratic_drag: float = 0.0

    def __post_init__(self):
        for name in ('acceleration_amplitude', 'angular_frequency', 'phase'):
            object.__setattr__(self, name, require_real(name, getattr(self, name)))
        for name in ('linear_drag', 'quadratic_drag'):
            object.__setattr__(self, name, require_nonnegative(name, getattr(self, name)))

    @property
    def active(self):
        return (self.acceleration_amplitude != 0.0 or self.linear_drag != 0.0
                or self.quadratic_drag != 0.0)

    def dimensionless(self, mass, scales, start_time):
        """(A T²/Z, Ω T, Ω t₀ + ϕ, c₁ T/m, c₂ Z/m): the slots P_AMPLITUDE ... P_DRAG2 of a phase
        that starts at t₀ with the scales Z, T."""
        length, time = scales.length, scales.time
        return (self.acceleration_amplitude * time ** 2 / length,
                self.angular_frequency * time,
                self.angular_frequency * start_time + self.phase,
                self.linear_drag * time / mass,
                self.quadratic_drag * length / mass)


class PhaseIntegrator:
    """Steps one contact phase of a sphere (mass m) against a plate, with gravity g.

    Construct at the start of contact; call ``step()`` until ``lifted_off``.  Every step
    appends its end point to ``points`` (dimensional t, z, ż, F), as do the located peak
    force, the maximum penetration and lift-off, so that no peak is lost between steps.
    """

    def __init__(self, contact, mass, gravity, start_time, penetration, penetration_rate,
                 rtol=DEFAULT_RTOL, atol=DEFAULT_ATOL):
        self.contact = contact
        self.mass = mass
        self.start_time = start_time
        self.scales = sc = phase_scales(contact, mass, gravity, penetration, penetration_rate)
        law = contact.law
        self._n, self._p, self._q = law.n, law.p, law.q
        self._gamma, self._zeta = sc.gravity, sc.damping
        x0, u0 = penetration / sc.length, penetration_rate * sc.time / sc.length
        # The right-hand side vanishes at σ = 0, which misleads the automatic first step;
        # a contact lasts σ ≈ 1.8 in these units, so start at a step a few per cent of that.
        # Under gravity, heavy damping (ζ >> 1) makes the phase stiff: the sphere creeps into
        # its rest position on the damper's time scale.  Then the implicit Radau method, which
        # also provides step() and dense output.  (Without gravity DOP853 stays cheaper.)
        method = Radau if gravity > 0.0 and sc.damping > STIFF_DAMPING else DOP853
        self._solver = method(self._rhs, 0.0, np.array([x0, u0]), math.inf,
                              rtol=rtol, atol=atol, first_step=FIRST_STEP)
        self._last_dense = None
        self.lifted_off = False
        self.steps = 0
        self.peak_force = self.force_of(penetration, penetration_rate)
        if penetration <= 0.0 and law.p == 0.0 and penetration_rate > 0.0:
            # a law with p = 0 jumps to λ ż^q at touch: the peak may be that limit z -> 0+
            self.peak_force = max(self.peak_force, contact.damping * penetration_rate ** law.q)
        self.max_penetration = penetration
        self.end = None  # (t, z, ż) at lift-off
        self.points = [(start_time, penetration, penetration_rate, self.peak_force)]

    # -- dimensionless dynamics in σ = √τ -------------------------------------------------
    def _accel(self, x, u):
        # Unclamped beyond φ = 0: the phase ends at that located root anyway, and a smooth
        # right-hand side lets the step that crosses lift-off pass without rejections.
        if x <= 0.0:
            return self._gamma
        return self._gamma - x ** self._n - self._zeta * x ** self._p * (
            u if self._q == 1.0 else math.copysign(abs(u) ** self._q, u))

    def _rhs(self, s, y):
        x, u = y.tolist()
        return np.array((2.0 * s * u, 2.0 * s * self._accel(x, u)))

    def _phi(self, x, u):
        """x^(n-p) + ζ u|u|^(q-1): the force divided by xᵖ."""
        ux = u if self._q == 1.0 else math.copysign(abs(u) ** self._q, u)
        return (x if x > 0.0 else 0.0) ** (self._n - self._p) + self._zeta * ux

    def _force_slope(self, x, u):
        """x^(1-p) dF/dτ: changes sign from + to - at a force peak."""
        n, p = self._n, self._p
        phi = self._phi(x, u)
        a = self._gamma - max(x, 0.0) ** p * phi
        uq = 1.0 if self._q == 1.0 else self._q * abs(u) ** (self._q - 1.0)
        return p * u * phi + (n - p) * max(x, 0.0) ** (n - p) * u + self._zeta * uq * x * a

    # -- units --------------------------------------------------------------------------
    def force_of(self, z, zdot):
        return float(self.contact.force(z, zdot))

    def _dimensional(self, s, y):
        sc = self.scales
        t = self.start_time + sc.time * s * s
        z, zdot = float(y[0]) * sc.length, float(y[1]) * sc.length / sc.time
        return t, z, zdot

    @property
    def time(self):
        """Time (s) reached by the integrator (the end of its last step)."""
        return self.start_time + self.scales.time * self._solver.t ** 2

    def state_at(self, t):
        """(z, ż) at a time t within the last step, from the dense output."""
        s = math.sqrt(max(t - self.start_time, 0.0) / self.scales.time)
        y = self._dense(s)
        return self._dimensional(s, y)[1:]

    @property
    def state(self):
        return self._dimensional(self._solver.t, self._solver.y)[1:]

    def _dense(self, s):
        """y(s) inside the last step, from its dense output (built on first use)."""
        if self._last_dense is None:
            self._last_dense = self._solver.dense_output()
        sol = self._last_dense
        return sol(min(max(s, sol.t_min), sol.t_max))

    # -- stepping -----------------------------------------------------------------------
    def step(self):
        """Take one integrator step; locate peak, maximum penetration and lift-off in it.

        Events are tested at the step's ends first; the dense output (which costs extra
        stages) is built only for a step that holds a root, or when a state inside is asked.
        """
        solver = self._solver
        s0, y0 = solver.t, solver.y.copy()
        message = solver.step()
        if solver.status == 'failed':
            raise RuntimeError(f'contact integration failed: {message}')
        self.steps += 1
        self._last_dense = None
        s1, y1 = solver.t, solver.y

        # lift-off: the first root of x or φ going down in this step
        roots = []
        for g in (lambda yy: yy[0], lambda yy: self._phi(yy[0], yy[1])):
            if g(y0) > 0.0 and g(y1) <= 0.0:
                roots.append(self._root(g, s0, s1))
        s_end = min(roots) if roots else s1
        y_end = self._dense(s_end) if roots else y1

        found = []
        if s_end > s0:
            for g in (lambda yy: yy[1], lambda yy: self._force_slope(yy[0], yy[1])):
                if g(y0) > 0.0 and g(y_end) <= 0.0:     # maximum penetration, force peak
                    found.append(self._root(g, s0, s_end))
        for s in sorted(found):
            self._record(s, self._dense(s))
        if roots:
            self.lifted_off = True
            y_end[0] = max(y_end[0], 0.0)
            t, z, zdot = self._dimensional(s_end, y_end)
            self.end = (t, z, zdot)
            self.points.append((t, z, zdot, 0.0))
        else:
            self._record(s1, y1)

    def run(self, t_stop=math.inf, max_steps=None, stop_energy=-math.inf):
        """Step until lift-off, until ``time >= t_stop`` (s), for ``max_steps`` steps, or until a
        step that did not lift off ends with ``energy_above_rest() < stop_energy`` (J).

        Returns the number of steps taken.  (The same contract as ``CompiledPhase.run``.)
        """
        budget = math.inf if max_steps is None else max_steps
        taken = 0
        while not self.lifted_off and self.time < t_stop and taken < budget:
            self.step()
            taken += 1
            if not self.lifted_off and self.energy_above_rest() < stop_energy:
                break
        return taken

    def _root(self, g, s0, s1):
        """The root of g(y(s)) in [s0, s1] on the dense output, to machine precision."""
        return brentq(lambda s: g(self._dense(s)), s0, s1, xtol=1e-15, rtol=1e-15)

    def _record(self, s, y):
        t, z, zdot = self._dimensional(s, y)
        f = self.force_of(z, zdot)
        self.points.append((t, z, zdot, f))
        self.peak_force = max(self.peak_force, f)
        self.max_penetration = max(self.max_penetration, z)

    def energy_above_rest(self):
        """Mechanical energy (J) above static equilibrium at the integrator's current state."""
        z, zdot = self.state
        g = self.scales.gravity * self.scales.length / self.scales.time ** 2
        return energy_above_rest(self.contact, self.mass, g, z, zdot)


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
        self.contact = contact
        self.mass = mass
        self.start_time = start_time
        self.scales = sc = scales if scales is not None else phase_scales(
            contact, mass, gravity, penetration, penetration_rate)
        law = contact.law
        k, mass_g = contact.stiffness, mass * sc.gravity * sc.length / sc.time ** 2
        g = mass_g / mass                           # as PhaseIntegrator.energy_above_rest
        z0 = contact.static_penetration(mass_g)
        rest_potential = float(_potential(contact, mass, g, z0))
        # the layout of compiled.P_*; the forcing: gravity, and the terms of ``forcing``
        extra = (0.0,) * 5 if forcing is None else forcing.dimensionless(mass, sc, start_time)
        par = np.array([law.n, law.p, law.q, sc.damping,
                        sc.gravity, *extra,
                        start_time, sc.time, sc.length,
                        k, contact.damping, mass, g, rest_potential, rtol, atol,
                        float(law.kernel)])
        self._par = par
        self._st, self._k, self._f = compiled.new_state(
            penetration / sc.length, penetration_rate * sc.time / sc.length, FIRST_STEP)
        self._buffer = np.empty((compiled.POINT_BUFFER, 4))
        self._keep_points = keep_points
        # a generous margin on the energy test: the caller's own test has the last word
        self._energy_margin = 1e-12 * mass * (sc.length / sc.time) ** 2
        self.lifted_off = False
        self.steps = 0
        self.peak_force = compiled.contact_force(penetration, penetration_rate, par)
        if penetration <= 0.0 and law.p == 0.0 and penetration_rate > 0.0:
            # a law with p = 0 jumps to λ ż^q at touch: the peak may be that limit z -> 0+
            self.peak_force = max(self.peak_force, contact.damping * penetration_rate ** law.q)
        self.max_penetration = penetration
        self._st[compiled.S_PEAK], self._st[compiled.S_DEPTH] = self.peak_force, penetration
        self.end = None  # (t, z, ż) at lift-off
        self.points = [(start_time, penetration, penetration_rate, self.peak_force)]

    def run(self, t_stop=math.inf, max_steps=None, stop_energy=-math.inf):
        """Step until lift-off, until ``time >= t_stop`` (s), for ``max_steps`` steps, or until a
        step that did not lift off ends with ``energy_above_rest() < stop_energy`` (J) (the
        compiled test uses a margin of 1e-12 of the phase's kinetic energy scale, so it may stop
        a step before the caller's own test agrees, never after).  Returns the steps taken."""
        budget = compiled.MAX_STEPS if max_steps is None else int(min(max_steps, compiled.MAX_STEPS))
        stop = (stop_energy + abs(stop_energy) * 1e-9 + self._energy_margin
                if stop_energy > -math.inf else -math.inf)
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
        values = st.tolist()
        self.steps = int(values[compiled.S_STEPS])
        self.peak_force = values[compiled.S_PEAK]
        self.max_penetration = values[compiled.S_DEPTH]
        if values[compiled.S_LIFTED]:
            self.lifted_off = True
            self.end = (values[compiled.S_END_T], values[compiled.S_END_Z],
                        values[compiled.S_END_RATE])
        if reason == compiled.STEP_TOO_SMALL:
            raise RuntimeError('contact integration failed: Required step size is less than '
                               'spacing between numbers.')
        return taken

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
        s = math.sqrt(max(t - self.start_time, 0.0) / self.scales.time)
        x, u = compiled.state_in_last_step(self._st, self._k, self._f, self._par, s)
        return self._dimensional(s, x, u)[1:]

    def energy_above_rest(self):
        """Mechanical energy (J) above static equilibrium at the integrator's current state
        (``energy_above_rest``, evaluated in compiled code)."""
        return compiled.energy_above_rest(self._st, self._par)


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
                  forcing=None):
    """The integrator of one contact phase (see ``PhaseIntegrator`` for the arguments;
    ``keep_points=False`` lets the compiled phase skip its point list).

    ``forcing`` (a ``Forcing`` beyond gravity) needs the compiled engine, which then integrates
    the phase with DOP853 even when it is stiff.

    ``engine`` ('compiled' or 'scipy', default ``get_engine()``) picks ``CompiledPhase`` or
    ``PhaseIntegrator``; a heavily damped phase under gravity (ζ > COMPILED_STIFF_DAMPING, stiff)
    always gets ``PhaseIntegrator`` and its Radau method.
    """
    engine = get_engine() if engine is None else _check_engine(engine)
    if forcing is not None and forcing.active:
        if engine != 'compiled':
            raise ValueError(f'forcing = {forcing!r} needs the compiled engine: allowed '
                             f"engine = 'compiled' (not {engine!r}) or no forcing")
        return CompiledPhase(contact, mass, gravity, start_time, penetration, penetration_rate,
                             rtol=rtol, atol=atol, keep_points=keep_points, forcing=forcing)
    if engine == 'compiled':
        scales = phase_scales(contact, mass, gravity, penetration, penetration_rate)
        if not (gravity > 0.0 and scales.damping > COMPILED_STIFF_DAMPING):
            return CompiledPhase(contact, mass, gravity, start_time, penetration,
                                 penetration_rate, rtol=rtol, atol=atol, scales=scales,
                                 keep_points=keep_points)
    return PhaseIntegrator(contact, mass, gravity, start_time, penetration, penetration_rate,
                           rtol=rtol, atol=atol)


def _potential(contact, mass, gravity, z):
    """Spring energy k z₊^(n+1)/(n+1) minus gravity's work m g z (J)."""
    n = contact.law.n
    return contact.stiffness * np.maximum(z, 0.0) ** (n + 1.0) / (n + 1.0) - mass * gravity * z


def energy_above_rest(contact, mass, gravity, z, zdot):
    """½ m ż² + potential(z) - potential(z0): a Lyapunov function of the contact (J).

    It never increases (the damper only dissipates, flight conserves it), so once it is below
    ``lift_off_energy`` the sphere can never leave the plate again.
    """
    z0 = contact.static_penetration(mass * gravity)
    return (0.5 * mass * zdot ** 2 + _potential(contact, mass, gravity, z)
            - _potential(contact, mass, gravity, z0))


def lift_off_energy(contact, mass, gravity, margin=0.5):
    """A lower bound (J) on the energy above rest of any state in which the force is zero.

    Zero force means z <= 0, or z > 0 on the curve λ ż|ż|^(q-1) = -k z^(n-p); the minimum over
    that curve is taken on a fine logarithmic grid and multiplied by ``margin`` for safety.
    (Remembered per argument set: a drop asks it once per contact phase.)
    """
    return _lift_off_energy_cached(contact, float(mass), float(gravity), float(margin))


def _lift_off_energy(contact, mass, gravity, margin):
    law = contact.law
    z0 = contact.static_penetration(mass * gravity)
    candidates = [energy_above_rest(contact, mass, gravity, 0.0, 0.0)]
    if contact.damping > 0.0:
        z = z0 * np.logspace(-8.0, 2.0, 2001)
        speed = (contact.stiffness * z ** (law.n - law.p) / contact.damping) ** (1.0 / law.q)
        candidates.append(float(np.min(energy_above_rest(contact, mass, gravity, z, speed))))
    return margin * min(candidates)


_lift_off_energy_cached = functools.lru_cache(maxsize=256)(_lift_off_energy)

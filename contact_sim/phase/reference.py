"""The reference path of one contact phase: scipy's DOP853 (Radau when stiff) stepped from Python.

The mathematics of ``phase`` (the integration in σ = √τ, lift-off at x = 0 or φ = 0 as
``lift_off`` says, events located on the dense output by Brent's method), written plainly:
the path the compiled engine is tested against.  Heavily damped phases that creep (into rest
under gravity, or out to the surface when the force cannot vanish inside) are stiff: above
ζ = STIFF_DAMPING they are integrated with scipy's Radau.
"""
import bisect
import math
from operator import itemgetter

import numpy as np
from scipy.integrate import DOP853, Radau
from scipy.optimize import brentq

from contact_sim.phase.energy import energy_above_rest
from contact_sim.phase.lift_off import force_can_vanish_inside, is_stiff
from contact_sim.phase.scales import (DEFAULT_ATOL, DEFAULT_RTOL, FIRST_STEP, phase_scales,
                                      start_peak_force)

_TIME = itemgetter(0)   # a point's time (points are (t, z, ż, F))
STIFF_DAMPING = 30.0   # ζ above which a phase is integrated by Radau instead of DOP853


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
        self._linear_in_rate = law.linear_in_rate      # q = 1: the rate term is u itself
        self._gamma, self._zeta = sc.gamma, sc.zeta
        self._lift_events = ((lambda yy: yy[0], lambda yy: self._phi(yy[0], yy[1]))
                             if force_can_vanish_inside(law, gravity) else
                             (lambda yy: yy[0],))
        x0, u0 = penetration / sc.length, penetration_rate * sc.time / sc.length
        # The first step is FIRST_STEP (the right-hand side vanishes at σ = 0).
        # Heavy damping (ζ >> 1) makes a phase stiff where the sphere creeps on the damper's
        # time scale: into rest under gravity, or out to the surface when its force cannot
        # vanish inside (Hunt-Crossley).  Then the implicit Radau method, which also provides
        # step() and dense output.  (A phase that ends at a force zero stays cheaper on DOP853.)
        method = Radau if is_stiff(law, gravity, sc.zeta, STIFF_DAMPING) else DOP853
        self._solver = method(self._rhs, 0.0, np.array([x0, u0]), math.inf,
                              rtol=rtol, atol=atol, first_step=FIRST_STEP)
        self._last_dense = None
        self.lifted_off = False
        self.steps = 0
        self.peak_force = start_peak_force(contact, penetration, penetration_rate,
                                           self.force_of(penetration, penetration_rate))
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
            u if self._linear_in_rate else math.copysign(abs(u) ** self._q, u))

    def _rhs(self, s, y):
        x, u = y.tolist()
        return np.array((2.0 * s * u, 2.0 * s * self._accel(x, u)))

    def _phi(self, x, u):
        """x^(n-p) + ζ u|u|^(q-1): the force divided by xᵖ."""
        ux = u if self._linear_in_rate else math.copysign(abs(u) ** self._q, u)
        return (x if x > 0.0 else 0.0) ** (self._n - self._p) + self._zeta * ux

    def _force_slope(self, x, u):
        """x^(1-p) dF/dτ: changes sign from + to - at a force peak."""
        n, p = self._n, self._p
        phi = self._phi(x, u)
        a = self._gamma - max(x, 0.0) ** p * phi
        uq = 1.0 if self._linear_in_rate else self._q * abs(u) ** (self._q - 1.0)
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

        # lift-off: the first root of x or φ (if it can vanish inside) going down in this step
        roots = []
        for g in self._lift_events:
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

    def points_after(self, first, after, until):
        """(rows, end): the points of index ``first`` on with times in (``after``, ``until``]
        (s), an (n, 4) array of rows (t, z, ż, F), and the index after the last of them (as
        ``CompiledPhase.points_after``)."""
        points = self.points
        start = bisect.bisect_right(points, after, lo=first, key=_TIME)
        end = bisect.bisect_right(points, until, lo=start, key=_TIME)
        return np.array(points[start:end], dtype=float).reshape(-1, 4), end

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
        g = self.scales.gamma * self.scales.length / self.scales.time ** 2
        return energy_above_rest(self.contact, self.mass, g, z, zdot)

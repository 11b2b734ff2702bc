"""Closed forms of the dimensionless impact: exact results of two laws as functions of ζ alone.

Without gravity an impact reduces to x'' = -xⁿ - ζ xᵖ x'|x'|^(q-1), x(0) = 0, x'(0) = 1, with
the one damping group ζ (``impact`` derives it).  Two laws have exact solutions:

* Hunt-Crossley (n = p = 3/2, q = 1) has the first integral v/ζ - ln(1 + ζ v)/ζ² + (2/5) x^(5/2)
  = const, so u = 1 - ζ e solves u - ln u = 1 + ζ - ln(1 + ζ): u = -W₀(-exp(-1 - ζ + ln(1 + ζ)))
  (Lambert W), found by Newton's method on the well-conditioned form (compiled for arrays); its
  duration is a quadrature of the same integral.
* The clamped linear law separates when x + ζ x' = 0, which gives e = exp(-ζ τc / 2) with
  τc = atan2(ζ ω, ζ²/2 - 1) / ω, ω = √(1 - ζ²/4), and past critical damping (ζ > 2)
  τc = ln(ζ²/2 - 1 + ζκ) / κ, κ = √(ζ²/4 - 1).

These are facts of the model (pure functions of ζ, no time stepping), so they live beside the
laws: ``laws`` attaches each ``ClosedForm`` to its law, and ``impact`` asks the law for it.
"""
import functools
import math
import warnings
from dataclasses import dataclass

import numpy as np

from contact_sim.model.hunt_crossley_scalar import hunt_crossley_restitution_scalar

HC_QUADRATURE_FROM = 0.1   # ζ from which the Hunt-Crossley duration comes from its first integral


@dataclass(frozen=True)
class ClosedForm:
    """Exact dimensionless results of one law.

    ``vector`` maps a quantity ('restitution', 'duration', ...) to a function of an array of
    ζ > 0; ``scalar`` is e(ζ) for one float ζ > 0 in plain Python (or ``None``);
    ``table_duration`` is ``(ζ0, τc)``: the exact (slow) duration τc(ζ) for one float ζ >= ζ0,
    which the master curve is built from where integrating the impact is ill-conditioned (the
    force fades long before it is exactly zero), or ``None``.
    """

    vector: dict
    scalar: object = None
    table_duration: tuple = None


# the table of e(ζ) that starts the vectorised Hunt-Crossley iteration: uniform in ln ζ over
# [1e-6, 64] (above 64, c > 59 and u = exp(-1 - c) < 1e-26 is exact at once)
HC_TABLE_ZETA = (1e-6, 64.0)
HC_TABLE_INTERVALS = 2048


@functools.cache
def hunt_crossley_table():
    """Cubic Hermite pieces of the Hunt-Crossley e(ζ) on a uniform grid in ln ζ.

    The values come from the full iteration (``hunt_crossley_restitution_scalar``, compiled),
    the slopes from the first integral: de/d ln ζ = (1 - ζ e) / ((1 + ζ) e) - e (from
    g(-s) = g(ζ), g(x) = x - ln(1 + x), s = ζ e).  Within 1e-10 of e over the table
    (``test/model``), far inside the one-step bound ``ONE_STEP_GUESS_RTOL``.  Built at the
    first call (about 1 ms).

    Returns
    -------
    tuple
        (s0, h, coef): the grid ln ζ = s0 + h i and the (intervals, 4) array of the pieces'
        coefficients a, b, c, d of a t³ + b t² + c t + d, t = ln ζ - s0 - h i.
    """
    from contact_sim.model.closed_form_kernels import hunt_crossley_restitution_many
    s0, s1 = math.log(HC_TABLE_ZETA[0]), math.log(HC_TABLE_ZETA[1])
    h = (s1 - s0) / HC_TABLE_INTERVALS
    zeta = np.exp(s0 + h * np.arange(HC_TABLE_INTERVALS + 1))
    e = np.empty(zeta.size)
    hunt_crossley_restitution_many(zeta, e)
    slope = (1.0 - zeta * e) / ((1.0 + zeta) * e) - e
    rise = np.diff(e) / h
    coef = np.stack([(slope[:-1] + slope[1:] - 2.0 * rise) / h ** 2,
                     (3.0 * rise - 2.0 * slope[:-1] - slope[1:]) / h, slope[:-1], e[:-1]], axis=1)
    return s0, h, np.ascontiguousarray(coef)


def hunt_crossley_restitution(zeta):
    """Exact e(ζ) of the Hunt-Crossley law (n = p = 3/2, q = 1), vectorised, ζ > 0: the
    algorithm of ``hunt_crossley_restitution_scalar`` compiled (numba), element by element,
    started from ``hunt_crossley_table`` so that one Newton step finishes it (1.4e7 ζ per
    second through ``impact.dimensionless``, 9.7e6 speeds per second through ``restitution``,
    at a load of 3.4: ``python bench/bench_restitution.py``)."""
    zeta = np.asarray(zeta, dtype=float)
    flat = np.ascontiguousarray(zeta).ravel()
    out = np.empty(flat.size)
    from contact_sim.model.closed_form_kernels import hunt_crossley_restitution_tabled
    hunt_crossley_restitution_tabled(flat, out, *hunt_crossley_table())   # (numba: imported at
    return out.reshape(zeta.shape)                                        # the first call only)


def hunt_crossley_duration(zeta):
    """Exact contact duration τc of the Hunt-Crossley law at ζ > 0, by quadrature of its first
    integral (used to build the master curve where integrating the impact is ill-conditioned).

    With w = ζ x', the first integral reads w - ln(1 + w) = d(x), d = c (1 - (x/x̂)^(5/2)),
    c = ζ - ln(1 + ζ), x̂ = (c / (0.4 ζ²))^(2/5): w > 0 on the approach, -1 < w < 0 on the
    return.  The force x^(3/2) (1 + w) stays positive until x = 0, so
    τc = ζ ∫₀^x̂ (1/w_in - 1/w_out) dx, integrated in s with x = x̂ (1 - s²) (which removes the
    1/√ at x̂, and gives d = -c expm1(2.5 log1p(-s²)) without cancellation).
    """
    c = zeta - math.log1p(zeta) if zeta >= 1e-3 else \
        zeta * zeta * (0.5 - zeta * (1 / 3 - zeta * (0.25 - zeta / 5)))
    top = (c / (0.4 * zeta * zeta)) ** 0.4

    def branch(d, w):
        for _ in range(100):          # Newton on w - ln(1 + w) - d (convex in w)
            g = w - math.log1p(w) - d if abs(w) > 1e-4 else \
                w * w * (0.5 - w * (1 / 3 - w * (0.25 - w / 5))) - d
            step = g * (1.0 + w) / w
            w_new = w - step
            if w_new <= -1.0:
                w_new = 0.5 * (w - 1.0)
            if abs(w_new - w) <= 1e-15 * abs(w):
                return w_new
            w = w_new
        return w

    def integrand(s):
        if s == 0.0:
            s = 1e-300
        d = -c * math.expm1(2.5 * math.log1p(-s * s))
        w_in = branch(d, math.sqrt(2.0 * d) if d < 1.0 else d + math.log1p(d))
        if d < 0.5:
            w_out = branch(d, -math.sqrt(2.0 * d))
        else:                                  # in u = 1 + w, which may be tiny: Newton on
            u = math.exp(-1.0 - d)             # u - ln u - 1 - d from the left (monotone)
            for _ in range(100):
                if u == 0.0:
                    break
                step = (u - math.log(u) - 1.0 - d) / (1.0 - 1.0 / u)
                u -= step
                if abs(step) <= 1e-16 * u:
                    break
            w_out = u - 1.0
        return 2.0 * top * s * zeta * (1.0 / w_in - 1.0 / w_out)

    from scipy.integrate import quad   # here: importing the model (and the command line's
    # argument parsing) does not import scipy's integrators and solvers
    with warnings.catch_warnings():
        warnings.simplefilter('ignore')       # quad's round-off notice at the 1e-12 request
        value, _ = quad(integrand, 0.0, 1.0, epsabs=0.0, epsrel=1e-12, limit=200)
    return value


def linear_restitution_scalar(zeta):
    """``linear_restitution_and_duration(ζ)[0]`` for one float in plain Python."""
    disc = 1.0 - zeta * zeta / 4.0
    if disc > 0.0:
        w = math.sqrt(disc)
        tau = math.atan2(zeta * w, zeta * zeta / 2.0 - 1.0) / w
    elif disc < 0.0:
        kappa = math.sqrt(-disc)
        tau = math.log(zeta * zeta / 2.0 - 1.0 + zeta * kappa) / kappa   # = atanh(ζκ/(ζ²/2-1))/κ
    else:
        tau = 2.0
    return math.exp(-zeta * tau / 2.0)


def linear_restitution_and_duration(zeta):
    """Exact (e, τc) of the clamped linear law for ζ = λ / √(m k) > 0; τc in units √(m/k)."""
    zeta = np.asarray(zeta, dtype=float)
    disc = 1.0 - zeta ** 2 / 4.0
    under = disc > 0.0
    over = disc < 0.0
    w = np.sqrt(np.where(under, disc, 1.0))
    kappa = np.sqrt(np.where(over, -disc, 1.0))
    tau_under = np.arctan2(zeta * w, zeta ** 2 / 2.0 - 1.0) / w
    # atanh(ζκ / (ζ²/2 - 1)) = ln(ζ²/2 - 1 + ζκ), since (ζ²/2 - 1)² - (ζκ)² = 1
    tau_over = np.log(np.where(over, zeta ** 2 / 2.0 - 1.0 + zeta * kappa, 1.0)) / kappa
    tau = np.where(under, tau_under, np.where(over, tau_over, 2.0))
    return np.exp(-zeta * tau / 2.0), tau


def _linear_duration(zeta):
    return float(linear_restitution_and_duration(zeta)[1])


HUNT_CROSSLEY_FORM = ClosedForm({'restitution': hunt_crossley_restitution},
                                hunt_crossley_restitution_scalar,
                                (HC_QUADRATURE_FROM, hunt_crossley_duration))
LINEAR_FORM = ClosedForm({'restitution': lambda z: linear_restitution_and_duration(z)[0],
                          'duration': lambda z: linear_restitution_and_duration(z)[1]},
                         linear_restitution_scalar, (0.0, _linear_duration))

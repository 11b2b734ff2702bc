"""The bouncing ball on a vibrating table: closed-form thresholds and the engine's bounce series.

A table moves as s(t) = a sin(ω t + ϕ), Γ = a ω² / g.  With a constant restitution e and
instantaneous impacts (the linear law with short contacts), the exact impact map is

    flight:  s(t_k) + v_k Δ - ½ g Δ² = s(t_k + Δ),   Δ = t_(k+1) - t_k,
    impact:  v_(k+1) = -e (v_k - g Δ) + (1 + e) ṡ(t_(k+1))      (v: the ball's velocity, up > 0)

Period-1 (one bounce per table period T = 2π/ω, at the same phase θ): the ball must come back to
the same height after T, so it leaves at V = g T / 2 = π g / ω, and the impact law gives the
table's velocity there, u = V (1 - e)/(1 + e) = a ω cos θ.  It exists when |u| <= a ω:

    Γ cos θ = π (1 - e)/(1 + e),    so   Γ₁(e) = π (1 - e)/(1 + e).

Linearising the map about it (δt' = δt + c δv with c = T/(u + V) = (1 + e)/g; δv' = (1 + e) s̈ δt
+ (e g c - e + (1 + e) s̈ c) δv) gives det J = e² and tr J = 1 + e² + (1 + e)² s̈/g with s̈ = -a ω²
sin θ.  The eigenvalue +1 (tr = 1 + det) is at sin θ = 0, i.e. Γ = Γ₁ (saddle-node); the
eigenvalue -1 (tr = -(1 + det)) at Γ sin θ = 2 (1 + e²)/(1 + e)², so with Γ² = (Γ cos θ)² +
(Γ sin θ)²

    Γ₂(e) = √( (π (1 - e)/(1 + e))² + (2 (1 + e²)/(1 + e)²)² ),

and period-1 is stable on the branch sin θ > 0 for Γ₁ < Γ < Γ₂ (it needs no high-bounce
approximation: the flight equation is exact).  ``test/test_table.py`` finds both thresholds in the
full engine within 1 % at three values of e.
"""
import math
from dataclasses import dataclass

import numpy as np

from contact_sim.drop.engine import DropSimulation
from contact_sim.drop.limits import GRAVITY_MAX, require_height, require_mass
from contact_sim.drop.plate import (TABLE_ACCELERATION_MAX, TABLE_AMPLITUDE_MAX,
                                    TABLE_FREQUENCY_MAX, SinusoidalPlate)
from contact_sim.model import require_contact
from contact_sim.validation import require_int, require_positive, require_range

MAX_TABLE_IMPACTS = 1_000_000     # bounces (and transient impacts) of one VibratingTable call
MAX_TABLE_PERIODS = 10 ** 7       # table periods one call may simulate


def period_one_threshold(restitution):
    """The table's Γ above which the period-1 bouncing exists, Γ₁(e) = π (1 - e)/(1 + e).

    Parameters
    ----------
    restitution : float
        A constant restitution e, 0 <= e <= 1.

    Returns
    -------
    float
        Γ₁ = a ω²/g, dimensionless.

    Raises
    ------
    InputError
        Keyed ``restitution``: out of range.

    Examples
    --------
    >>> from contact_sim.drop import period_one_threshold
    >>> print(f"{period_one_threshold(0.7):.4f}")
    0.5544
    """
    e = require_range('restitution', restitution, 0.0, 1.0)
    return math.pi * (1.0 - e) / (1.0 + e)


def period_doubling_threshold(restitution):
    """The Γ above which the period-1 bouncing loses stability.

    Γ₂(e) = √(Γ₁² + (2 (1 + e²)/(1 + e)²)²).

    Parameters
    ----------
    restitution : float
        A constant restitution e, 0 <= e <= 1.

    Returns
    -------
    float
        Γ₂, dimensionless.

    Raises
    ------
    InputError
        Keyed ``restitution``: out of range.

    Examples
    --------
    >>> from contact_sim.drop import period_doubling_threshold
    >>> print(f"{period_doubling_threshold(0.7):.4f}")
    1.1707
    """
    e = require_range('restitution', restitution, 0.0, 1.0)
    return math.hypot(period_one_threshold(e), 2.0 * (1.0 + e * e) / (1.0 + e) ** 2)


def period_one_phase(restitution, gamma):
    """The table's phase θ (rad) at the impacts of the stable period-1 motion (sin θ >= 0):
    cos θ = Γ₁/Γ; ``ValueError`` below Γ₁."""
    g1 = period_one_threshold(restitution)
    gamma = require_positive('gamma', gamma)
    if gamma < g1:
        raise ValueError(f'gamma = {gamma!r} is out of range: allowed gamma >= Γ₁ = {g1:.6g}')
    return math.acos(g1 / gamma)


@dataclass(frozen=True)
class VibratingTable:
    """A sphere bouncing on a table vibrating at ``frequency`` (Hz) with the full engine.

    Called with Γ, it runs ``transient + bounces`` impacts (the sphere starts from the table on the
    constant-e period-1 orbit at ``restitution_guess``, or dropped from ``start_height`` below Γ₁)
    and returns the table phases ωt mod 2π (rad) of the last ``bounces`` impacts: the points of
    the bifurcation diagram.  Picklable: a ``sweep`` sends it to worker processes.
    ``max_periods`` bounds the simulated time (a sphere the table carries stops bouncing).

    Attributes
    ----------
    contact : Contact
        The contact (law, k, λ).
    mass : float
        The sphere's mass, kg.
    frequency : float
        The table's frequency f, Hz, > 0 (default 10).
    bounces : int
        Impacts returned per Γ, >= 1 (default 300).
    transient : int
        Impacts left out first, >= 0 (default 100).
    gravity : float
        Gravity g, m/s², > 0 (default 9.81).
    restitution_guess : float
        The e of the period-1 orbit the sphere starts on, 0 < e < 1 (default 0.7).
    start_height : float
        The drop height below Γ₁, m (default 0.01).
    max_periods : int
        Table periods simulated at most, >= 1 (default 5000).

    Raises
    ------
    InputError
        Keyed by the field out of its range.

    See Also
    --------
    bifurcation_diagram : The table called over many Γ.

    Examples
    --------
    >>> import contact_sim as cs
    >>> from contact_sim.drop import VibratingTable
    >>> contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron',
    ...                                     radius=0.0127, damping_factor=8.87e5)
    >>> table = VibratingTable(contact, cs.build_mass(sphere='steel', radius=0.0127),
    ...                        frequency=20.0, bounces=4, transient=20)
    >>> phases = table(1.0)                # Γ = 1: the period-1 orbit
    >>> print(*(f"{phase:.1f}" for phase in phases))
    1.2 1.2 1.2 1.2
    """

    contact: object
    mass: float
    frequency: float = 10.0
    bounces: int = 300
    transient: int = 100
    gravity: float = 9.81
    restitution_guess: float = 0.7
    start_height: float = 0.01
    max_periods: int = 5000

    def __post_init__(self):
        require_contact(self.contact)
        for name, value in (('mass', require_mass(self.mass)),
                            ('frequency', require_range('frequency', self.frequency, 0.0,
                                                        TABLE_FREQUENCY_MAX, low_open=True,
                                                        unit='Hz')),
                            ('bounces', require_int('bounces', self.bounces, 1, MAX_TABLE_IMPACTS)),
                            ('transient', require_int('transient', self.transient, 0,
                                                      MAX_TABLE_IMPACTS)),
                            ('gravity', require_range('gravity', self.gravity, 0.0, GRAVITY_MAX,
                                                      low_open=True, unit='m/s^2')),
                            ('restitution_guess', require_range('restitution_guess',
                                                                self.restitution_guess, 0.0, 1.0,
                                                                low_open=True, high_open=True)),
                            ('start_height', require_height(self.start_height)),
                            ('max_periods', require_int('max_periods', self.max_periods, 1,
                                                        MAX_TABLE_PERIODS))):
            object.__setattr__(self, name, value)

    def gamma_max(self):
        """The largest Γ = a ω²/g a table at this frequency reaches within its ranges.

        The ranges are ``plate.TABLE_AMPLITUDE_MAX`` and ``plate.TABLE_ACCELERATION_MAX``.

        Returns
        -------
        float
            Γ, dimensionless.
        """
        w = 2.0 * math.pi * self.frequency
        return min(TABLE_ACCELERATION_MAX, TABLE_AMPLITUDE_MAX * w * w) / self.gravity

    def run(self, gamma):
        """Run the table at Γ and return all its impacts.

        Parameters
        ----------
        gamma : float
            Γ = a ω²/g, 0 <= Γ <= ``gamma_max()``.

        Returns
        -------
        tuple of numpy.ndarray
            (impact times s, table phases ωt mod 2π rad, impact speeds m/s).

        Raises
        ------
        InputError
            Keyed ``gamma``: out of range.
        """
        top = self.gamma_max()
        gamma = require_range('gamma', gamma, 0.0, top)
        w = 2.0 * math.pi * self.frequency
        amplitude = gamma * self.gravity / w ** 2
        g1 = period_one_threshold(self.restitution_guess)
        if gamma >= g1:
            theta = math.acos(g1 / gamma)
            height, velocity = 0.0, -math.pi * self.gravity / w
        else:
            theta, height, velocity = 0.0, self.start_height, 0.0
        sim = DropSimulation(self.contact, self.mass, height, velocity=velocity,
                             gravity=self.gravity, plate=SinusoidalPlate(amplitude,
                                                                         self.frequency, theta))
        period, total = 1.0 / self.frequency, self.bounces + self.transient
        t = 0.0
        while len(sim.impacts) < total and t < self.max_periods * period and not (
                sim.carried and t > 10 * period):
            t += 20.0 * period
            sim.run_to(t)
        times = np.array([im.time for im in sim.impacts[:total]])
        speeds = np.array([im.impact_speed for im in sim.impacts[:total]])
        return times, np.mod(w * times + theta, 2.0 * math.pi), speeds

    def __call__(self, gamma):
        return self.run(gamma)[1][self.transient:]

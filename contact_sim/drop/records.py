"""What a drop produces: its states, samples, impacts and the results of ``advance``,
``advance_ticks`` and ``simulate_drop``, and the ``Recorder`` that keeps the impacts, apexes and
integrator steps as the engine's modes report them.  Units: SI."""
import math
from dataclasses import dataclass, field

import numpy as np

@dataclass(frozen=True)
class DropState:
    """The sphere at one instant: time (s), penetration z (m), rate ż (m/s), force F (N).

    With a moving plate z = p - y is relative to the plate's surface at height p (m, moving at
    ṗ m/s): ``plate_position``, ``plate_velocity``; F acts up on the sphere, -F on the plate.

    Attributes
    ----------
    time : float
        Time t, s.
    penetration : float
        Penetration z, m (> 0 in contact; -z: the height of the lowest point above the plate).
    penetration_rate : float
        Penetration rate ż, m/s (> 0 is approach).
    force : float
        Force F, N, on the sphere (up), >= 0.
    plate_position : float
        Plate position p, m (0 for the fixed plate).
    plate_velocity : float
        Plate velocity ṗ, m/s (0 for the fixed plate).

    Examples
    --------
    >>> import contact_sim as cs
    >>> contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron',
    ...                                     radius=0.0127, damping_factor=8.87e5)
    >>> mass = cs.build_mass(sphere='steel', radius=0.0127)
    >>> sim = cs.DropSimulation(contact, mass, height=0.1)
    >>> state = sim.state
    >>> state.time, state.penetration, state.in_contact
    (0.0, -0.1, False)
    """

    time: float
    penetration: float
    penetration_rate: float
    force: float
    plate_position: float = 0.0
    plate_velocity: float = 0.0

    @property
    def plate_force(self):
        """The contact's reaction on the plate (N, up positive): -F."""
        return -self.force

    @property
    def in_contact(self):
        """True while the contact pushes (F > 0)."""
        return self.force > 0.0


@dataclass(frozen=True)
class Samples:
    """Sampled trajectory: equal-length arrays of t (s), z (m), ż (m/s) and F (N).

    F is the force on the sphere (up); ``plate_force`` = -F is its reaction on the plate.  With a
    moving plate, z and ż are relative to the plate; ``DropSimulation.plate_samples`` gives p, ṗ.

    Attributes
    ----------
    time : numpy.ndarray
        Time t, s, non-decreasing.
    penetration : numpy.ndarray
        Penetration z, m.
    penetration_rate : numpy.ndarray
        Penetration rate ż, m/s (> 0 is approach).
    force : numpy.ndarray
        Force F, N, on the sphere.

    Examples
    --------
    >>> import contact_sim as cs
    >>> contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron',
    ...                                     radius=0.0127, damping_factor=8.87e5)
    >>> mass = cs.build_mass(sphere='steel', radius=0.0127)
    >>> result = cs.simulate_drop(contact, mass, 0.1, duration=0.2, sample_rate=1000)
    >>> samples = result.trajectory
    >>> print(f"{samples.time[0]:.1f} to {samples.time[-1]:.1f} s")
    0.0 to 0.2 s
    >>> print(f"peak {samples.force.max():.0f} N")
    peak 3003 N
    """

    time: np.ndarray
    penetration: np.ndarray
    penetration_rate: np.ndarray
    force: np.ndarray

    @classmethod
    def from_points(cls, points):
        """Samples from rows (t, z, ż, F).

        Parameters
        ----------
        points : array_like of float
            Rows (t s, z m, ż m/s, F N), any shape of 4·N values.

        Returns
        -------
        Samples
            The samples, copied.

        Examples
        --------
        >>> import contact_sim as cs
        >>> samples = cs.Samples.from_points([(0.0, -0.1, 0.0, 0.0), (0.1, -0.05, 1.0, 0.0)])
        >>> samples.penetration.tolist()
        [-0.1, -0.05]
        """
        arr = np.asarray(points, dtype=float).reshape(-1, 4)
        return cls(*(arr[:, i].copy() for i in range(4)))

    @classmethod
    def concatenate(cls, parts):
        """The samples of ``parts`` one after the other.

        Parameters
        ----------
        parts : sequence of Samples
            The parts, in time order.

        Returns
        -------
        Samples
            Their concatenation (empty arrays for no parts).

        Examples
        --------
        >>> import contact_sim as cs
        >>> part = cs.Samples.from_points([(0.0, -0.1, 0.0, 0.0), (0.1, -0.05, 1.0, 0.0)])
        >>> cs.Samples.concatenate([part, part]).time.size
        4
        """
        return cls(*(np.concatenate([getattr(p, f) for p in parts]) if parts else np.empty(0)
                     for f in ('time', 'penetration', 'penetration_rate', 'force')))

    @property
    def plate_force(self):
        """The reaction on the plate (N, up positive): -F."""
        return -self.force


@dataclass(frozen=True)
class ImpactRecord:
    """One contact phase: when it began (s), speeds (m/s), restitution, duration (s), peak (N).

    The final, permanent contact has rebound_speed = restitution = 0 and contact_duration = inf.

    Attributes
    ----------
    time : float
        The touch, s.
    impact_speed : float
        The approach speed at touch, m/s.
    rebound_speed : float
        The separation speed at lift-off, m/s.
    restitution : float
        ``rebound_speed / impact_speed``.
    contact_duration : float
        Touch to lift-off, s (``inf`` for the permanent contact).
    peak_force : float
        The largest force, N.
    max_penetration : float
        The deepest penetration, m.

    Examples
    --------
    >>> import contact_sim as cs
    >>> contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron',
    ...                                     radius=0.0127, damping_factor=8.87e5)
    >>> mass = cs.build_mass(sphere='steel', radius=0.0127)
    >>> first = cs.simulate_drop(contact, mass, 0.1, duration=0.2).impacts[0]
    >>> print(f"t = {first.time:.4f} s, v = {first.impact_speed:.4f} m/s, "
    ...       f"e = {first.restitution:.4f}")
    t = 0.1428 s, v = 1.4007 m/s, e = 0.7236
    >>> first.permanent
    False
    """

    time: float
    impact_speed: float
    rebound_speed: float
    restitution: float
    contact_duration: float
    peak_force: float
    max_penetration: float

    @property
    def permanent(self):
        """True for the final, permanent contact (``contact_duration`` is inf)."""
        return math.isinf(self.contact_duration)

    @classmethod
    def _of_contact(cls, impact_point, rebound_speed, contact_duration, peak_force,
                    max_penetration):
        """The record of a contact that began at ``impact_point`` (t s, z m, ż m/s, F N), with
        the rest of its fields: the one place the drop makes one (``Recorder``), beside the
        fields it fills."""
        impact_time, _, impact_rate, _ = impact_point
        impact_speed = max(impact_rate, 0.0)
        return cls(impact_time, impact_speed, rebound_speed,
                   rebound_speed / impact_speed if impact_speed > 0.0 else 0.0,
                   contact_duration, peak_force, max_penetration)


@dataclass(frozen=True)
class AdvanceResult:
    """What one ``DropSimulation.advance`` call produced.

    Attributes
    ----------
    samples : Samples
        The contact points passed and the state reached (the last sample).
    impacts : tuple of ImpactRecord
        The impacts completed in the call.
    apex_heights : tuple of float
        The apex heights (m) of the flights begun in the call.

    Examples
    --------
    >>> import contact_sim as cs
    >>> contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron',
    ...                                     radius=0.0127, damping_factor=8.87e5)
    >>> mass = cs.build_mass(sphere='steel', radius=0.0127)
    >>> sim = cs.DropSimulation(contact, mass, height=0.1)
    >>> advance = sim.advance(0.2)
    >>> len(advance.impacts), round(advance.apex_heights[0], 4)
    (1, 0.0523)
    """

    samples: Samples
    impacts: tuple
    apex_heights: tuple = ()


@dataclass(frozen=True)
class TickBatch:
    """What one ``DropSimulation.advance_ticks`` call produced, as arrays (SI units).

    ``ticks`` tick times of the call were reached (the first ``ticks``; fewer than asked when the
    step budget ran out).  Per tick reached, its end's state: ``time`` (s), ``penetration`` z
    (m), ``penetration_rate`` ż (m/s), ``force`` F (N, on the sphere; -F on the plate),
    ``plate_position`` p (m) and ``plate_velocity`` ṗ (m/s) (0 for the fixed plate), the same
    numbers as ``DropSimulation.state`` after ``advance`` to that time.  ``points`` (``Samples``)
    are the contact points passed, in time order, without the tick ends; ``point_tick[i]`` is the
    index of the tick point i belongs to (``ticks`` for the points of the tick the budget stopped
    in: its last point is the state reached, as ``advance`` returns it).  ``impacts`` completed,
    with ``impact_tick`` (the same indexing), and the ``apex_heights`` of the flights begun.

    Attributes
    ----------
    ticks : int
        The number of tick times reached.
    time, penetration, penetration_rate, force : numpy.ndarray
        Per tick reached: t (s), z (m), ż (m/s), F (N).
    plate_position, plate_velocity : numpy.ndarray
        Per tick reached: p (m), ṗ (m/s).
    points : Samples
        The contact points passed.
    point_tick : numpy.ndarray
        The tick index of each point.
    impacts : tuple of ImpactRecord
        The impacts completed.
    impact_tick : numpy.ndarray
        The tick index of each impact.
    apex_heights : tuple of float
        The apex heights (m) of the flights begun.

    Examples
    --------
    >>> import contact_sim as cs
    >>> contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron',
    ...                                     radius=0.0127, damping_factor=8.87e5)
    >>> mass = cs.build_mass(sphere='steel', radius=0.0127)
    >>> import numpy as np
    >>> sim = cs.DropSimulation(contact, mass, height=0.1)
    >>> batch = sim.advance_ticks(np.arange(1, 11) * 0.01)   # ten 10 ms ticks, in flight
    >>> batch.ticks, len(batch.impacts)
    (10, 0)
    >>> print(f"{batch.penetration[-1]:.5f} m")
    -0.05095 m
    """

    ticks: int
    time: np.ndarray
    penetration: np.ndarray
    penetration_rate: np.ndarray
    force: np.ndarray
    plate_position: np.ndarray
    plate_velocity: np.ndarray
    points: Samples
    point_tick: np.ndarray
    impacts: tuple
    impact_tick: np.ndarray
    apex_heights: tuple = ()


@dataclass(frozen=True)
class DropResult:
    """Outcome of ``simulate_drop``; ``trajectory`` is ``None`` unless a sample rate was given.

    Attributes
    ----------
    impacts : tuple of ImpactRecord
        Every contact phase, in time order (the last one permanent if reached).
    apex_heights : tuple of float
        The apex height (m) of each flight after a lift-off.
    permanent_contact_time : float
        When the landing for good began, s (nan if not reached).
    settle_time : float
        When the closed-form rest took over, s (nan if not reached).
    steps : int
        Integrator steps taken.
    duration : float
        The time simulated, s.
    trajectory : Samples or None
        The sampled trajectory (with ``sample_rate``).

    Examples
    --------
    >>> import contact_sim as cs
    >>> contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron',
    ...                                     radius=0.0127, damping_factor=8.87e5)
    >>> mass = cs.build_mass(sphere='steel', radius=0.0127)
    >>> result = cs.simulate_drop(contact, mass, 0.1, duration=2.0)
    >>> print(f"at rest for good from t = {result.permanent_contact_time:.3f} s")
    at rest for good from t = 1.065 s
    >>> result.impacts[-1].permanent, result.trajectory is None
    (True, True)
    """

    impacts: tuple
    apex_heights: tuple
    permanent_contact_time: float
    settle_time: float
    steps: int
    duration: float
    trajectory: Samples = None


@dataclass
class Recorder:
    """The drop's ledger: what the engine's transitions report, written here and only here.

    ``impacts`` completed (a list of ``ImpactRecord``; a permanent contact's record is made when
    it lands and completed when it settles), the ``apex_heights`` (m) of the flights begun after
    a lift-off, the integrator ``steps`` of the modes left, the ``permanent_contact_time`` (s)
    of the landing for good and the ``settle_time`` (s) at which the closed-form rest took over
    (``None``: not reached).  The engine's transition table (``transitions``) writes each event
    with one method: ``apex``, ``lift_off``, ``land``, ``settle``, ``carry``; ``left`` counts a
    mode's steps."""

    impacts: list = field(default_factory=list)
    apex_heights: list = field(default_factory=list)
    steps: int = 0
    permanent_contact_time: float = None
    settle_time: float = None
    landing: int = None     # the index in ``impacts`` of the last landing for good

    def apex(self, height):
        """A flight after a lift-off rises to ``height`` (m; ``None``: none to record)."""
        if height is not None:
            self.apex_heights.append(height)

    def left(self, steps):
        """A mode that took ``steps`` integrator steps has ended."""
        self.steps += steps

    def lift_off(self, impact_point, time, rebound_rate, peak_force, max_penetration, resumed):
        """A contact phase lifted off at ``time`` (s) at the rate ``rebound_rate`` ż (m/s): the
        impact that began at ``impact_point`` (t s, z m, ż m/s, F N) with its ``peak_force``
        (N) and ``max_penetration`` (m), or, ``resumed`` (a change from outside moved the
        sphere), no impact: the sphere left the rest it had landed in."""
        if resumed:
            self.permanent_contact_time = self.settle_time = None
            return
        self.impacts.append(ImpactRecord._of_contact(impact_point, max(-rebound_rate, 0.0),
                                                     time - impact_point[0], peak_force,
                                                     max_penetration))

    @staticmethod
    def _permanent(start_point, peak_force, max_penetration):
        """The ``ImpactRecord`` of a permanent contact from ``start_point`` (t, z, ż, F):
        rebound 0, duration inf."""
        return ImpactRecord._of_contact(start_point, 0.0, math.inf, peak_force, max_penetration)

    def land(self, start_point, peak_force, max_penetration):
        """A contact phase from ``start_point`` (t s, z m, ż m/s, F N) became permanent, its
        ``peak_force`` (N) and ``max_penetration`` (m) so far: the landing for good, recorded as
        an impact."""
        self.permanent_contact_time = start_point[0]
        self.landing = len(self.impacts)
        self.impacts.append(self._permanent(start_point, peak_force, max_penetration))

    def settle(self, time, start_point=None, peak_force=None, max_penetration=None,
               impact_time=None):
        """The closed-form rest took over at ``time`` (s); with ``start_point``, the phase that
        landed for good settled: its landing's record completed with the final ``peak_force``
        (N) and ``max_penetration`` (m), the landing dated at its contact's ``impact_time``
        (s)."""
        if start_point is not None:
            self.impacts[self.landing] = self._permanent(start_point, peak_force,
                                                         max_penetration)
            self.permanent_contact_time = impact_time
        self.settle_time = time

    def carry(self, impact_time):
        """The plate carries the sphere: the landing for good began at ``impact_time`` (s)
        unless a landing came before."""
        if self.permanent_contact_time is None:
            self.permanent_contact_time = impact_time

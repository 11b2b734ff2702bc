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
    ṗ m/s): ``plate_position``, ``plate_velocity``; F acts up on the sphere, -F on the plate."""

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
        return self.force > 0.0


@dataclass(frozen=True)
class Samples:
    """Sampled trajectory: equal-length arrays of t (s), z (m), ż (m/s) and F (N).

    F is the force on the sphere (up); ``plate_force`` = -F is its reaction on the plate.  With a
    moving plate, z and ż are relative to the plate; ``DropSimulation.plate_samples`` gives p, ṗ.
    """

    time: np.ndarray
    penetration: np.ndarray
    penetration_rate: np.ndarray
    force: np.ndarray

    @classmethod
    def from_points(cls, points):
        arr = np.asarray(points, dtype=float).reshape(-1, 4)
        return cls(*(arr[:, i].copy() for i in range(4)))

    @classmethod
    def concatenate(cls, parts):
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
        return math.isinf(self.contact_duration)


@dataclass(frozen=True)
class Advance:
    """What one ``DropSimulation.advance`` call produced."""

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
    """Outcome of ``simulate_drop``; ``trajectory`` is ``None`` unless a sample rate was given."""

    impacts: tuple
    apex_heights: tuple
    permanent_contact_time: float
    settle_time: float
    steps: int
    duration: float
    trajectory: Samples = None


@dataclass
class Recorder:
    """The drop's record so far, kept as the modes report it: the ``impacts`` completed (a list
    of ``ImpactRecord``; a permanent contact's record is made when it lands and completed when it
    settles), the ``apex_heights`` (m) of the flights begun after a lift-off, the integrator
    ``steps`` of the modes left, the ``permanent_contact_time`` (s) of the landing for good and
    the ``settle_time`` (s) at which the closed-form rest took over (``None``: not reached)."""

    impacts: list = field(default_factory=list)
    apex_heights: list = field(default_factory=list)
    steps: int = 0
    permanent_contact_time: float = None
    settle_time: float = None

    def apex(self, height):
        """A flight after a lift-off rises to ``height`` (m; ``None``: none to record)."""
        if height is not None:
            self.apex_heights.append(height)

    def landing(self, record):
        """A contact became permanent: record it (``ImpactRecord``); returns its index."""
        self.impacts.append(record)
        return len(self.impacts) - 1

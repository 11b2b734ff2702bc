"""Forcing of a contact phase besides gravity and the contact force (the compiled engine's)."""
import functools
from dataclasses import dataclass

from contact_sim.validation import require_nonnegative, require_real


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

    @functools.cached_property
    def terms(self):
        """(A m/s², Ω rad/s, ϕ rad, c₁ N·s/m, c₂ N·s²/m²), as the compiled start of a phase takes
        them (``compiled_phase.start_phase`` makes them dimensionless for its slots)."""
        return (self.acceleration_amplitude, self.angular_frequency, self.phase,
                self.linear_drag, self.quadratic_drag)


NO_FORCING_TERMS = (0.0, 0.0, 0.0, 0.0, 0.0)    # ``Forcing.terms`` of gravity alone

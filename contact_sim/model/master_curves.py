"""Master curves: the shipped dimensionless impact results of the named laws, by splines in ln ζ.

``scripts/build_master_curves.py`` tabulates e, τc, F̂ and x̂ of every named law on a uniform
grid in s = ln ζ (each point by the package's exact ``simulate_impact``) into
``contact_sim/data/master_curves.npz``; here they are loaded (once, on first use) and
interpolated by cubic splines.  A table is the fact of one law, its name and exponents
(``curve_for``): ``laws`` gives each law its curve, and ``impact`` asks the law for it.
"""
import math
from dataclasses import dataclass, field
from functools import lru_cache
from importlib import resources

import numpy as np

QUANTITIES = ('restitution', 'duration', 'peak_force', 'max_penetration')
TABLE_FILE = 'master_curves.npz'


@dataclass(frozen=True)
class MasterCurve:
    """Splines of the four dimensionless results on a uniform grid s = ln ζ ∈ [s0, s0 + h N].

    ``rows`` (derived, not an argument) holds the same coefficients as Python floats, one
    (a, b, c, d) tuple an interval, for ``evaluate_scalar``."""

    law_key: tuple
    s0: float
    h: float
    coefficients: dict  # quantity -> (4, N) cubic coefficients, highest power first
    rows: dict = field(init=False, repr=False, compare=False)   # quantity -> N (a, b, c, d)

    def __post_init__(self):
        object.__setattr__(self, 'rows', {q: [tuple(col) for col in c.T.tolist()]
                                          for q, c in self.coefficients.items()})

    @property
    def zeta_range(self):
        n = next(iter(self.coefficients.values())).shape[1]
        return math.exp(self.s0), math.exp(self.s0 + self.h * n)

    def evaluate(self, quantity, zeta):
        """Interpolated value at ``zeta`` (array) and the mask of points inside the table."""
        c = self.coefficients[quantity]
        s = np.log(np.asarray(zeta, dtype=float))
        x = (s - self.s0) / self.h
        n = c.shape[1]
        inside = (x >= 0.0) & (x <= n)
        i = np.clip(np.floor(x).astype(int), 0, n - 1)
        ds = (np.clip(x, 0.0, n) - i) * self.h
        value = ((c[0, i] * ds + c[1, i]) * ds + c[2, i]) * ds + c[3, i]
        return value, inside

    def evaluate_scalar(self, quantity, zeta):
        """The same for one float, in plain Python (no numpy overhead); ``None`` if outside."""
        x = (math.log(zeta) - self.s0) / self.h
        rows = self.rows[quantity]
        n = len(rows)
        if not 0.0 <= x <= n:
            return None
        i = min(int(x), n - 1)
        ds = (x - i) * self.h
        a, b, c, d = rows[i]
        return ((a * ds + b) * ds + c) * ds + d


@lru_cache(maxsize=1)
def _load_tables():
    from scipy.interpolate import CubicSpline   # here: importing the model does not import scipy
    path = resources.files('contact_sim') / 'data' / TABLE_FILE
    curves = {}
    with resources.as_file(path) as real_path, np.load(real_path) as data:
        for name in data['laws']:
            name = str(name)
            key = tuple(float(v) for v in data[f'{name}/key'])
            s = data[f'{name}/s']
            h = float(s[1] - s[0])
            coefficients = {q: CubicSpline(s, data[f'{name}/{q}']).c for q in QUANTITIES}
            curves[name, key] = MasterCurve(key, float(s[0]), h, coefficients)
    return curves


def curve_for(name, exponents):
    """The shipped master curve of one law (``ContactLaw.master_curve`` asks it).

    Parameters
    ----------
    name : str
        The law's name.
    exponents : tuple of float
        Its (n, p, q).

    Returns
    -------
    MasterCurve or None
        The table of the law with this name and these exponents, or ``None``: a custom law is
        integrated even where its exponents equal a named law's.
    """
    return _load_tables().get((name, tuple(exponents)))

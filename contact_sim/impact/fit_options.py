"""The options of a fit of λ to data, checked: its size limit, its loss and its confidence level.

Apart from ``damping_fit`` (scipy's solvers, the impact engine) so that the command line can
build its parsers from them without importing the engine.
"""
from contact_sim.validation import InputError, require_range

MAX_POINTS = 2000   # points of one fit: each costs one inversion of e(λ) (1000 points: 14-29 s
# on a loaded 2-core machine, python -c 'cs.fit_damping(...)' with np.geomspace(0.1, 5, 1000))

LOSSES = ('linear', 'soft_l1', 'huber', 'cauchy', 'arctan')   # scipy.optimize.least_squares


CONFIDENCE_MAX = 0.999999   # above it the interval's quantile is inf (0.9999999999999999 was)


def require_fit_options(confidence, loss):
    """The checked (confidence, loss) of a fit: 0 < confidence <= ``CONFIDENCE_MAX``, a loss of
    ``LOSSES``."""
    confidence = require_range('confidence', confidence, 0.0, CONFIDENCE_MAX, low_open=True)
    if loss not in LOSSES:
        raise InputError('loss', loss, '{n[loss]} = {value} is unknown: allowed one of %s'
                         % ', '.join(LOSSES), value=repr(loss))
    return confidence, loss

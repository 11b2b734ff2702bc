"""What `contact-sim` says when it refuses: the core's errors rendered with the option names
and the exit status of each (2 bad input, 1 missing matplotlib or a closed pipe)."""
import os
import sys

from contact_sim.cli.plotting import MissingMatplotlib
from contact_sim.validation import InputError

# The core's field keys as this command line spells them (InputError.render): the same
# refusal reads `--mass = ...` here and `sphere_mass = ...` in the node.
OPTION_NAMES = {key: '--' + key.replace('_', '-') for key in (
    'law', 'sphere', 'plate', 'radius', 'plate_radius', 'stiffness', 'mass', 'damping',
    'damping_factor', 'height', 'gravity', 'duration', 'sample_rate', 'points', 'confidence',
    'speed_range', 'loss', 'air_density', 'drag_coefficient', 'height_error', 'holdout',
    'micro_bounce_ratio', 'min_flight', 'timing_resolution', 'column')}
OPTION_NAMES.update(speed='--speeds', speeds='--speeds', material='--sphere/--plate',
                    velocity='--initial-velocity')
for _body in ('sphere', 'plate'):   # custom materials: --sphere-modulus, --plate-poisson, ...
    OPTION_NAMES.update({f'{_body}_{_o}': f'--{_body}-{_o}' for _o in ('modulus', 'poisson', 'density')})

# the errors a subcommand may end with, each reported by ``report``
REPORTED = (ValueError, ArithmeticError, MissingMatplotlib, BrokenPipeError)


DATA_FIELDS = {'speeds': 'speed', 'restitutions': 'restitution', 'uncertainties': 'uncertainty'}


def option_names(args, error=None):
    """The field -> option map for ``args``: a derived quantity is named with the options it
    comes from (lambda from --damping-factor, the Hertz k from the materials), a data file's
    columns by their names (the file is named before the message, never inside a field)."""
    names = dict(OPTION_NAMES)
    if getattr(args, 'damping', None) is None and getattr(args, 'damping_factor', None) is not None:
        names['damping'] = 'lambda = --damping-factor x sqrt(R)'
    computed = getattr(error, 'value', 0.0) is not None   # a value, not a missing option
    if computed and getattr(args, 'stiffness', 1.0) is None \
            and getattr(args, 'radius', None) is not None:
        names['stiffness'] = 'the Hertz stiffness of --sphere/--plate/--radius' + (
            '/--plate-radius' if getattr(args, 'plate_radius', float('inf')) < float('inf')
            else '')
        names['mass'] = '--mass' if getattr(args, 'mass', None) is not None else \
            'the mass from --sphere and --radius'
    if getattr(args, 'data', None) is not None and isinstance(args.data, str):
        names.update(DATA_FIELDS)
    return names


def _source(error, args):
    """'FILE: ' before a refusal of a data file's column (``fit``), '--params-file FILE: '
    before a refusal of a value taken from a parameter file, else ''."""
    data = getattr(args, 'data', None)
    field = getattr(error, 'field', None)
    if isinstance(data, str) and field in DATA_FIELDS:
        return ('stdin' if data == '-' else data) + ': '
    if field is not None and field in getattr(args, 'params_file_keys', ()):
        return f'--params-file {args.params_file}: '
    return ''


def report(error, args):
    """Print ``error`` (one of ``REPORTED``) on stderr as the command line words it and return
    the exit status: 2 for bad input, 1 for a missing matplotlib or a closed stdout."""
    if isinstance(error, InputError):
        print(f'contact-sim: error: {_source(error, args)}{error.render(option_names(args, error))}',
              file=sys.stderr)
        return 2
    if isinstance(error, ValueError):
        print(f'contact-sim: error: {error}', file=sys.stderr)
        return 2
    if isinstance(error, ArithmeticError):   # extreme values that overflow the model
        args = error.args   # OverflowError(34, 'Numerical result out of range'): the text only
        reason = args[1] if len(args) == 2 and isinstance(args[0], int) else str(error)
        print(f'contact-sim: error: the values given overflow the model ({reason}): allowed '
              'physically sensible magnitudes', file=sys.stderr)
        return 2
    if isinstance(error, MissingMatplotlib):
        print(f'contact-sim: error: {error}', file=sys.stderr)
        return 1
    # BrokenPipeError, e.g. `contact-sim drop ... | head`: stop quietly
    os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
    return 1

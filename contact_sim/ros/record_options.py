"""``contact_sim_record``'s command line: the parser and the checks of its values, done before
ROS starts (one line naming the option and its allowed range, exit code 2; no traceback, no
empty bag).
"""
import argparse
import os
from pathlib import Path

from contact_sim.validation import InputError, require_range

from .params import NODE_NAME

OPTION_NAMES = {'output': '-o/--output', 'node': '--node', 'duration': '--duration'}


def record_parser():
    """The command line of ``contact_sim_record``.

    Returns
    -------
    argparse.ArgumentParser
        Options ``-o/--output``, ``-s/--storage``, ``--node``, ``--no-clock``, ``--duration``
        (s of wall time) and ``--recover BAG``.

    Examples
    --------
    >>> from contact_sim.ros.record_options import record_parser
    >>> options = record_parser().parse_args(['-o', 'drop_bag', '--duration', '5'])
    >>> options.output, options.storage, options.duration
    ('drop_bag', 'mcap', 5.0)
    """
    parser = argparse.ArgumentParser(
        prog='contact_sim_record',
        description='Record a contact_sim node\'s topics and /clock to a rosbag2 file (MCAP by '
                    'default) with the rosbags library; stop with Ctrl-C.')
    parser.add_argument('-o', '--output', default=None,
                        help='bag directory to create, in an existing writable directory '
                             '(default: contact_sim_YYYY_MM_DD-HH_MM_SS)')
    parser.add_argument('-s', '--storage', choices=('mcap', 'sqlite3'), default='mcap',
                        help='storage format (default: mcap)')
    parser.add_argument('--node', default=f'/{NODE_NAME}',
                        help='fully qualified name of the node to record, such as /contact_sim '
                             'or /robot1/contact_sim (default: /contact_sim)')
    parser.add_argument('--no-clock', action='store_true', help='do not record /clock')
    parser.add_argument('--duration', type=float, default=None,
                        help='stop after this many wall-clock seconds, 0 < DURATION < inf '
                             '(default: until Ctrl-C)')
    parser.add_argument('--recover', metavar='BAG', default=None,
                        help='do not record: make the bag BAG that a killed recorder left '
                             'readable (rewrites its index and writes metadata.yaml), like '
                             '`ros2 bag reindex`')
    return parser


def check_duration(duration):
    """``--duration`` as given, if finite and positive (None: until Ctrl-C).

    Parameters
    ----------
    duration : float or None
        s of wall time.

    Returns
    -------
    float or None
        ``duration``.

    Raises
    ------
    InputError
        On ``duration`` (``--duration``) for NaN, infinities and values <= 0.

    Examples
    --------
    >>> check_duration(2.5)
    2.5
    >>> try:
    ...     check_duration(float('nan'))
    ... except InputError as error:
    ...     print(error.render(OPTION_NAMES))
    --duration = nan is not finite; it must be a finite real number
    """
    if duration is None:
        return None
    return require_range('duration', duration, 0.0, low_open=True,
                         unit='s of wall time; leave --duration out to record until Ctrl-C')


def check_node(name):
    """``--node``: a fully qualified node name, ``/`` then ``/``-separated names of letters,
    digits and underscores, none starting with a digit (``/contact_sim``, ``/robot1/sim``).

    Parameters
    ----------
    name : str
        As given.

    Returns
    -------
    str
        ``name``, with a leading ``/`` added if it had none.

    Raises
    ------
    InputError
        On ``node`` (``--node``) for any other text.

    Examples
    --------
    >>> check_node('robot1/contact_sim')
    '/robot1/contact_sim'
    >>> try:
    ...     check_node('a b')
    ... except InputError as error:
    ...     print(error.render(OPTION_NAMES))     # doctest: +ELLIPSIS
    --node = 'a b' is not a node name: allowed ...
    """
    full = name if name.startswith('/') else '/' + name
    parts = full[1:].split('/')
    if not all(part and (part[0].isascii() and (part[0].isalpha() or part[0] == '_'))
               and all(c.isascii() and (c.isalnum() or c == '_') for c in part)
               for part in parts) or len(full) > 255:
        raise InputError('node', name, '{n[node]} = {value} is not a node name: allowed a fully '
                         'qualified name such as /contact_sim or /robot1/contact_sim (names of '
                         'ASCII letters, digits and _, not starting with a digit, separated by '
                         '/; at most 255 characters)')
    return full


def check_output(path):
    """``-o/--output``: a new directory that can be made where asked (tried: made and removed
    again, so that a path such as ``/proc/x`` is refused before anything starts).

    Parameters
    ----------
    path : str
        As given.

    Returns
    -------
    str
        ``path``.

    Raises
    ------
    InputError
        On ``output`` (``-o/--output``) for an empty path, one that exists, or one whose
        directory cannot be made (the system's reason is said).

    Examples
    --------
    >>> try:
    ...     check_output('')
    ... except InputError as error:
    ...     print(error.render(OPTION_NAMES))
    -o/--output = '' is empty: allowed the path of a new directory
    """
    if not path:
        raise InputError('output', path, '{n[output]} = {value} is empty: allowed the path of '
                         'a new directory')
    target = Path(path)
    if os.path.lexists(target):
        raise InputError('output', path, '{n[output]} = {value} exists already: allowed the '
                         'path of a new directory (a bag is never overwritten)')
    try:
        target.mkdir()
        target.rmdir()
    except OSError as error:
        raise InputError('output', path, '{n[output]} = {value} cannot be made ({reason}): '
                         'allowed a new directory in an existing, writable one',
                         reason=error.strerror or type(error).__name__) from None
    return path


def check_options(options):
    """Check ``record_parser``'s ``--duration`` and ``--node`` in place (``node`` made fully
    qualified; ``-o`` is ``check_output``'s, once its default is known).

    Parameters
    ----------
    options : argparse.Namespace
        As parsed.

    Raises
    ------
    InputError
        The first option refused (``error.render(OPTION_NAMES)`` names it as typed).

    Examples
    --------
    >>> options = record_parser().parse_args(['--duration', '-1'])
    >>> try:
    ...     check_options(options)
    ... except InputError as error:
    ...     print(error.render(OPTION_NAMES))     # doctest: +ELLIPSIS
    --duration = -1.0 is out of range: allowed 0 < --duration (s of wall time; ...)
    """
    check_duration(options.duration)
    options.node = check_node(options.node)

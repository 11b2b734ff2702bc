"""The start and the stop of the ROS processes: the node's command line (``--help``, arguments
that are not ROS arguments refused), its ``--params-file`` files checked before rclpy reads them
(one line naming the file and what is wrong, not an ``RCLError`` traceback), and the spin that
ends on SIGINT or SIGTERM between two executor turns (no callback cut off, no traceback).
"""
import math
import os
import signal
import stat
import time

import yaml
from rclpy.experimental.events_executor import EventsExecutor

USAGE = '''\
usage: contact_sim_node [-h] [--ros-args [-p NAME:=VALUE ...] [--params-file FILE ...]
                        [-r __node:=NAME] [-r __ns:=NAMESPACE] ...]

Simulate a sphere dropped on a plate (compliant contact, Azad & Featherstone 2014) and publish its
contact wrench, state, impacts, markers and diagnostics stamped with simulated time, until
Ctrl-C or SIGTERM. Every parameter, with its range and rule, is in the parameter table of
docs/node.md ("Parameters"; built from the code) and in `ros2 param describe /contact_sim NAME`;
config/default.yaml spells out the defaults.

options:
  -h, --help  show this message and exit (without starting ROS)

exit codes: 0 after SIGINT/SIGTERM, 2 for an invalid argument, parameter or parameter file.
'''


class ArgumentError(Exception):
    """The command line cannot start the node: the message is one line naming the argument."""


def node_arguments(argv):
    """What the command line asks for: ``'help'`` or ``'run'``; ArgumentError otherwise.

    Parameters
    ----------
    argv : list of str
        The full argument vector (``sys.argv``), ROS arguments included.

    Returns
    -------
    str
        ``'help'`` for ``-h``/``--help`` before ``--ros-args``, else ``'run'``.

    Raises
    ------
    ArgumentError
        For an argument outside ``--ros-args ... [--]`` (the node takes none), or a
        ``--params-file`` that does not hold ROS parameters (see ``check_params_file``).
    """
    from rclpy.utilities import remove_ros_args

    from .rclpy_private import RCLError
    if any(arg in ('-h', '--help') for arg in _before_ros_args(argv)):
        return 'help'
    for path in params_files(argv):
        check_params_file(path)
    try:
        own = remove_ros_args(list(argv))[1:]
    except RCLError as error:   # rcl's own parse, e.g. -p contact_law:=
        reason = str(error).splitlines()[0].partition('. Error:')[0]
        raise ArgumentError(f'invalid ROS arguments: {reason.removeprefix("Failed to parse ROS arguments: ")}'
                            ' (allowed -p NAME:=VALUE with a YAML VALUE, --params-file FILE)'
                            ) from None
    if own:
        raise ArgumentError(f'unknown argument {own[0]!r}: contact_sim_node takes only ROS '
                            'arguments (--ros-args -p NAME:=VALUE, --params-file FILE); see '
                            'contact_sim_node --help')
    return 'run'


def _before_ros_args(argv):
    """The arguments before the first ``--ros-args`` (the program's own)."""
    argv = list(argv)[1:]
    return argv[:argv.index('--ros-args')] if '--ros-args' in argv else argv


def params_files(argv):
    """The FILE of every ``--params-file FILE`` inside ``--ros-args`` (in order)."""
    files, ros = [], False
    for i, arg in enumerate(argv):
        if arg == '--ros-args':
            ros = True
        elif arg == '--':
            ros = False
        elif ros and arg == '--params-file':
            if i + 1 >= len(argv):
                raise ArgumentError('--params-file needs a FILE')
            files.append(argv[i + 1])
    return files


MAX_PARAMS_FILE_BYTES = 262_144  # 256 KiB: a dump of this node is about 0.8 KB
MAX_PARAMS_FILE_DEPTH = 32       # nested mappings and lists: a node's section needs 3 to 5
MAX_PARAMS_FILE_VALUES = 10_000  # scalars: rcl's parser slows down with their square
# PyYAML's C loader when built with libyaml (it reads as yaml.safe_load does, faster)
_LOADER = getattr(yaml, 'CSafeLoader', yaml.SafeLoader)


def check_params_file(path):
    """Refuse a parameter file rclpy could not read, with one line naming the file and why.

    The file is bounded before it is parsed: at most ``MAX_PARAMS_FILE_BYTES`` bytes are read
    (rcl's parser took 5.6 s for 1.2 MB of 60,000 parameters, and would take minutes for
    10 MB, deaf to SIGINT), and its nesting and number of values are counted on YAML's event
    stream (no recursion) before it is composed (PyYAML's composer recurses, a RecursionError
    at about 1,000 levels).

    Parameters
    ----------
    path : str
        The FILE of ``--params-file FILE``.

    Raises
    ------
    ArgumentError
        If the file cannot be read, is not a regular file (a FIFO, a device, a directory: rcl
        reads the file again after this check), is larger than ``MAX_PARAMS_FILE_BYTES``, is not UTF-8
        YAML, nests deeper than ``MAX_PARAMS_FILE_DEPTH`` or holds more than
        ``MAX_PARAMS_FILE_VALUES`` values, or is not a mapping of node names (``/**`` for any
        node) to mappings with a ``ros__parameters`` mapping.
    """
    where = f'--params-file {path}'
    try:   # rcl reads the file again after this check: a pipe would be empty (and rcl wait
        mode = os.stat(path).st_mode   # for another writer, silently, for ever)
        if not stat.S_ISREG(mode):
            kind = ('a directory' if stat.S_ISDIR(mode) else 'a FIFO (pipe)'
                    if stat.S_ISFIFO(mode) else 'a device or socket')
            raise ArgumentError(f'{where}: is {kind}: allowed a regular file (the node checks '
                                'it, then rcl reads it again)')
        with open(path, 'rb') as file:
            data = file.read(MAX_PARAMS_FILE_BYTES + 1)
    except OSError as error:
        raise ArgumentError(f'{where}: cannot be read ({error.strerror})') from None
    if len(data) > MAX_PARAMS_FILE_BYTES:
        raise ArgumentError(f'{where}: is larger than {MAX_PARAMS_FILE_BYTES} bytes: allowed at '
                            f'most {MAX_PARAMS_FILE_BYTES} bytes (256 KiB) a parameter file')
    try:
        text = data.decode('utf-8')
        _check_shape(text, where)
        data = yaml.load(text, Loader=_LOADER)
    except UnicodeDecodeError:
        raise ArgumentError(f'{where}: is not a text (UTF-8 YAML) file') from None
    except yaml.YAMLError as error:
        mark = getattr(error, 'problem_mark', None)
        line = f' at line {mark.line + 1}' if mark is not None else ''
        raise ArgumentError(f'{where}: is not valid YAML{line} '
                            f'({getattr(error, "problem", None) or error})') from None
    expected = ('allowed a mapping of node names (/** for any node) to '
                '{ros__parameters: {NAME: VALUE, ...}}, as config/default.yaml')
    if not isinstance(data, dict) or not data:
        raise ArgumentError(f'{where}: holds no node names: {expected}')
    for name, section in data.items():
        if not _holds_parameters(section):
            raise ArgumentError(f'{where}: {name!s} has no ros__parameters mapping: {expected}')


def _check_shape(text, where):
    """Count the nesting and the values of a YAML text on its event stream (iterative, no
    composition); ArgumentError past ``MAX_PARAMS_FILE_DEPTH`` or ``MAX_PARAMS_FILE_VALUES``,
    or for an alias (a few anchors used ten times each over nine levels are a billion values
    to walk)."""
    depth = values = 0
    for event in yaml.parse(text, Loader=_LOADER):
        if isinstance(event, yaml.CollectionStartEvent):
            depth += 1
            if depth > MAX_PARAMS_FILE_DEPTH:
                raise ArgumentError(f'{where}: nests deeper than {MAX_PARAMS_FILE_DEPTH} levels: '
                                    f'allowed at most {MAX_PARAMS_FILE_DEPTH} nested mappings '
                                    'and lists')
        elif isinstance(event, yaml.CollectionEndEvent):
            depth -= 1
        elif isinstance(event, yaml.AliasEvent):   # each use would count its anchor's again
            raise ArgumentError(f'{where}: uses a YAML alias (*{event.anchor}): allowed none in '
                                'a parameter file')
        elif isinstance(event, yaml.ScalarEvent):
            values += 1
            if values > MAX_PARAMS_FILE_VALUES:
                raise ArgumentError(f'{where}: holds more than {MAX_PARAMS_FILE_VALUES} values: '
                                    f'allowed at most {MAX_PARAMS_FILE_VALUES} a parameter file')


def _holds_parameters(section):
    """A node's section (with a ``ros__parameters`` mapping) or a namespace of such sections."""
    if not isinstance(section, dict) or not section:
        return False
    if 'ros__parameters' in section:
        return isinstance(section['ros__parameters'], dict)
    return all(_holds_parameters(inner) for inner in section.values())


def print_usage(file):
    """Write the node's usage (``USAGE``) to ``file``."""
    file.write(USAGE)


PUBLICATION_MODE = 'ASYNCHRONOUS'   # the node's RMW_FASTRTPS_PUBLICATION_MODE unless set


def publication_mode(environ=os.environ):
    """Before ``rclpy.init`` in the node's process: Fast DDS publication ``ASYNCHRONOUS``
    (``PUBLICATION_MODE``) unless ``RMW_FASTRTPS_PUBLICATION_MODE`` is set already (then it is
    left as it is). A publish then hands the sample to Fast DDS's sending thread, which sends
    what has queued meanwhile together: measured with ``bench/bench_dds_floor.py
    --publication-mode ASYNCHRONOUS --take waitset``, 10-15 us of the publishing thread's CPU a
    message instead of 27-31, and 13-17 us a message taking instead of 30-35, as
    ``contact_sim_record`` takes (``recorder.Recorder.taker``). Only the node's process: an
    asynchronous writer of depth 1 (the recorder's ``~/recorded``) had its publishes refused
    ("cannot publish data") in that bench; the node's writers keep 10 to 10,000 samples.

    Parameters
    ----------
    environ : mapping, optional
        The environment to set it in (default ``os.environ``).

    Returns
    -------
    str
        The publication mode the process will use.
    """
    return environ.setdefault('RMW_FASTRTPS_PUBLICATION_MODE', PUBLICATION_MODE)


TAKE_WAIT = 0.02   # s: with ``take``, the longest wait for a message before the executor's turn
EXECUTOR_TURNS = 3  # with ``take``, ready executor work done after each take (timers, services)


def spin_until_signal(node, stop_after=None, drain=None, drain_timeout=10.0, take=None):
    """Spin ``node`` until SIGINT or SIGTERM (or ``stop_after`` wall seconds), then return.

    The signals only set a flag, checked between executor turns, so a callback is never cut off
    and the context is shut down after spinning has stopped, not under the executor's feet.
    With ``drain`` (called once at the stop; it returns a predicate that is true when nothing
    more is needed), spinning goes on after the stop until that predicate holds, for at most
    ``drain_timeout`` wall seconds; a signal during it (a second one, after a signal) ends it at
    once. Returns whether the predicate held in the end (True without ``drain``). rclpy must be
    initialised with ``SignalHandlerOptions.NO``. With ``take`` (``take(timeout)``: wait at most
    ``timeout`` s for messages the executor does not serve and handle them, as
    ``recorder.Recorder.taker``), each turn is ``take(TAKE_WAIT)`` then up to
    ``EXECUTOR_TURNS`` pieces of the executor's ready work (timers, services), without waiting.
    """
    stop = []
    previous = {sig: signal.signal(sig, lambda *_: stop.append(True))
                for sig in (signal.SIGINT, signal.SIGTERM)}
    deadline = math.inf if stop_after is None else time.monotonic() + stop_after
    executor = EventsExecutor(context=node.context)
    executor.add_node(node)
    drained = True

    def turn(timeout):
        if take is None:
            executor.spin_once(timeout_sec=timeout)
        else:
            take(min(timeout, TAKE_WAIT))
            for _ in range(EXECUTOR_TURNS):
                executor.spin_once(timeout_sec=0.0)
    try:
        while not stop and node.context.ok() and time.monotonic() < deadline:
            turn(0.1)
        if drain is not None:
            done, limit, signals = drain(), time.monotonic() + drain_timeout, len(stop)
            while not (drained := done()) and len(stop) == signals and node.context.ok() \
                    and time.monotonic() < limit:
                turn(0.05)
    finally:
        executor.remove_node(node)
        executor.shutdown()
        for sig, handler in previous.items():
            signal.signal(sig, handler)
    return drained



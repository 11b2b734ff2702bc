#!/usr/bin/env python3
"""Replay hostile inputs across the library, the command line and the node; count what breaks.

Every case is one bad input (a non-finite, negative, huge, tiny, wrongly typed or empty value of
one argument of a public function, one option of a subcommand, one parameter of the node), or
one call of the issue-17 campaign (``EXPRESSIONS``: refused naming the field given, or, with no
field, accepted with finite numbers), or an output file that cannot be written (``--plot ''``,
a directory, ``/dev/full``, a missing directory).  The
expected outcome is a refusal: an ``InputError`` naming the argument (library), one line on
stderr and exit 2 (command line), one ``[FATAL]`` line and exit 2 (node).  Anything else is
counted:

* ``traceback``: another exception, or a traceback printed;
* ``hang``: no answer within ``--timeout`` seconds;
* ``memory``: a ``MemoryError`` (each case runs under a 2 GiB address-space limit);
* ``nonsense``: accepted, with a non-finite number in the result (library) or in the output;
* ``unnamed``: refused, but the message does not name the argument the user gave, or shows a
  numpy repr (``np.float64(...)``);
* ``refused``: a valid command line (the newcomer's ``contact-sim restitution``) that fails;
* ``accepted``: a bad input that must be refused (an issue-34 case naming a field) accepted.
A RuntimeWarning in a library call that succeeds is raised as an error, so it counts as a
``traceback``.

    python scripts/hostile_inputs.py [--only library|cli|node] [--timeout 20] [--in-process]
                                     [--list]

It prints one line per case that is not a clean refusal, then the counts; exit status 1 if any.
The node cases need ROS (the set-up's venv); they are skipped with a note where rclpy is absent.
"""
import argparse
import atexit
import json
import math
import os
import re
import resource
import select
import shutil
import subprocess
import sys
import tempfile

BAD_NUMBERS = [math.nan, math.inf, -math.inf, -1.0, 0.0, 1e308, -1e308, 1e-308, 'abc', True,
               None, 1 + 2j, '1', b'1']
NOT_NUMBERS = (str, bytes, bool, complex)   # never a number: accepting one is a failure
MEMORY = 2 * 1024 ** 3

# -- the library: (call, argument name, keyword arguments of a valid call) --------------------
LIBRARY = [
    ('cs.simulate_drop', dict(contact='C', mass=0.066, height=1.0, duration=1.0,
                              gravity=9.81, radius=0.0127, velocity=0.0)),
    ('cs.DropSimulation', dict(contact='C', mass=0.066, height=1.0, gravity=9.81,
                               radius=0.0127, velocity=0.0, settle_tolerance=1e-3)),
    ('cs.check_drop', dict(contact='C', mass=0.066, gravity=9.81, height=1.0, velocity=0.0,
                           radius=0.0127, plate_speed=0.0)),
    ('cs.simulate_impact', dict(contact='C', mass=0.066, speed=1.0, gravity=9.81)),
    ('cs.damping_group', dict(contact='C', mass=0.066, speed=1.0)),
    ('cs.equivalent_radius', dict(radius=0.01, plate_radius=0.02)),
    ('cs.Material', dict(name='x', youngs_modulus=1e9, poisson_ratio=0.3, density=1000.0)),
    ('cs.build_mass', dict(sphere='steel', radius=0.01)),
    ('cs.drop.sphere_motion', dict(radius=0.01, penetration=0.0, penetration_rate=0.0,
                                   plate_position=0.0, plate_velocity=0.0)),
    ('cs.restitution', dict(contact='C', mass=0.066, speeds=1.0)),
    ('cs.contact_duration', dict(contact='C', mass=0.066, speeds=1.0)),
    ('cs.predict_bounces', dict(contact='C', mass=0.066, height=1.0, count=10)),
    ('cs.Contact', dict(law='azad_featherstone', stiffness=1e10, damping=1e5)),
    ('cs.FlightPath', dict(height=1.0, velocity=0.0, gravity=9.81)),
    ('cs.AirDrag', dict(air_density=1.2, drag_coefficient=0.5, radius=0.02)),
    ('cs.drop.SinusoidalPlate', dict(amplitude=0.001, frequency=20.0, phase=0.0)),
    ('cs.drop.VibratingTable', dict(contact='C', mass=0.01, frequency=20.0, bounces=3,
                                    transient=0)),
    ('cs.drop.sweep', dict(function='abs', values=[1], max_workers=1)),
    ('cs.fit_damping', dict(law='azad_featherstone', stiffness=1e10, mass=0.066,
                            speeds=[0.5, 1.0, 2.0], restitutions=[0.8, 0.75, 0.7])),
]

# -- the library, named calls of the 2026-12-01 campaign: (expression, the name a refusal must
# give); C is Contact(cs.AZAD_FEATHERSTONE, 1e10, 1e5), T six impact times
EXPRESSIONS = [
    ("cs.simulate_impact(C, 1e308, 1.0)", 'mass'),
    ("cs.simulate_impact(C, 0.066, 1e308)", 'speed'),
    ("cs.simulate_impact(C, 0.066, 1e-308)", 'speed'),
    ("cs.restitution(C, 0.066, np.array([1 + 1j]))", 'speeds'),
    ("cs.restitution(C, 0.066, np.array(['2020-01-01'], dtype='datetime64[D]'))", 'speeds'),
    ("cs.contact_duration(C, 0.066, np.ma.masked_array([1.0, -1.0], [0, 1]))", 'speeds'),
    ("cs.restitution(cs.Contact(cs.AZAD_FEATHERSTONE, 1e300, 1e5), 0.066, 1.0)", 'stiffness'),
    ("cs.restitution(C, 1e300, 1.0)", 'mass'),
    ("cs.FlightPath(-1.0, 0.0, 9.81, surface=-1.5).touch()", 'level'),
    ("cs.predict_bounces(C, 0.066, height=1.0, count=60)", ''),
    ("cs.predict_bounces(C, 0.066, height=1e308, count=5)", 'height'),
    ("cs.fit_damping(cs.AZAD_FEATHERSTONE, 1e10, 0.066, [1, 2], [0.8])", 'restitutions'),
    ("cs.fit_damping(cs.AZAD_FEATHERSTONE, 1e10, 0.066, [0.5, 1, 2, 3], [0.8, 0.75, 0.7, 0.66], "
     "uncertainties=np.full(4, 1e-300))", ''),
    ("cs.fit_damping(cs.AZAD_FEATHERSTONE, 1e10, 0.066, [0.5, 1, 2, 3], [0.8, 0.75, 0.7, 0.66], "
     "uncertainties=np.full(4, 1e300))", ''),
    ("cs.damping_group(cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 1e5), 0.066, 1.0)", ''),
    ("cs.simulate_drop(C, 0.066, 1.0, duration=1.0, drag=0.5)", 'drag'),
    ("cs.fit_bounces(1e10, 0.066, [T], drag=0.5)", 'drag'),
    ("cs.compare_laws(1e10, 0.066, [1, 2], [0.8, 0.7], laws=0.0)", 'laws'),
    ("cs.DropSimulation(C, 0.066, 1.0).advance(1e308)", 't_end'),
    ("parse_impact_times(1.0)", 'text'),
    ("cs.fit_bounces(1e10, 0.066, np.vstack([T, T + 1]), laws=[cs.AZAD_FEATHERSTONE])", ''),
    ("cs.simulate_drop(C, 0.066, 1.0, duration=1.0, radius=1e-308)", 'radius'),
    ("cs.drop.sweep(abs, [1], max_workers=10 ** 6)", 'max_workers'),
    ("cs.DropSimulation(C, 0.066, 1.0).advance(1.0, max_steps=0.5)", 'max_steps'),
    # issue 34: one rule per quantity (gravity as for a drop; text, bytes, booleans not numbers)
    ("cs.simulate_impact(C, 0.066, 1.0, gravity=1e300)", 'gravity'),
    ("cs.simulate_impact(C, 0.066, 1.0, gravity=1e7)", 'gravity'),
    ("cs.simulate_impact(C, 0.066, 1.0, gravity='9.81')", 'gravity'),
    ("cs.simulate_drop(C, 0.066, 1.0, duration=1.0, gravity='9.81')", 'gravity'),
    ("cs.simulate_drop(C, 0.066, 1.0, duration=1.0, gravity=b'1')", 'gravity'),
    ("cs.simulate_drop(C, 0.066, '\u0661', duration=1.0)", 'height'),
    ("cs.simulate_drop(C, True, 1.0, duration=1.0)", 'mass'),
    ("cs.simulate_drop(C, 0.066, 1.0, duration='1')", 'duration'),
    ("cs.Contact(cs.AZAD_FEATHERSTONE, '1e10', 1e5)", 'stiffness'),
    ("cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, b'1')", 'damping'),
    ("cs.Material('x', '1e9', 0.3, 1000.0)", 'youngs_modulus'),
    ("cs.build_contact('azad_featherstone', stiffness='1e10', damping=1.0)", 'stiffness'),
    ("cs.build_mass(sphere='steel', radius='0.01')", 'radius'),
    ("cs.restitution(C, 0.066, [1.0, True])", 'speeds'),
    ("cs.restitution(C, '0.066', 1.0)", 'mass'),
    ("cs.simulate_drop(cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 5e-324), 0.066, 1.0, duration=1.0)",
     'damping'),
    ("cs.FlightPath(-1.0, 0.0, 9.81)", 'height'),
    ("cs.FlightPath(1.0, 0.0, '9.81')", 'gravity'),
    ("cs.equivalent_radius(math.nan, 0.01)", 'radius'),
    ("cs.equivalent_radius(0.01, math.nan)", 'plate_radius'),
    ("cs.damping_group(cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 1e5), 0.066, math.nan)", 'speed'),
    ("cs.damping_group(cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 1e5), 0.066, math.inf)", 'speed'),
    ("cs.damping_group(cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 1e5), 0.066, -1.0)", 'speed'),
    ("cs.damping_group(cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 1e5), 0.066, 1j)", 'speed'),
    ("cs.damping_group(cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, '1e5'), 0.066, 1.0)", 'damping'),
    ("cs.check_drop(C, 0.066, 9.81, 1.0, 0.0, plate_speed=math.nan)", 'plate_speed'),
    ("sphere_motion('a', 0.0, 0.0)", 'radius'),
    ("sphere_motion(math.nan, 0.0, 0.0)", 'radius'),
    ("sphere_motion(0.01, 0.0, 0.0, plate_position=None)", 'plate_position'),
    ("sphere_motion(0.01, 0.0, math.inf)", 'penetration_rate'),
    ("CommandedPlate((0.0, 1e-300), (0.0, 0.01), (0.0, 0.0))", 'times'),
    ("CommandedPlate((0.0, 1.0), (0.0, 1e300), (0.0, 0.0))", 'positions'),
    ("CommandedPlate((0.0, 1e300), (0.0, 0.01), (0.0, 0.0))", 'times'),
    ("CommandedPlate((0.0, 1.0), (0.0, True), (0.0, 0.0))", 'positions'),
    ("CommandedPlate((0.0, 1.0), (0.0, 1e-300), (0.0, 0.0)).state(0.5)", ''),
    ("command_motion(0.0, 0.0, 0.0, [1e-300, 1.0], [0.01, 0.0])", 'times'),
    ("command_motion(0.0, 0.0, 0.0, [0.5, 1.0], ['0.01', 0.0])", 'positions'),
    ("cs.drop.SinusoidalPlate('0.001', 20.0, 0.0)", 'amplitude'),
    ("cs.drop.SinusoidalPlate(0.001, 5e-324, 0.0)", 'frequency'),
]

# -- the command line: (subcommand with a valid set of options, option names to spoil) --------
CLI = [
    (['restitution', '--law', 'azad_featherstone', '--sphere', 'steel', '--plate', 'cast_iron',
      '--radius', '0.0127', '--damping-factor', '8.87e5', '--speeds', '1'],
     ['--radius', '--damping-factor', '--speeds', '--mass', '--stiffness']),
    (['drop', '--stiffness', '1e10', '--damping', '1e5', '--mass', '0.066', '--height', '1',
      '--duration', '1'],
     ['--stiffness', '--damping', '--mass', '--height', '--duration', '--gravity']),
]
CLI_VALUES = ['nan', 'inf', '-inf', '-1', '0', '1e308', '1e-308', 'abc', '', ',']

# -- the node: parameters to spoil at start-up ------------------------------------------------
NODE = ['sphere_radius', 'sphere_mass', 'initial_height', 'stiffness', 'damping',
        'real_time_factor', 'publish_rate', 'gravity', 'plate_amplitude', 'plate_frequency']
NODE_VALUES = ['nan', '-1.0', '1.0e+308', 'abc']


def _limit_memory():
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY, MEMORY))


def library_cases():
    for call, kwargs in LIBRARY:
        for name, good in kwargs.items():
            if name in ('contact', 'function', 'law', 'name', 'sphere'):
                continue
            for bad in BAD_NUMBERS:
                if bad == good:
                    continue
                yield ('library', f'{call}({name}={bad!r})', (call, kwargs, name, bad))


def expression_cases():
    for expr, field in EXPRESSIONS:
        yield ('library', expr, ('__expr__', {'expr': expr}, field, None))


def cli_cases():
    for argv, options in CLI:
        for option in options:
            for bad in CLI_VALUES:
                spoilt = list(argv)
                if option in spoilt:
                    spoilt[spoilt.index(option) + 1] = bad
                else:
                    spoilt += [option, bad]
                yield ('cli', 'contact-sim ' + ' '.join(spoilt), (spoilt, option))
    for argv, option in issue34_cli_cases():   # strict: exit 0 is a failure ('accepted')
        yield ('cli', 'contact-sim ' + ' '.join(a if len(a) < 80 else a[:20] + '...'
                                                for a in argv), (argv, option, True))
    # output files: each refused before the work, naming the option (issue 17, item 3)
    for argv, _ in CLI:
        for option, bad in (('--plot', ''), ('--plot', '.'), ('--plot', '/dev/full'),
                            ('--plot', '/nonexistent/dir/x.png')):
            yield ('cli', 'contact-sim ' + ' '.join(argv + [option, repr(bad)]),
                   (argv + [option, bad], option))


def _fixtures(folder=None, write_files=True):
    """Input files of the issue-34 command lines, written in ``folder`` (default: a new
    temporary directory); their paths only, unless ``write_files``."""
    if folder is None:
        folder = tempfile.mkdtemp(prefix='hostile_inputs_')
        atexit.register(shutil.rmtree, folder, True)   # 1 MB of fixtures: not left behind
    folder = str(folder)
    files = {}

    def write(name, data):
        files[name] = os.path.join(folder, name)
        if write_files:
            with open(files[name], 'wb') as f:
                f.write(data)
    write('points.csv', b'speed,restitution\n0.5,0.8\n1,0.75\n2,0.7\n')
    write('wide.csv', b'speed,restitution\n0.5,' + b'7' * 1_100_000 + b'\n')
    write('radius.yaml', b'contact_sim:\n  ros__parameters:\n    sphere_radius: -1.0\n')
    write('latin1.yaml', b'contact_sim:\n  ros__parameters:\n    contact_law: "\xe9"\n')
    return files


def issue34_cli_cases(folder=None, write_files=True):
    """(argv, the option a refusal must name; None: the command must succeed), with the input
    files in ``folder`` (``_fixtures``)."""
    f = _fixtures(folder, write_files)
    valid = ['--stiffness', '1e10', '--damping', '1e5', '--mass', '0.066']
    return [
        (['restitution'], None), (['drop', '--duration', '1'], None),   # the default contact
        (['restitution', '--law', 'linear', '--law', 'linear', *valid], '--law'),
        (['restitution', '--speeds', '1', '--speeds', '2', *valid], '--speeds'),
        (['restitution', '--speeds', '1,2', '--points', '5', *valid], '--points'),
        (['restitution', '--mass', '1', '--mass', '2', '--stiffness', '1e10', '--damping', '1'],
         '--mass'),
        (['drop', '--law', 'linear', '--law', 'hunt_crossley', *valid], '--law'),
        (['drop', '--gravity', '1e300', *valid], '--gravity'),
        (['drop', '--sample-rate', 'inf', '--plot', 'x.png', *valid], '--sample-rate'),
        (['drop', '--sample-rate', '1e400', '--plot', 'x.png', *valid], '--sample-rate'),
        (['drop', '--duration', '1e400', *valid], '--duration'),
        (['restitution', '--plot', '/proc/x.png', *valid], '--plot'),
        (['drop', '--plot', '/proc/x.png', *valid], '--plot'),
        (['restitution', '--speed-range', '1', '1e400', *valid], '--speed-range'),
        (['fit', f['wide.csv'], '--stiffness', '1e10', '--mass', '0.066'], f['wide.csv']),
        (['fit', f['points.csv'], '--confidence', '1e400', '--stiffness', '1e10', '--mass',
          '0.066'], '--confidence'),
        (['fit', f['points.csv'], f['points.csv']], 'unrecognized'),
        (['export', 'mujoco', '--params-file', f['radius.yaml']], '--params-file'),
        (['export', 'mujoco', '--params-file', f['latin1.yaml']], '--params-file'),
    ]


def node_cases():
    for name in NODE:
        for bad in NODE_VALUES:
            yield ('node', f'contact_sim_node --ros-args -p {name}:={bad}', (name, bad))


LIBRARY_WORKER = r"""
import json, math, sys, warnings
import numpy as np
import contact_sim as cs
from contact_sim.calibration import parse_impact_times
from contact_sim.drop import CommandedPlate, command_motion, sphere_motion
C = cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 1e5)
T = np.cumsum([0.0, 0.45, 0.40, 0.36, 0.32, 0.29])
# documented non-finite values: a time not reached (nan), a permanent contact's duration (inf),
# the interval of a drag not fitted and the AIC difference without both kinds of law (nan)
DOCUMENTED = {'permanent_contact_time', 'settle_time', 'contact_duration', 'drag_interval',
              'delta_aic'}

def decode(bad):
    if isinstance(bad, str) and bad in ('nan', 'inf', '-inf'):
        return float(bad)
    if isinstance(bad, list) and bad and bad[0] == '__complex__':
        return complex(bad[1], bad[2])
    if isinstance(bad, list) and bad and bad[0] == '__bytes__':
        return bad[1].encode('latin-1')
    return bad

def numbers(x, depth=0):
    if depth > 4:
        return
    if isinstance(x, (float, int, np.floating, np.integer)) and not isinstance(x, bool):
        yield float(x)
    elif isinstance(x, np.ndarray) and x.dtype.kind in 'fc':
        yield from (float(v) for v in np.abs(x).ravel()[:100000])
    elif isinstance(x, (list, tuple)):
        for v in list(x)[:1000]:
            yield from numbers(v, depth + 1)
    elif hasattr(x, '__dataclass_fields__'):
        for f in x.__dataclass_fields__:
            if f not in DOCUMENTED:
                yield from numbers(getattr(x, f), depth + 1)

print('ready', flush=True)
for line in sys.stdin:
    call, kwargs, name, bad = json.loads(line)
    # a law is named in the cases (JSON) and resolved here, as a front end does
    args = {k: (C if v == 'C' else abs if v == 'abs' else cs.LAWS[v] if k == 'law' else v)
            for k, v in kwargs.items()}
    args[name] = decode(bad)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter('error', RuntimeWarning)   # a warning on a success counts
            result = eval(args['expr']) if call == '__expr__' else eval(call)(**args)
        answer = {'outcome': 'accepted' if all(math.isfinite(v) for v in numbers(result))
                  else 'nonsense'}
    except cs.InputError as error:
        answer = {'outcome': 'refused', 'message': str(error)}
    except MemoryError:
        answer = {'outcome': 'memory'}
    except Exception as error:
        answer = {'outcome': 'traceback', 'message': f'{type(error).__name__}: {error}'}
    if 'np.' in answer.get('message', ''):          # a numpy repr in a message
        answer = {'outcome': 'unnamed', 'message': answer['message']}
    print(json.dumps(answer), flush=True)
"""


def _encode(value):
    if isinstance(value, float) and not math.isfinite(value):
        return repr(value)              # 'nan', 'inf', '-inf'
    if isinstance(value, complex):
        return ['__complex__', value.real, value.imag]
    if isinstance(value, bytes):
        return ['__bytes__', value.decode('latin-1')]
    return value


class LibraryWorker:
    """One Python process that runs the library cases in turn (restarted after a hang or a
    crash), so that each case does not pay the import of contact_sim."""

    SCRIPT, READY_TIMEOUT = LIBRARY_WORKER, 120.0   # the worker's code; s for its 'ready'

    def __init__(self, timeout):
        self.timeout, self.proc = timeout, None

    def _start(self):
        self.proc = subprocess.Popen([sys.executable, '-c', self.SCRIPT], text=True,
                                     stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                     stderr=subprocess.DEVNULL, preexec_fn=_limit_memory)
        self._read(self.READY_TIMEOUT)   # 'ready': the import done

    def _read(self, timeout):
        ready, _, _ = select.select([self.proc.stdout], [], [], timeout)
        if not ready:
            raise TimeoutError
        line = self.proc.stdout.readline()
        if not line:
            raise EOFError
        return line

    def _ask(self, request):
        """Send one case (JSON) and read its answer: (answer, None), or (None, (outcome,
        message)) when the worker hung or died (it is stopped; the next case restarts it)."""
        if self.proc is None or self.proc.poll() is not None:
            self._start()
        self.proc.stdin.write(json.dumps(request) + '\n')
        self.proc.stdin.flush()
        try:
            return json.loads(self._read(self.timeout)), None
        except TimeoutError:
            self.stop()
            return None, ('hang', '')
        except EOFError:                # killed: out of memory in C code, or a crash
            self.stop()
            return None, ('memory', 'the worker died')

    def run(self, case):
        call, kwargs, name, bad = case
        answer, failed = self._ask([call, kwargs, name, _encode(bad)])
        if failed:
            return failed
        outcome, message = answer['outcome'], answer.get('message', '')
        if outcome == 'refused' and (not name or name not in message):
            return 'unnamed', message
        if outcome == 'accepted' and call == '__expr__' and name:   # must be refused
            return 'accepted', ''
        if outcome == 'accepted' and isinstance(bad, NOT_NUMBERS):   # text, bytes, True, 1j
            return 'accepted', ''
        return ('ok' if outcome in ('refused', 'accepted') else outcome), message

    def stop(self):
        if self.proc is not None:
            self.proc.kill()
            self.proc.wait()
            self.proc = None


CLI_WORKER = r"""
import contextlib, io, json, os, sys, tempfile, traceback
os.chdir(tempfile.gettempdir())
from contact_sim.cli.app import main
print('ready', flush=True)
for line in sys.stdin:
    argv = json.loads(line)
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(argv)
        except SystemExit as stop:
            code = stop.code if isinstance(stop.code, int) else (0 if stop.code is None else 2)
        except BaseException:
            traceback.print_exc(file=err)
            code = 1
    print(json.dumps({'code': code, 'out': out.getvalue()[-4000:], 'err': err.getvalue()[-4000:]}),
          flush=True)
"""


class CliWorker(LibraryWorker):
    """``contact-sim``'s ``main`` in one long-lived process (``--in-process``): the same verdicts
    as the executable, without paying the import for every case (on a loaded machine the
    import alone can exceed the timeout)."""

    SCRIPT, READY_TIMEOUT = CLI_WORKER, 300.0

    def run(self, case):
        argv, option, *strict = case
        answer, failed = self._ask(argv)
        if failed:
            return failed
        return verdict(answer['code'], answer['out'], answer['err'], option, *strict)


def verdict(code, stdout, stderr, option, strict=False):
    """The outcome of one command line from its exit status and output (``strict``: a bad
    input that must be refused, so exit 0 is ``accepted``)."""
    text = stdout + stderr
    if 'Traceback' in text:
        return 'traceback', stderr[-300:]
    if 'MemoryError' in text:
        return 'memory', ''
    if option is None:   # a valid command line: must run
        return ('ok', '') if code == 0 and not re.search(r'\b(nan|inf)\b', stdout) \
            else ('refused', stderr.strip()[-200:])
    if code == 0 and strict and option is not None:
        return 'accepted', stdout[-200:]
    if code == 0:
        if re.search(r'\b(nan|inf)\b', stdout):
            return 'nonsense', stdout[-200:]
        if 'Warning' in stderr:
            return 'nonsense', stderr[-200:]   # a warning on a run that exits 0
        return 'ok', ''
    if code == 2 and option not in stderr:
        return 'unnamed', stderr.strip()[-200:]
    return 'ok', ''


def run_cli(case, timeout, exe):
    argv, option, *strict = case
    try:
        out = subprocess.run([exe, *argv], capture_output=True, text=True, timeout=timeout,
                             preexec_fn=_limit_memory, cwd=tempfile.gettempdir())
    except subprocess.TimeoutExpired:
        return 'hang', ''
    return verdict(out.returncode, out.stdout, out.stderr, option, *strict)


def run_node(case, timeout, exe, domain):
    name, bad = case
    env = dict(os.environ, ROS_DOMAIN_ID=str(domain), ROS_LOG_DIR=tempfile.mkdtemp(),
               ROS_AUTOMATIC_DISCOVERY_RANGE='LOCALHOST')
    try:
        proc = subprocess.Popen([exe, '--ros-args', '-p', f'{name}:={bad}'], env=env,
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                start_new_session=True)
        out, _ = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, 2)
        proc.communicate()
        return 'hang', 'still running: the bad value was accepted?'
    if 'Traceback' in out:
        return 'traceback', out[-300:]
    if proc.returncode != 2 or name not in out:
        return 'unnamed', out.strip()[-200:]
    return 'ok', ''


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--only', choices=['library', 'cli', 'node'])
    parser.add_argument('--timeout', type=float, default=20.0)
    parser.add_argument('--list', action='store_true', help='list the cases and stop')
    parser.add_argument('--in-process', action='store_true',
                        help="run the command lines through contact-sim's main in one worker "
                             'process instead of one executable each (for a loaded machine)')
    args = parser.parse_args(argv)
    groups = {'library': library_cases, 'cli': cli_cases, 'node': node_cases}
    cases = [c for kind, make in groups.items() if args.only in (None, kind) for c in make()]
    if args.only in (None, 'library'):
        cases[len(list(library_cases())):len(list(library_cases()))] = list(expression_cases())
    if args.list:
        for kind, label, _ in cases:
            print(kind, label)
        print(f'{len(cases)} cases')
        return 0
    bindir = os.path.dirname(sys.executable)
    exe_cli = os.path.join(bindir, 'contact-sim')
    exe_node = os.path.join(bindir, 'contact_sim_node')
    counts = {}
    domain = 150 + os.getpid() % 50
    library = LibraryWorker(args.timeout)
    cli = CliWorker(args.timeout) if args.in_process else None
    for kind, label, case in cases:
        if kind == 'library':
            outcome, detail = library.run(case)
        elif kind == 'cli':
            outcome, detail = (cli.run(case) if cli is not None
                               else run_cli(case, args.timeout, exe_cli))
        elif not os.path.exists(exe_node):
            outcome, detail = 'skipped', 'no contact_sim_node next to this python'
        else:
            outcome, detail = run_node(case, args.timeout, exe_node, domain)
        counts[outcome] = counts.get(outcome, 0) + 1
        if outcome not in ('ok', 'skipped'):
            print(f'{outcome:9s} {label}: {" ".join(detail.split())[:160]}', flush=True)
    library.stop()
    if cli is not None:
        cli.stop()
    print(f'{len(cases)} cases: ' + ', '.join(f'{counts.get(k, 0)} {k}' for k in
          ('ok', 'traceback', 'hang', 'memory', 'nonsense', 'unnamed', 'refused',
           'accepted', 'skipped')))
    return 1 if any(counts.get(k) for k in ('traceback', 'hang', 'memory', 'nonsense',
                                            'unnamed', 'refused', 'accepted')) else 0


if __name__ == '__main__':
    sys.exit(main())

"""Fast refusals (issue 17, item 7): the command line parses its arguments before it imports the
engine.  A refused argument of any subcommand imports neither numba nor scipy's solvers and
signal processing, nor the compiled phase engine or the audio detector: the parsers are built
from light modules (the packages' names are imported on first use, ``contact_sim._lazy``).

Each command line runs in a fresh interpreter (this one has imported everything already).  No
timing is asserted: ``bench/`` measures the speed.
"""
import subprocess
import sys

import pytest

HEAVY = ('numba', 'scipy.optimize', 'scipy.signal', 'contact_sim.phase.compiled',
         'contact_sim.calibration.audio')

PROBE = '''\
import sys
from contact_sim.cli.app import main
try:
    code = main({argv!r})
except SystemExit as stop:
    code = stop.code
print(code)
print(sorted(name for name in {heavy!r} if name in sys.modules))
'''


@pytest.mark.parametrize('argv', [
    ['bounces', '--bogus'],
    ['bounces', 'data.csv', '--bogus'],
    ['bounces', 'data.csv', '--loss', 'l2'],       # a choice from the core's LOSSES
    ['export', '--bogus'],
    ['export', 'mujoco', '--bogus'],
    ['audit', '--bogus'],
    ['audit', 'mujoco', 'ball.xml', '--bogus'],
    ['fit', '--bogus'],
    ['fit', 'data.csv', '--confidence', 'high'],
    ['drop', '--bogus'],
], ids=' '.join)
def test_a_refused_argument_imports_no_engine(argv):
    done = subprocess.run([sys.executable, '-c', PROBE.format(argv=argv, heavy=HEAVY)],
                          capture_output=True, text=True, timeout=300)
    code, imported = done.stdout.strip().splitlines()
    assert code == '2', done.stderr
    assert imported == '[]', f'{" ".join(argv)} imported {imported} before refusing'
    lines = done.stderr.rstrip('\n').splitlines()
    assert lines[0].startswith('usage: contact-sim')
    errors = [line for line in lines if ': error: ' in line]
    assert errors == lines[-1:], done.stderr          # one error line, the last
    assert errors[0].startswith('contact-sim')

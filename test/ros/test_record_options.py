"""``contact_sim_record``'s arguments refused before anything starts (issue 34, item 4: `-o
/proc/x`, `--node ''`, `--node 'a b'` gave tracebacks; `--duration nan`, `-1`, `0` wrote an empty
bag and exited 0): one line naming the option and its range, exit code 2, no bag made.
"""
import subprocess

import pytest

from contact_sim.ros.record_options import check_node
from contact_sim.ros.recorder import record_main

from .harness import TIMEOUT, executable

REFUSED = [
    (['-o', '/proc/x'], "-o/--output = '/proc/x' cannot be made"),
    (['-o', ''], "-o/--output = '' is empty"),
    (['--node', ''], "--node = '' is not a node name: allowed a fully qualified name"),
    (['--node', 'a b'], "--node = 'a b' is not a node name"),
    (['--node', '/contact_sim/'], "is not a node name"),
    (['--node', '/1robot/sim'], "is not a node name"),
    (['--node', '/robot/sim-1'], "is not a node name"),
    (['--duration', 'nan'], '--duration = nan is not finite'),
    (['--duration', 'inf'], '--duration = inf is not finite'),
    (['--duration', '-1'], '--duration = -1.0 is out of range: allowed 0 < --duration'),
    (['--duration', '0'], '--duration = 0.0 is out of range: allowed 0 < --duration'),
]


@pytest.mark.parametrize(('args', 'message'), REFUSED)
def test_each_bad_argument_is_one_line_naming_it_and_exit_2(args, message, tmp_path,
                                                             monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    if '-o' not in args:
        args = [*args, '-o', 'bag']
    assert record_main(['contact_sim_record', *args]) == 2
    out, err = capsys.readouterr()
    assert out == ''
    assert err.startswith('contact_sim_record: error: ') and message in err, err
    assert err.count('\n') == 1, err
    assert list(tmp_path.iterdir()) == []    # no bag, no directory left behind


def test_an_existing_output_is_refused_before_ros_starts(tmp_path, capsys):
    (tmp_path / 'bag').mkdir()
    assert record_main(['contact_sim_record', '-o', str(tmp_path / 'bag')]) == 2
    assert 'exists already: allowed the path of a new directory' in capsys.readouterr().err


def test_node_names_as_ros_spells_them_are_taken():
    assert check_node('/contact_sim') == '/contact_sim'
    assert check_node('contact_sim') == '/contact_sim'
    assert check_node('/robot_1/_sim2') == '/robot_1/_sim2'


def test_the_executable_refuses_without_a_traceback(ros_env, workdir):
    done = subprocess.run([executable('contact_sim_record'), '--node', 'a b', '--duration', '1'],
                          env=ros_env, cwd=workdir, capture_output=True, text=True,
                          timeout=TIMEOUT)
    assert done.returncode == 2, done
    assert done.stderr.splitlines() == [
        "contact_sim_record: error: --node = 'a b' is not a node name: allowed a fully qualified "
        'name such as /contact_sim or /robot1/contact_sim (names of ASCII letters, digits and _, '
        'not starting with a digit, separated by /; at most 255 characters)'], done.stderr

"""The node's start and stop with real processes: ``--help`` and unknown arguments, parameter
files rclpy cannot read, numbers past the node's bounds (one ``[FATAL]`` line naming the file or
the parameter and the range, exit code 2, no traceback), and SIGINT or SIGTERM on a node running
as fast as possible (exit code 0, no ``[FATAL]``, no traceback).

The tests without the package's node come first, the one with it last; a test that waits for
processes while the package's node runs spins the client meanwhile (see test_node_parameters.py).
"""
import os
import signal
import subprocess
import time
from pathlib import Path

import pytest

import rclpy  # noqa: E402,F401  (pinned: a missing install fails here)

from .harness import NODE, PROGRESS_TIMEOUT, TIMEOUT, Process, assert_clean_exit  # noqa: E402

INF = float('inf')


def finished(process):
    """Exit code and output of a process that must end by itself."""
    try:
        code = process.popen.wait(TIMEOUT)
    except subprocess.TimeoutExpired:
        process.stop()
        pytest.fail(f'{process.name} kept running:\n{process.output()}')
    return code, process.output()


def assert_one_fatal_line(code, output, *texts):
    assert code == 2, output
    assert 'Traceback' not in output, output
    lines = [line for line in output.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith('[FATAL]'), output
    for text in texts:
        assert text in lines[0], output


def test_the_node_publishes_asynchronously_unless_the_environment_says_otherwise():
    from contact_sim.ros.startup import PUBLICATION_MODE, publication_mode
    environ = {}
    assert publication_mode(environ) == PUBLICATION_MODE == 'ASYNCHRONOUS'
    assert environ == {'RMW_FASTRTPS_PUBLICATION_MODE': 'ASYNCHRONOUS'}
    environ = {'RMW_FASTRTPS_PUBLICATION_MODE': 'SYNCHRONOUS'}
    assert publication_mode(environ) == 'SYNCHRONOUS'
    assert environ == {'RMW_FASTRTPS_PUBLICATION_MODE': 'SYNCHRONOUS'}


def test_help_prints_the_usage_without_starting_ros_and_unknown_arguments_are_refused(
        ros_env, workdir):
    helped = Process('contact_sim_node', ['--help'], ros_env, workdir)
    unknown = Process('contact_sim_node', ['--frobnicate'], ros_env, workdir)
    code, output = finished(helped)
    assert code == 0 and output.startswith('usage: contact_sim_node'), output
    assert '[INFO]' not in output and 'drop from' not in output, output   # no simulation
    assert_one_fatal_line(*finished(unknown), "unknown argument '--frobnicate'", '--help')


def test_an_unreadable_parameter_file_is_one_fatal_line_naming_it(ros_env, workdir):
    files = {'missing': workdir / 'nonexistent.yaml', 'malformed': workdir / 'malformed.yaml',
             'binary': workdir / 'binary.yaml', 'bare': workdir / 'bare.yaml'}
    files['malformed'].write_text('/**:\n  ros__parameters: [\n')
    files['binary'].write_bytes(bytes(range(256)) * 4)
    files['bare'].write_text('/**:\n  stiffness: 5.0e+4\n')
    cases = {name: (['--ros-args', '--params-file', str(path)], [str(path), reason])
             for (name, path), reason in zip(files.items(), (
                 'cannot be read', 'is not valid YAML at line', 'is not a text',
                 'has no ros__parameters'))}
    cases['empty override'] = (['--ros-args', '-p', 'contact_law:='],
                               ["'-p contact_law:='", 'NAME:=VALUE'])
    processes = {name: Process('contact_sim_node', args, ros_env, workdir)
                 for name, (args, _) in cases.items()}
    for name, process in processes.items():
        assert_one_fatal_line(*finished(process), *cases[name][1])


def test_parameter_files_past_the_bounds_are_one_fatal_line_before_parsing(ros_env, workdir):
    # reproduced: a 10 MB file hung the node for 240 s and more (rcl's parser, deaf to SIGINT),
    # and 5,000 nested levels gave a RecursionError traceback (PyYAML's composer)
    from contact_sim.ros.startup import (MAX_PARAMS_FILE_BYTES, MAX_PARAMS_FILE_DEPTH,
                                         MAX_PARAMS_FILE_VALUES)
    files = {name: workdir / f'{name}.yaml' for name in ('huge', 'deep', 'many', 'alias')}
    line = '    p{}: 1.5\n'
    files['huge'].write_text('/**:\n  ros__parameters:\n' + ''.join(
        line.format(i) for i in range(10_000_000 // len(line.format(0)))))
    files['deep'].write_text('/**:\n  ros__parameters:\n    a: ' + '[' * 5000 + ']' * 5000)
    files['many'].write_text('/**:\n  ros__parameters:\n    a: [' + '1,' * 20_000 + '1]\n')
    files['alias'].write_text('/**:\n  ros__parameters:\n    a: &x [1, 2]\n    b: *x\n')
    assert files['huge'].stat().st_size >= 10_000_000 - 20
    reasons = {'huge': f'is larger than {MAX_PARAMS_FILE_BYTES} bytes',
               'deep': f'nests deeper than {MAX_PARAMS_FILE_DEPTH} levels',
               'many': f'holds more than {MAX_PARAMS_FILE_VALUES} values',
               'alias': 'uses a YAML alias (*x)'}
    processes = {name: Process('contact_sim_node', ['--ros-args', '--params-file', str(path)],
                               ros_env, workdir) for name, path in files.items()}
    for name, process in processes.items():
        assert_one_fatal_line(*finished(process), str(files[name]), reasons[name])


def test_a_parameter_file_that_is_not_a_regular_file_is_refused_unread(ros_env, workdir):
    # a FIFO (`--params-file <(cat dump.yaml)`): the check read it, then rcl opened it again and
    # waited for another writer, silently, for ever; a directory, a device: one line each too
    fifo = workdir / 'params.fifo'
    os.mkfifo(fifo)
    cases = {str(fifo): 'is a FIFO (pipe): allowed a regular file',
             str(workdir): 'is a directory: allowed a regular file',
             '/dev/zero': 'is a device or socket: allowed a regular file'}
    processes = {path: Process('contact_sim_node', ['--ros-args', '--params-file', path],
                               ros_env, workdir) for path in cases}
    for path, process in processes.items():
        assert_one_fatal_line(*finished(process), path, cases[path])
    with pytest.raises(OSError):   # nobody reads the FIFO: a writer finds no reader
        os.close(os.open(fifo, os.O_WRONLY | os.O_NONBLOCK))


def test_sigint_while_python_imports_the_package_stops_it_quietly(ros_env, workdir):
    # caught in the package's import (numba's llvmlite is loaded, main not yet reached): before,
    # Python's own KeyboardInterrupt traceback (the import took 3.3 s under load), and with
    # Ctrl-C held down exit code -2
    process = Process('contact_sim_node', ['--ros-args', '-r', '__node:=importing'], ros_env,
                      workdir)

    def importing():
        try:
            return 'llvmlite' in Path(f'/proc/{process.popen.pid}/maps').read_text()
        except OSError:
            return False
    try:
        deadline = time.monotonic() + TIMEOUT
        while process.popen.poll() is None and not importing() and time.monotonic() < deadline:
            time.sleep(0.001)   # polling for the import: not a wait for a fixed time
        assert importing(), process.output()
        while process.popen.poll() is None and time.monotonic() < deadline:
            process.popen.send_signal(signal.SIGINT)   # held down: one every 2 ms until exit
            time.sleep(0.002)
        code, output = finished(process)
    finally:
        process.stop()
    assert code == 0, output
    assert 'Traceback' not in output and '[FATAL]' not in output, output


def test_ctrl_c_held_down_stops_the_node_quietly(ros_env, workdir):
    # SIGINT after SIGINT, as a user pressing Ctrl-C again while the node stops: before, one
    # that came while main destroyed the node gave a KeyboardInterrupt traceback and exit -2
    process = Process('contact_sim_node', ['--ros-args', '-r', '__node:=held_down', '-p',
                                           'publish_clock:=false'], ros_env, workdir)
    try:
        deadline = time.monotonic() + TIMEOUT
        while 'drop from' not in process.output() and process.popen.poll() is None \
                and time.monotonic() < deadline:
            time.sleep(0.01)   # polling for the start: not a wait for a fixed time
        assert 'drop from' in process.output(), process.output()
        while process.popen.poll() is None and time.monotonic() < deadline:
            process.popen.send_signal(signal.SIGINT)
            time.sleep(0.002)  # a signal every 2 ms until the node has exited
        code, output = finished(process)
    finally:
        process.stop()
    assert code == 0, output
    assert 'Traceback' not in output and '[FATAL]' not in output, output


def test_numbers_past_the_bounds_stop_the_start_with_the_field_and_the_range(ros_env, workdir):
    cases = {'real_time_factor:=1000000000.0': 'real_time_factor = 1000000000.0 is out of range: '
                                               'allowed 0.0001 <= real_time_factor <= 1000',
             'real_time_factor:=1.0e+300': 'real_time_factor = 1e+300 is out of range',
             'stiffness:=1.0e+308': 'stiffness out of range Min: 0.0, Max: 1e+20',
             'sphere_youngs_modulus:=1.0e+308': 'sphere_youngs_modulus out of range'}
    processes = {arg: Process('contact_sim_node', ['--ros-args', '-p', arg], ros_env, workdir)
                 for arg in cases}
    for arg, process in processes.items():
        assert_one_fatal_line(*finished(process), cases[arg])


def cpu_seconds(pid):
    """User and system CPU time (s) of the process ``pid`` so far (/proc/PID/stat)."""
    from pathlib import Path
    fields = Path(f'/proc/{pid}/stat').read_text().rpartition(')')[2].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf('SC_CLK_TCK')


@pytest.mark.parametrize('signum', [signal.SIGINT, signal.SIGTERM], ids=['SIGINT', 'SIGTERM'])
def test_a_signal_stops_a_flat_out_node_cleanly(client, ros_env, workdir, signum):
    """Three nodes flat out with no reader (nothing paces them), each signalled once it has
    worked a CPU second since it started its loop."""
    names = [f'flat_{signum.name.lower()}_{i}' for i in range(3)]
    processes = [Process('contact_sim_node', [
        '--ros-args', '-r', f'__node:={name}', '-p', 'real_time_factor:=0.0',
        '-p', 'publish_clock:=false'], ros_env, workdir) for name in names]
    started = {}

    def working(process):
        if process.popen.poll() is not None:
            return True
        if 'drop from' not in process.output():
            return False
        now = cpu_seconds(process.popen.pid)
        return now - started.setdefault(process, now) >= 1.0

    try:
        client.spin_until(lambda: all(working(p) for p in processes),
                          'every node to work flat out for a CPU second', PROGRESS_TIMEOUT)
        for process in processes:
            assert process.popen.poll() is None, process.output()
            process.popen.send_signal(signum)
        client.spin_until(lambda: all(p.popen.poll() is not None for p in processes),
                          'every node to stop')
        for process in processes:
            code, output = process.popen.returncode, process.output()
            assert code == 0, output
            assert '[FATAL]' not in output and 'Traceback' not in output, output
    finally:
        for process in processes:
            process.stop()


def test_numbers_past_the_bounds_are_refused_at_run_time_for_their_true_reason(sim, client):
    cases = [(dict(real_time_factor=1e9), 'allowed 0.0001 <= real_time_factor <= 1000'),
             (dict(real_time_factor=1e308), 'allowed 0.0001 <= real_time_factor <= 1000'),
             (dict(stiffness=1e308), 'stiffness out of range Min: 0.0, Max: 1e+20'),
             (dict(damping=1e308), 'damping = 1e+308 is too large for this drop')]
    for values, reason in cases:
        (result,) = client.set_parameters(NODE, **values)
        assert not result.successful and reason in result.reason, (values, result.reason)
    n = client.count(f'{NODE}/pose')
    client.spin_until(lambda: client.count(f'{NODE}/pose') >= n + 20, 'the node to go on')
    assert sim.popen.poll() is None, sim.output()
    assert 'Traceback' not in sim.output() and 'struct.error' not in sim.output()


def test_a_huge_real_time_factor_after_inf_is_refused_and_the_node_goes_on(
        sim, client, ros_env, workdir):
    # (a node of its own: flat out, the package's node would flood the client's readers)
    name = '/flat_bounds'
    process = Process('contact_sim_node', ['--ros-args', '-r', f'__node:={name[1:]}', '-p',
                                           'real_time_factor:=.inf', '-p',
                                           'publish_clock:=false'], ros_env, workdir)
    try:
        (result,) = client.set_parameters(name, real_time_factor=1e308)
        assert not result.successful and 'real_time_factor = 1e+308' in result.reason
        assert client.get_parameters(name, ['real_time_factor']) == {'real_time_factor': INF}
        (result,) = client.set_parameters(name, real_time_factor=1000.0)   # the bound: accepted
        assert result.successful, result.reason
    finally:
        assert_clean_exit(process)
    assert 'OverflowError' not in process.output(), process.output()

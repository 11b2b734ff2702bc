"""Hostile command lines (issue 17): refusals in the user's words (the option typed, plain
numbers), and every output file checked before the work starts."""
import os

import pytest

from test_cli import run

MATERIALS = ['--sphere', 'steel', '--plate', 'cast_iron', '--radius', '0.0127']
RESTITUTION = ['restitution', *MATERIALS, '--damping-factor', '8.87e5', '--speeds', '1']
DROP = ['drop', '--stiffness', '1e10', '--damping', '1e5', '--mass', '0.066', '--duration', '1']




@pytest.mark.parametrize('argv, option', [
    (['drop', '--stiffness', '1e308', '--damping', '1e5', '--mass', '0.066'], '--stiffness'),
    (['drop', '--stiffness', '1e10', '--damping', '1e308', '--mass', '0.066'], '--damping'),
    (['restitution', *MATERIALS, '--damping-factor', '1e308', '--speeds', '1'],
     '--damping-factor'),
    (['restitution', '--sphere', 'steel', '--plate', 'cast_iron', '--radius', 'inf',
      '--damping-factor', '8.87e5', '--speeds', '1'], '--radius'),
    (['restitution', *MATERIALS, '--damping-factor', '8.87e5', '--speeds', '1,,2'], '--speeds'),
    (['restitution', *MATERIALS, '--damping-factor', '8.87e5', '--speed-range', '0', '1'],
     '--speed-range'),
    (['restitution', *MATERIALS, '--damping-factor', '8.87e5', '--sphere-modulus', '1e-308',
      '--speeds', '1'], '--sphere-modulus'),   # issue 34: the option, not 'Hertz stiffness'
    (['restitution', '--stiffness', '1e300', '--mass', '0.066', '--damping', '1e5',
      '--speeds', '1'], '--stiffness'),
    (['restitution', '--stiffness', '1e10', '--mass', '1e300', '--damping', '1e5',
      '--speeds', '1'], '--mass'),
])
def test_a_refusal_names_the_option_typed(capsys, argv, option):
    # reproduced: 'a contact phase needs motion or gravity', 'allowed --damping <= inf',
    # '--speeds = 1.0' for a bad modulus, 'speed_range = (0, 1)', '1,,2' accepted as 1,2,
    # e = 1 for --stiffness 1e300 and --mass 1e300
    code, out, err = run(capsys, argv)
    assert code == 2, out
    last = err.strip().splitlines()[-1]     # the one error line (after usage or notes)
    assert 'error:' in last and option in last
    assert '<= inf' not in err and 'speed_range' not in err and 'np.' not in err


def test_a_data_file_is_named_before_the_message_not_inside_a_field(capsys, tmp_path):
    # reproduced: 'allowed 6.08e-14 <= /tmp/.../fit_e_tiny.csv restitution[0] <= 1'
    data = tmp_path / 'fit_e_tiny.csv'
    data.write_text('1.0,1e-30\n2.0,0.5\n')
    code, _, err = run(capsys, ['fit', str(data), *MATERIALS, '--law', 'azad_featherstone'])
    assert code == 2
    assert err.startswith(f'contact-sim: error: {data}: ')
    assert f'{data} restitution' not in err and 'restitution[0]' in err


def test_fit_of_points_all_above_one_prints_no_zero_width_interval(capsys, tmp_path):
    # reproduced: lambda = 0 with the interval [0, 0] for every law
    data = tmp_path / 'e_above_one.csv'
    data.write_text('0.5,1.01\n1.0,1.02\n2.0,1.005\n')
    code, out, _ = run(capsys, ['fit', str(data), *MATERIALS])
    assert code == 0
    assert '[0.000000e+00, 0.000000e+00]' not in out
    assert 'n/a (every point has e >= 1' in out


@pytest.fixture
def recording(tmp_path):
    path = tmp_path / 'data.csv'
    path.write_text('0.0\n0.45\n0.85\n1.21\n')
    return path


def _bounces(path, *extra):
    return ['bounces', str(path), '--mass', '0.046', '--stiffness', '2e8', *extra]


@pytest.mark.parametrize('make_argv, reason', [
    (lambda d, t: _bounces(d, '--save-params', str(d)), 'input file'),
    (lambda d, t: _bounces(d, '--save-params', os.path.join(str(t), '.', 'data.csv')),
     'input file'),
    (lambda d, t: _bounces(d, '--plot', str(t / 'same.out'), '--save-params',
                           str(t / 'same.out')), 'same file'),
    (lambda d, t: _bounces(d, '--plot', ''), 'empty'),
    (lambda d, t: _bounces(d, '--save-params', ''), 'empty'),
    (lambda d, t: _bounces(d, '--plot', str(t)), 'directory'),
    (lambda d, t: _bounces(d, '--save-params', str(t / 'nonexistent' / 'x.yaml')),
     'does not exist'),
    (lambda d, t: _bounces(d, '--plot', '/dev/full'), 'not a regular file'),
    (lambda d, t: [*DROP, '--plot', ''], 'empty'),
    (lambda d, t: [*RESTITUTION, '--plot', str(t)], 'directory'),
    (lambda d, t: ['fit', str(d), *MATERIALS, '--plot', str(d)], 'input file'),
])
def test_outputs_are_checked_before_the_work(capsys, recording, tmp_path, make_argv, reason):
    # reproduced: --save-params data.csv replaced the recording (exit 0); --plot same.out
    # --save-params same.out overwrote the plot; --plot '' wrote nothing, exit 0; a directory,
    # /dev/full or a missing directory failed only after the whole table was printed
    before = recording.read_bytes()
    code, out, err = run(capsys, make_argv(recording, tmp_path))
    assert code == 2
    assert out == ''                          # refused before any work
    assert reason in err and err.count('\n') == 1
    assert recording.read_bytes() == before
    assert not (tmp_path / 'same.out').exists()


def test_an_overflow_is_reported_without_its_errno_tuple(capsys):
    # reproduced: "overflow the model ((34, 'Numerical result out of range'))"
    from contact_sim.cli import errors
    assert errors.report(OverflowError(34, 'Numerical result out of range'), None) == 2
    err = capsys.readouterr().err
    assert '(Numerical result out of range)' in err and '34' not in err


def test_a_damping_too_small_to_matter_is_refused_not_warned_about(capsys):
    # reproduced: `drop --damping 1e-308` exited 0 after RuntimeWarnings (overflow in divide)
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter('error', RuntimeWarning)
        code, out, err = run(capsys, ['drop', '--stiffness', '1e10', '--damping', '1e-308',
                                      '--mass', '0.066'])
    assert code == 2 and out == ''
    assert '--damping = 1e-308 is too small' in err and "--damping = 0 (elastic)" in err


def test_fit_refuses_a_data_file_beyond_the_point_limit_while_reading(capsys, tmp_path):
    # reproduced: 100,000 rows gave no answer in 120 s; 10 million a MemoryError traceback
    from contact_sim.impact import MAX_POINTS
    data = tmp_path / 'big.csv'
    data.write_text('speed,restitution\n' + '1.0,0.8\n' * (MAX_POINTS + 5))
    code, out, err = run(capsys, ['fit', str(data), *MATERIALS, '--law', 'azad_featherstone'])
    assert code == 2 and out == ''
    assert f'has more than {MAX_POINTS} rows' in err and err.count('\n') == 1


@pytest.mark.parametrize('command', ['restitution', 'drop', 'fit', 'materials'])
def test_an_argument_error_is_refused_before_the_engine_is_imported(command):
    # reproduced: argparse errors took 1.3-5 s (12 s on a loaded machine) because every
    # subcommand's engine was imported before the arguments were parsed
    import subprocess
    import sys
    probe = ('import sys\nfrom contact_sim.cli.app import main\n'
             f'try:\n    main([{command!r}, "--no-such-option"])\nexcept SystemExit as stop:\n'
             '    print(stop.code)\n'
             'print(sorted(m for m in sys.modules if m.split(".")[0] == "numba" or m in '
             '("contact_sim.phase.compiled", "contact_sim.impact.simulate", '
             '"contact_sim.drop.engine", "contact_sim.drop.simulate", '
             '"contact_sim.calibration.bounce_fit", '
             '"contact_sim.export.engines")))\n')
    done = subprocess.run([sys.executable, '-c', probe], capture_output=True, text=True,
                          timeout=300)
    code, engine = done.stdout.strip().splitlines()[-2:]
    assert code == '2' and 'error: ' in done.stderr
    assert engine == '[]'


# -- issue 34 -------------------------------------------------------------------------------
@pytest.mark.parametrize('argv, option', [
    (['drop', '--law', 'linear', '--law', 'hunt_crossley'], '--law'),
    (['drop', '--gravity', '1', '--gravity', '2'], '--gravity'),
    (['drop', '--height', '1', '--height', '2'], '--height'),
    (['restitution', '--speeds', '1', '--speeds', '2'], '--speeds'),
    (['restitution', '--mass', '1', '--mass', '2'], '--mass'),
    (['restitution', '--law', 'linear', '--law', 'linear'], '--law'),      # repeatable, same law
    (['fit', 'x.csv', '--confidence', '0.9', '--confidence', '0.5'], '--confidence'),
    (['export', 'mujoco', '--law', 'linear', '--law', 'lee_wang'], '--law'),
    (['bounces', 'x.csv', '--gravity', '9.8', '--gravity', '9.81'], '--gravity'),
    (['audit', 'mujoco', 'x.xml', '--timestep', '1e-3', '--timestep', '2e-3'], '--timestep')])
def test_an_option_given_twice_is_refused_not_overridden(capsys, argv, option):
    # reproduced: the last one silently won (`drop --law linear --law hunt_crossley` ran
    # hunt_crossley); refused by the shared parser, so every subcommand has the rule
    code, out, err = run(capsys, argv)
    assert code == 2 and out == ''
    assert f'argument {option}' in err and 'given twice' in err


def test_a_repeatable_option_takes_different_values():
    from test_cli import main
    assert main(['restitution', '--law', 'azad_featherstone', '--law', 'hunt_crossley',
                 '--stiffness', '1e10', '--mass', '0.066', '--damping', '1', '--speeds', '1']) == 0


def test_points_beside_speeds_is_refused(capsys):
    # reproduced: --points silently ignored beside --speeds
    code, out, err = run(capsys, [*RESTITUTION, '--points', '5'])
    assert code == 2 and err.strip().splitlines()[-1].startswith('contact-sim: error: --points')


@pytest.mark.parametrize('command, first', [
    (['restitution', '--speeds', '1'], '# coefficient of restitution'),
    (['drop', '--duration', '1'], '# drop from 1 m')])
def test_a_newcomers_first_command_runs_on_the_default_contact(capsys, command, first):
    # reproduced: `contact-sim restitution` and `contact-sim drop` said "--mass is missing"
    code, out, err = run(capsys, command)
    assert code == 0, err
    lines = out.splitlines()
    assert lines[0].startswith('# no contact given: the default contact, steel sphere R1 = '
                               '0.0127 m on cast_iron (flat), azad_featherstone law')
    assert lines[1].startswith(first)
    assert 'k = 1.095172e+10' in out   # the Hertz k of steel on cast iron, R = 12.7 mm
    # the same numbers as the README's contact given in full
    code, full, _ = run(capsys, [*command, *MATERIALS, '--damping-factor', '8.87e5',
                                 '--law', 'azad_featherstone'])
    assert code == 0 and full.splitlines() == lines[1:]   # no note: the contact was given


def test_a_partial_contact_is_still_refused_naming_what_is_missing(capsys):
    code, _, err = run(capsys, ['drop', '--stiffness', '1e10', '--damping', '1'])
    assert code == 2 and '--mass is missing' in err


@pytest.mark.parametrize('path', ['/proc/x.png', '/proc/self/x.png', '/sys/x.png'])
def test_a_plot_where_no_file_can_be_made_is_refused_before_the_work(capsys, path):
    # reproduced: --plot /proc/x.png refused only after the whole computation, naming 'plot'
    code, out, err = run(capsys, [*DROP, '--plot', path])
    assert code == 2 and out == ''
    assert err.startswith(f"contact-sim: error: --plot = '{path}' cannot be written")


def test_a_data_row_beyond_the_limit_is_refused_naming_the_file(capsys, tmp_path):
    # reproduced: _csv.Error: field larger than field limit (131072), a traceback
    data = tmp_path / 'wide.csv'
    data.write_text('speed,restitution\n0.5,' + '7' * 1_000_000 + '\n')
    code, out, err = run(capsys, ['fit', str(data), *MATERIALS])
    assert code == 2 and out == ''
    assert f"data = '{data}' line 2 is longer than 10000 characters" in err


@pytest.mark.parametrize('content, words', [
    (b'contact_sim:\n  ros__parameters:\n    sphere_radius: -1.0\n',
     ': sphere_radius = -1.0 is out of range: allowed 0 < sphere_radius'),
    (b'contact_sim:\n  ros__parameters:\n    contact_law: "\xe9"\n', 'is not UTF-8 text'),
    (b'#' * 1_000_001, 'bytes: allowed at most 1000000')])
def test_a_params_file_refusal_names_the_file_once(capsys, tmp_path, content, words):
    # reproduced: 'allowed 0 < x.yaml: sphere_radius' (the file pasted into the bound) and a
    # bare "'utf-8' codec can't decode byte 0xe9"
    path = tmp_path / 'x.yaml'
    path.write_bytes(content)
    code, out, err = run(capsys, ['export', 'mujoco', '--params-file', str(path)])
    assert code == 2 and out == ''
    assert err.startswith('contact-sim: error: --params-file') and str(path) in err
    assert words in err and err.count(str(path)) == 1

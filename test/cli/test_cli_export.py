"""`contact-sim export`: the JSON record has exactly the issue's keys, the table and snippet are
printed, and bad input is refused naming the option."""
import json

import numpy as np
import pytest

from contact_sim import cli

STEEL_ON_CAST_IRON = ['--law', 'azad_featherstone', '--sphere', 'steel', '--plate', 'cast_iron',
                      '--radius', '0.0127', '--damping-factor', '8.87e5']
KEYS = {'engine', 'engine_version', 'target', 'parameters', 'snippet', 'speeds',
        'target_restitution', 'engine_restitution', 'engine_restitution_source', 'max_abs_error'}
PARAMETERS = {'mujoco': {'solref', 'solimp', 'timestep', 'integrator'},
              'pybullet': {'restitution', 'contactStiffness', 'contactDamping', 'timestep'},
              'drake': {'point_contact_stiffness', 'hunt_crossley_dissipation', 'time_step'},
              'gazebo': {'kp', 'kd', 'restitution_coefficient', 'threshold'}}
SNIPPET = {'mujoco': 'solref="', 'pybullet': 'changeDynamics(', 'gazebo': '<kp>',
           'drake': '<drake:hunt_crossley_dissipation>'}


def run(capsys, argv):
    code = cli.main(argv)
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.parametrize('engine', sorted(PARAMETERS))
def test_json_has_exactly_the_keys(capsys, engine):
    code, out, _ = run(capsys, ['export', engine, *STEEL_ON_CAST_IRON, '--speeds', '0.5,2',
                                '--format', 'json'])
    assert code == 0
    record = json.loads(out)
    assert set(record) == KEYS
    assert set(record['target']) == {'law', 'stiffness', 'damping', 'mass', 'radius'}
    assert set(record['parameters']) == PARAMETERS[engine]
    assert SNIPPET[engine] in record['snippet']
    assert record['speeds'] == [0.5, 2.0]
    error = np.abs(np.subtract(record['engine_restitution'], record['target_restitution']))
    assert record['max_abs_error'] == pytest.approx(error.max())


def test_text_table_and_snippet(capsys):
    code, out, _ = run(capsys, ['export', 'gazebo', *STEEL_ON_CAST_IRON, '--speed-range', '0.1',
                                '10', '--points', '3'])
    assert code == 0
    rows = [line.split() for line in out.split('# snippet:')[0].splitlines() if line[:1] == ' ']
    assert [float(r[0]) for r in rows] == pytest.approx([0.1, 1.0, 10.0])
    assert '<surface>' in out and 'predicted' in out


@pytest.mark.parametrize('argv, option', [
    (['--timestep', '0'], '--timestep'), (['--timestep', '1'], '--timestep'),
    (['--speed-range', '2', '1'], 'speed_range'), (['--points', '1'], '--points'),
    (['--mass', '-1'], '--mass')])
def test_bad_input_names_the_option(capsys, argv, option):
    code, _, err = run(capsys, ['export', 'gazebo', *STEEL_ON_CAST_IRON, *argv])
    assert code == 2
    assert option in err and 'allowed' in err


def test_radius_is_needed(capsys):
    code, _, err = run(capsys, ['export', 'gazebo', '--stiffness', '1e9', '--mass', '0.1',
                                '--damping', '1e4', '--law', 'azad_featherstone'])
    assert code == 2 and '--radius' in err

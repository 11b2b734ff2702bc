"""`contact-sim export`: the JSON record has exactly the issue's keys, the table and snippet are
printed, and bad input is refused naming the option."""
import json
import warnings
from pathlib import Path

import numpy as np
import pytest

from contact_sim import cli

CONFIG = Path(__file__).resolve().parents[2] / 'config' / 'fig5_geometry_b_steel_cast_iron.yaml'

STEEL_ON_CAST_IRON = ['--law', 'azad_featherstone', '--sphere', 'steel', '--plate', 'cast_iron',
                      '--radius', '0.0127', '--damping-factor', '8.87e5']
KEYS = {'engine', 'engine_version', 'target', 'parameters', 'snippet', 'speeds',
        'target_restitution', 'engine_restitution', 'engine_restitution_source', 'max_abs_error',
        'lowest_speed_with_gravity', 'rest_sag'}
PARAMETERS = {'mujoco': {'solref', 'solimp', 'priority', 'timestep', 'integrator'},
              'pybullet': {'restitution', 'contactStiffness', 'contactDamping', 'linearDamping',
                           'angularDamping', 'timestep'},
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
    rows = [line.split() for line in out.split('# snippet')[0].splitlines() if line[:1] == ' ']
    assert [float(r[0]) for r in rows] == pytest.approx([0.1, 1.0, 10.0])
    assert '<surface>' in out and 'predicted' in out


@pytest.mark.parametrize('argv, option', [
    (['--timestep', '0'], '--timestep'), (['--timestep', '1'], '--timestep'),
    (['--timestep', '0.1'], '--timestep'), (['--timestep', '-1e-3'], '--timestep'),
    (['--timestep', '1e-7'], '--timestep'), (['--timestep=-1e-3'], '--timestep'),
    (['--timestep', '-inf'], '--timestep'), (['--timestep', '-nan'], '--timestep'),
    (['--timestep', '-.5'], '--timestep'), (['--timestep', 'nan'], '--timestep'),
    (['--speed-range', '2', '1'], '--speed-range'), (['--points', '1'], '--points'),
    (['--points', '1000'], '--points'), (['--points', '1000000'], '--points'),
    (['--speeds', ','.join(['1'] * 41)], '--speeds'), (['--mass', '-1'], '--mass')])
def test_bad_input_names_the_option(capsys, argv, option):
    code, out, err = run(capsys, ['export', 'gazebo', *STEEL_ON_CAST_IRON, *argv])
    assert code == 2 and out == ''
    assert option in err and ('allowed' in err or 'must be a finite real number' in err)
    assert 'expected one argument' not in err


def test_negative_step_names_the_range(capsys):
    code, _, err = run(capsys, ['export', 'mujoco', *STEEL_ON_CAST_IRON, '--timestep', '-1e-3'])
    assert code == 2
    assert '--timestep = -0.001 is out of range: allowed 1e-05 <= --timestep <= 0.01' in err


def test_fewer_points_below_a_tenth_of_a_millisecond(capsys):
    code, _, err = run(capsys, ['export', 'gazebo', *STEEL_ON_CAST_IRON, '--timestep', '1e-5',
                                '--points', '5'])
    assert code == 2 and 'allowed 2 <= --points <= 4 at --timestep 1e-05 s' in err


def test_a_contact_that_cannot_hold_the_ball_is_refused(capsys):
    # Gazebo at 0.01 s: kp = m (10 rad/s)^2 sinks the 12.7 mm ball 9.8 cm (m g / kp)
    code, out, err = run(capsys, ['export', 'gazebo', *STEEL_ON_CAST_IRON, '--timestep', '0.01',
                                  '--format', 'json'])
    assert code == 2 and out == ''
    assert 'cannot hold the ball up' in err and 'allowed a step below 0.0036 s' in err


def test_tolerance_says_none_does_for_a_linear_law(capsys):
    code, out, _ = run(capsys, ['export', 'gazebo', *STEEL_ON_CAST_IRON, '--speeds', '0.1,10',
                                '--tolerance', '0.01'])
    assert code == 0
    assert '# tolerance 0.01: none does for a linear law' in out
    code, out, _ = run(capsys, ['export', 'gazebo', *STEEL_ON_CAST_IRON, '--speeds', '0.1,10',
                                '--tolerance', '0.2'])
    # 0.01 s: kp resolves the step only as a spring that sinks the ball 9.8 cm, beyond its radius
    assert '# time step 0.01 s: unusable, its contact cannot hold the ball up' in out
    assert 'the largest time step that meets it is 0.003 s' in out


@pytest.mark.parametrize('argv', [['--tolerance', '0'], ['--tolerance', '0.1', '--format',
                                                          'json']])
def test_bad_tolerance_names_the_option(capsys, argv):
    code, out, err = run(capsys, ['export', 'gazebo', *STEEL_ON_CAST_IRON, *argv])
    assert code == 2 and out == ''
    assert '--tolerance' in err and 'allowed' in err


def test_radius_is_needed(capsys):
    code, _, err = run(capsys, ['export', 'gazebo', '--stiffness', '1e9', '--mass', '0.1',
                                '--damping', '1e4', '--law', 'azad_featherstone'])
    assert code == 2 and '--radius' in err


def test_params_file_is_the_same_contact_as_the_options(capsys):
    common = ['export', 'gazebo', '--speeds', '0.5,2', '--format', 'json']
    _, by_options, _ = run(capsys, [*common, *STEEL_ON_CAST_IRON])
    code, by_file, _ = run(capsys, [*common, '--params-file', str(CONFIG)])
    assert code == 0
    assert json.loads(by_file) == json.loads(by_options)


BOUNCES_RESULT = """\
# contact calibrated by `contact-sim bounces` from drops.csv
contact_sim:
  ros__parameters:
    contact_law: hunt_crossley
    stiffness: 2.0e+8
    damping: 1.5e+7
    sphere_mass: 0.0459
    gravity: 9.81
    sphere_radius: {radius}
    drag_coefficient: 0.0
"""


def test_a_bounces_result_is_exported(capsys, tmp_path):
    path = tmp_path / 'golf.yaml'
    path.write_text(BOUNCES_RESULT.format(radius=0.02135))
    code, out, _ = run(capsys, ['export', 'drake', '--params-file', str(path), '--speeds',
                                '0.5,2', '--format', 'json'])
    assert code == 0
    assert json.loads(out)['target'] == {'law': 'hunt_crossley', 'stiffness': 2e8,
                                         'damping': 1.5e7, 'mass': 0.0459, 'radius': 0.02135}


def test_a_bad_value_in_the_file_is_named_by_its_key(capsys, tmp_path):
    path = tmp_path / 'bad.yaml'
    path.write_text(BOUNCES_RESULT.format(radius=-1.0))
    code, _, err = run(capsys, ['export', 'drake', '--params-file', str(path)])
    assert code == 2
    assert f'{path}: sphere_radius = -1.0 is out of range' in err


@pytest.mark.parametrize('text', [None, 'not: [yaml', 'a: 1\n'])
def test_an_unusable_params_file_is_refused(capsys, tmp_path, text):
    path = tmp_path / 'params.yaml'
    if text is not None:
        path.write_text(text)
    code, _, err = run(capsys, ['export', 'drake', '--params-file', str(path)])
    assert code == 2 and '--params-file' in err


def test_audit_prints_the_models_e_and_the_suggestion(capsys, tmp_path):
    path = tmp_path / 'ball.xml'
    path.write_text('<mujoco><option timestep="0.0005"/><worldbody><geom type="plane" '
                    'size="1 1 0.1"/><body pos="0 0 0.1"><freejoint/><geom name="ball" '
                    'type="sphere" size="0.0127" mass="0.0673549" solref="-40000 -60"/></body>'
                    '</worldbody></mujoco>')
    code, out, _ = run(capsys, ['audit', 'mujoco', str(path), '--geom', 'ball',
                                *STEEL_ON_CAST_IRON, '--speeds', '0.5,2'])
    assert code == 0
    assert 'solref = [-40000, -60]' in out and 'timestep="0.0005"' in out
    assert "floor '#0 (unnamed)' (the first plane on the world body): solref = [0.02, 1]" in out
    assert "the pair, by MuJoCo's rules: solref = [-40000, -60]" in out
    code, _, err = run(capsys, ['audit', 'mujoco', str(path), '--geom', 'nope',
                                *STEEL_ON_CAST_IRON])
    assert code == 2 and "--geom = 'nope'" in err


def test_audit_pybullet_prints_the_links_e_and_the_suggestion(capsys, tmp_path):
    path = tmp_path / 'ball.urdf'
    path.write_text('<?xml version="1.0"?><robot name="b"><link name="ball"><contact><restitution '
                    'value="0.3"/><stiffness value="400"/><damping value="0.5"/></contact>'
                    '<inertial><mass value="0.0673549"/><inertia ixx="4e-6" iyy="4e-6" '
                    'izz="4e-6" ixy="0" ixz="0" iyz="0"/></inertial><collision><geometry>'
                    '<sphere radius="0.0127"/></geometry></collision></link></robot>')
    common = ['audit', 'pybullet', str(path), *STEEL_ON_CAST_IRON, '--speeds', '0.5,2']
    code, out, _ = run(capsys, [*common, '--link', 'ball', '--timestep', '1e-3'])
    assert code == 0
    assert 'contactStiffness = 400 N/m' in out and 'p.setTimeStep(0.001)' in out
    rows = [line.split() for line in out.split('# snippet')[0].splitlines() if line[:1] == ' ']
    assert [float(r[0]) for r in rows] == [0.5, 2.0]
    code, _, err = run(capsys, [*common, '--link', 'nope'])
    assert code == 2 and "--link = 'nope'" in err
    code, _, err = run(capsys, common)
    assert code == 2 and '--link is missing' in err


WELDED = ('<mujoco><worldbody><geom name="floor" type="plane" size="1 1 0.1"/><body pos="0 0 0.1">'
          '<geom name="ball" type="sphere" size="0.0127" mass="0.0673549"/></body></worldbody>'
          '</mujoco>')
UNSTABLE = ('<mujoco><option timestep="0.01"/><worldbody><geom type="plane" size="1 1 0.1"/>'
            '<body pos="0 0 0.1"><freejoint/><geom name="ball" type="sphere" size="0.0127" '
            'mass="0.0673549" solref="-1e30 -1e30" priority="1"/></body></worldbody></mujoco>')


def test_audit_refuses_a_welded_sphere(capsys, tmp_path):
    path = tmp_path / 'welded.xml'
    path.write_text(WELDED)
    code, out, err = run(capsys, ['audit', 'mujoco', str(path), '--geom', 'ball',
                                  *STEEL_ON_CAST_IRON, '--speeds', '1'])
    assert code == 2 and out == ''
    assert "--geom = 'ball' is on a body without a free joint" in err and 'allowed' in err


@pytest.mark.parametrize('solref', ['-1e30 -1e30', '-1e12 -1e9'])   # NaN; e of 6e7
def test_audit_leaves_no_mujoco_log(capsys, tmp_path, monkeypatch, solref):
    monkeypatch.chdir(tmp_path)
    (tmp_path / 'unstable.xml').write_text(UNSTABLE.replace('-1e30 -1e30', solref))
    with warnings.catch_warnings():
        warnings.simplefilter('ignore', RuntimeWarning)   # MuJoCo's own words, as a warning
        code, _, err = run(capsys, ['audit', 'mujoco', 'unstable.xml', '--geom', 'ball',
                                    *STEEL_ON_CAST_IRON, '--speeds', '1'])
    assert code == 2 and 'MuJoCo went unstable' in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ['unstable.xml']

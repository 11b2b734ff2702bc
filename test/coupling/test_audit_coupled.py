"""`contact-sim audit ... --coupled`: the model's e(v) with the target coupled in, beside the
target's (the coupling at the model's own step)."""

from contact_sim import cli

STEEL_ON_CAST_IRON = ['--law', 'azad_featherstone', '--sphere', 'steel', '--plate', 'cast_iron',
                      '--radius', '0.0127', '--damping-factor', '8.87e5']


def _rows(out):
    return [[float(x) for x in line.split()] for line in out.split('# snippet')[0].splitlines()
            if line[:1] == ' ']


def test_audit_mujoco_coupled(capsys, tmp_path):
    path = tmp_path / 'ball.xml'
    path.write_text('<mujoco><option timestep="0.001"/><worldbody><geom type="plane" '
                    'size="1 1 0.1"/><body pos="0 0 0.1"><freejoint/><geom name="ball" '
                    'type="sphere" size="0.0127" mass="0.0673549" solref="-40000 -60"/></body>'
                    '</worldbody></mujoco>')
    code = cli.main(['audit', 'mujoco', str(path), '--geom', 'ball', *STEEL_ON_CAST_IRON,
                     '--speeds', '0.1,1,5', '--coupled'])
    out = capsys.readouterr().out
    assert code == 0 and 'coupled' in out
    rows = _rows(out)
    assert len(rows) == 3
    for _, target, _, _, _, coupled in rows:
        assert abs(coupled - target) < 0.005
    assert max(abs(r[2] - r[1]) for r in rows) > 0.01      # the model's own contact misses


def test_audit_pybullet_coupled(capsys, tmp_path):
    path = tmp_path / 'ball.urdf'
    path.write_text('<?xml version="1.0"?><robot name="b"><link name="ball"><contact><restitution '
                    'value="0.3"/><stiffness value="400"/><damping value="0.5"/></contact>'
                    '<inertial><mass value="0.0673549"/><inertia ixx="4e-6" iyy="4e-6" '
                    'izz="4e-6" ixy="0" ixz="0" iyz="0"/></inertial><collision><geometry>'
                    '<sphere radius="0.0127"/></geometry></collision></link></robot>')
    code = cli.main(['audit', 'pybullet', str(path), '--link', 'ball', *STEEL_ON_CAST_IRON,
                     '--speeds', '0.5,2', '--timestep', '1e-3', '--coupled'])
    out = capsys.readouterr().out
    assert code == 0
    for row in _rows(out):
        assert abs(row[5] - row[1]) < 0.005


def test_audit_coupled_refuses_rk4(capsys, tmp_path):
    path = tmp_path / 'ball.xml'
    path.write_text('<mujoco><option timestep="0.001" integrator="RK4"/><worldbody><geom '
                    'type="plane" size="1 1 0.1"/><body pos="0 0 0.1"><freejoint/><geom '
                    'name="ball" type="sphere" size="0.0127" mass="0.0673549"/></body>'
                    '</worldbody></mujoco>')
    code = cli.main(['audit', 'mujoco', str(path), '--geom', 'ball', *STEEL_ON_CAST_IRON,
                     '--speeds', '0.5', '--coupled'])
    err = capsys.readouterr().err
    assert code == 2 and 'integrator' in err and 'RK4' in err

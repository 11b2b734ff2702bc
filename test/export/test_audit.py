"""The audit of a user's MuJoCo model: the e(v) it reports for a sphere geom is what MuJoCo
gives that model's ball (this test's own throw of the model as written)."""
import pytest

from contact_sim.export import audit, geom_contact
from contact_sim.validation import InputError

import mujoco  # noqa: E402

MODEL = """<mujoco><option timestep="0.0005" gravity="0 0 0"/><worldbody><geom type="plane" size="1 1 0.1"/>
<body pos="0 0 0.1"><freejoint/><geom name="ball" type="sphere" size="0.0127" mass="0.0673549"
solref="-40000 -60"/></body><geom name="box" type="box" size="0.1 0.1 0.1" pos="1 1 1"/>
</worldbody></mujoco>"""


def thrown(path, speed):
    """This test's own throw of the model file's ball (gravity off in the file, as e is
    defined), straight down at ``speed`` (m/s)."""
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    data.qvel[2] = -speed
    start = float(data.qpos[2])
    for _ in range(1_000_000):
        mujoco.mj_step(model, data)
        if data.qvel[2] > 0 and data.qpos[2] > start:
            return data.qvel[2] / speed
    raise AssertionError(f'no rebound at {speed} m/s')


def test_audit_gives_what_the_model_gives(tmp_path):
    path = tmp_path / 'ball.xml'
    path.write_text(MODEL)
    contact = geom_contact(path, 'ball')
    assert (contact.solref, contact.timestep, contact.integrator) == ((-40000.0, -60.0), 0.0005,
                                                                      'Euler')
    for speed, said in zip([0.2, 3.0], audit(contact, [0.2, 3.0])):
        assert abs(thrown(path, speed) - said) < 0.01


@pytest.mark.parametrize('geom, field', [('nope', 'geom'), ('box', 'geom')])
def test_not_a_sphere_geom_is_refused(tmp_path, geom, field):
    path = tmp_path / 'ball.xml'
    path.write_text(MODEL)
    with pytest.raises(InputError) as error:
        geom_contact(path, geom)
    assert error.value.field == field


def test_a_model_that_does_not_load_is_refused(tmp_path):
    with pytest.raises(InputError) as error:
        geom_contact(tmp_path / 'missing.xml', 'ball')
    assert error.value.field == 'model'


FLOORED = """<mujoco><option timestep="0.0002" gravity="0 0 0"/><worldbody>
<geom name="floor" type="plane" size="1 1 0.1" {floor}/>
<body pos="0 0 0.1"><freejoint/><geom name="ball" type="sphere" size="0.0127" mass="0.0673549"
{ball}/></body></worldbody></mujoco>"""


@pytest.mark.parametrize('floor, ball', [
    ('solref="0.005 0.5" solimp="0.8 0.9 0.001 0.5 2"', ''),   # the floor's own contact
    ('solref="0.005 0.5" solmix="3"', 'solref="0.02 0.3"'),      # mixed by solmix
    ('priority="1"', 'solref="-40000 -20"'),                     # the floor's wins whole
    ('margin="0.001"', 'solref="-40000 -20" priority="1"'),      # the larger margin
])
def test_audit_reads_the_models_floor(tmp_path, floor, ball):
    path = tmp_path / 'ball.xml'
    path.write_text(FLOORED.format(floor=floor, ball=ball))
    contact = geom_contact(path, 'ball')
    assert contact.floor_name == 'floor'
    assert 'floor \'floor\' (the first plane on the world body)' in contact.describe()[1]
    for speed, said in zip([0.3, 2.0], audit(contact, [0.3, 2.0])):
        assert abs(thrown(path, speed) - said) < 0.01


def test_the_pair_is_combined_by_mujocos_rules(tmp_path):
    path = tmp_path / 'ball.xml'
    path.write_text(FLOORED.format(floor='solref="0.01 0.5" solimp="0.8 0.9 0.002 0.5 2" '
                                         'solmix="3" margin="0.002"',
                                   ball='solref="0.03 1.5" solimp="0.9 0.95 0.001 0.5 2"'))
    solref, solimp, margin, gap = geom_contact(path, 'ball').combined()
    # equal priority: mixed, the ball's weight 1 / (1 + 3); the larger margin
    assert solref == pytest.approx((0.25 * 0.03 + 0.75 * 0.01, 0.25 * 1.5 + 0.75 * 0.5))
    assert solimp[:3] == pytest.approx((0.825, 0.9125, 0.00175))
    assert (margin, gap) == (0.002, 0.0)
    path.write_text(FLOORED.format(floor='solref="0.01 0.5"', ball='solref="-4e4 -20"'))
    assert geom_contact(path, 'ball').combined()[0] == (-4e4, -20.0)   # direct: the smaller


def test_a_welded_sphere_is_refused(tmp_path):
    path = tmp_path / 'ball.xml'
    path.write_text(FLOORED.format(floor='', ball='').replace('<freejoint/>', ''))
    with pytest.raises(InputError) as error:
        geom_contact(path, 'ball')
    assert error.value.field == 'geom' and 'free joint' in str(error.value)

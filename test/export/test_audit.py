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

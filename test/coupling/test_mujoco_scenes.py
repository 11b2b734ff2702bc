"""The MuJoCo coupling on scenes as users write them (``contact_sim.coupling.mujoco``): pairs that
cannot be coupled are refused by an ``InputError`` naming ``pairs``, before they can inject
energy; MuJoCo's explicit contact pairs of a coupled geom are switched off."""
import numpy as np
import pytest

import contact_sim as cs

import mujoco
from contact_sim.coupling.mujoco import CoupledContacts  # noqa: E402

R = 0.0127
STEEL = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron', radius=R,
                                  damping_factor=8.87e5)
MASS = float(cs.sphere_mass(cs.MATERIALS["steel"].density, R))


def scene(bodies, world='<geom name="floor" type="plane" size="1 1 0.1"/>', option='',
          after=''):
    xml = (f'<mujoco><option timestep="0.001" {option}/><worldbody>{world}{bodies}'
           f'</worldbody>{after}</mujoco>')
    model = mujoco.MjModel.from_xml_string(xml)
    return model, mujoco.MjData(model)


def ball(name, x, z):
    return (f'<body name="{name}" pos="{x!r} 0 {z!r}"><freejoint/><geom name="{name}" '
            f'type="sphere" size="{R!r}" mass="{MASS!r}"/></body>')


def test_a_pair_named_twice_is_refused():
    model, data = scene(ball('ball', 0.0, 0.2))
    for pairs in ([('ball', 'floor', STEEL), ('floor', 'ball', STEEL)],
                  [('ball', 'floor', STEEL), ('ball', 'floor', STEEL)]):
        with pytest.raises(cs.InputError) as refused:
            CoupledContacts(model, data, pairs)
        assert refused.value.field == 'pairs' and 'twice' in str(refused.value)


def test_two_geoms_of_one_body_are_refused():
    model, data = scene('<body pos="0 0 0.2"><freejoint/><geom name="a" type="sphere" size="0.01"'
                        '/><geom name="b" type="sphere" size="0.01" pos="0 0 0.1"/></body>')
    for pair in (('a', 'b', STEEL), ('a', 'a', STEEL)):
        with pytest.raises(cs.InputError) as refused:
            CoupledContacts(model, data, [pair])
        assert refused.value.field == 'pairs' and 'same body' in str(refused.value)


def test_a_stack_of_coupled_contacts_is_refused_not_launched():
    # a ball dropped on a ball resting on the floor: the two contacts push on one body along
    # one line; each pair integrated alone would pump energy in (measured before the refusal:
    # the lower ball launched to 2e4 m)
    model, data = scene(ball('low', 0.0, R) + ball('up', 0.0, 0.2))
    coupled = CoupledContacts(model, data, [('low', 'floor', STEEL), ('up', 'low', STEEL)])
    with pytest.raises(cs.InputError) as refused:
        for _ in range(3000):
            coupled.step()
            assert abs(data.qpos[2]) < 1.0 and abs(data.qpos[9]) < 1.0
    assert refused.value.field == 'pairs' and 'pairs[0] and pairs[1]' in str(refused.value)


def test_a_ball_in_a_corner_rests_on_both_pairs():
    # two pairs on one ball whose normals are orthogonal: independent, served
    walls = ('<geom name="floor" type="plane" size="1 1 0.1"/>'
             '<geom name="wall" type="plane" size="1 1 0.1" zaxis="1 0 0"/>')
    model, data = scene(ball('ball', R, 0.1), world=walls, option='gravity="-3 0 -9.81"')
    coupled = CoupledContacts(model, data, [('ball', 'floor', STEEL), ('ball', 'wall', STEEL)])
    path = []
    for _ in range(3000):
        coupled.step()
        path.append(data.qpos[[0, 2]].copy())
    tail = np.array(path[-500:])
    z0 = STEEL.static_penetration(MASS * 9.81)
    x0 = STEEL.static_penetration(MASS * 3.0)
    assert np.all(np.abs(tail[:, 1] - (R - z0)) < 1e-6), tail[:, 1].min()
    assert np.all(np.abs(tail[:, 0] - (R - x0)) < 1e-6), tail[:, 0].min()


def test_mujocos_explicit_pair_of_a_coupled_geom_is_switched_off():
    explicit = '<contact><pair geom1="ball" geom2="floor"/></contact>'
    runs = []
    for after in ('', explicit):
        model, data = scene(ball('ball', 0.0, 0.2), after=after)
        coupled = CoupledContacts(model, data, [('ball', 'floor', STEEL)])
        for _ in range(1500):
            coupled.step()
            assert data.ncon == 0
        runs.append([(i.speed_in, i.speed_out) for i in coupled.impacts])
    assert runs[0] == runs[1]


def test_a_ball_closing_more_than_the_reach_in_a_step_is_refused_not_launched():
    # 20 m/s at 5 ms: 10 cm a step, beyond the default reach of 5 cm (before: the touch fell
    # in a step the pair was not looked at, and the ball left at 830 m/s, e = 41.5)
    results = []
    for reach in (None, 0.2):
        model, data = scene(ball('ball', 0.0, 0.5), option='gravity="0 0 0"')
        model.opt.timestep = 0.005
        data.qvel[2] = -20.0
        coupled = CoupledContacts(model, data, [('ball', 'floor', STEEL)],
                                  **({} if reach is None else {'reach': reach}))
        try:
            for _ in range(100):
                coupled.step()
        except cs.InputError as refused:
            results.append(refused)
            continue
        results.append(data.qvel[2] / 20.0)
    assert isinstance(results[0], cs.InputError) and results[0].field == 'reach'
    assert results[1] == pytest.approx(coupled.impacts[0].restitution, rel=1e-6)
    assert 0.5 < results[1] < 0.7

"""Drake measured (pydrake, about 420 MB, is pinned in requirements.txt: a missing install fails
this file): the e(v) the export reports is what Drake gives the snippet's SDFormat
(this test's own plant, parsed from the snippet) within 0.01, for the discrete plant at 1e-3 s
and the continuous plant; the continuous plant gives the law f = k x (1 + d xdot), its peak
duration and peak force too (so the two geometries' 2k combine to k)."""
import re

import numpy as np
import pytest
from .test_export import RADIUS, SPEEDS, ode_contact, steel_on_cast_iron

from contact_sim.export import export_contact
from contact_sim.export.drake import drake_law_restitution

import pydrake.all as d  # noqa: E402  (pinned in requirements.txt: a missing install fails here)

SDF = ('<?xml version="1.0"?><sdf version="1.9" xmlns:drake="http://drake.mit.edu"><model '
       'name="{name}">{static}<link name="{name}">{inertial}{collision}</link></model></sdf>')


def snippet_plant(snippet, mass, time_step):
    """This test's own plant: the snippet's two collisions on a free ball and a static ground."""
    ball, plane = re.findall(r'<collision name="\w+">.*?</collision>', snippet, re.S)
    inertia = 0.4 * mass * RADIUS ** 2
    inertial = (f'<inertial><mass>{mass!r}</mass><inertia><ixx>{inertia!r}</ixx><iyy>'
                f'{inertia!r}</iyy><izz>{inertia!r}</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz>'
                '</inertia></inertial>')
    builder = d.DiagramBuilder()
    plant, _ = d.AddMultibodyPlant(d.MultibodyPlantConfig(time_step=time_step,
                                                          contact_model='point'), builder)
    parser = d.Parser(plant)
    parser.AddModelsFromString(SDF.format(name='ball', static='', inertial=inertial,
                                          collision=ball), 'sdf')
    parser.AddModelsFromString(SDF.format(name='ground', static='<static>true</static>',
                                          inertial='', collision=plane), 'sdf')
    plant.mutable_gravity_field().set_gravity_vector([0.0, 0.0, 0.0])
    plant.Finalize()
    return builder.Build(), plant


def snippet_throw(system, speed, gap):
    """e of the snippet's ball thrown at ``speed`` (m/s) from ``gap`` (m) above the ground."""
    diagram, plant = system
    simulator = d.Simulator(diagram)
    context = plant.GetMyMutableContextFromRoot(simulator.get_mutable_context())
    ball = plant.GetBodyByName('ball')
    plant.SetFreeBodyPose(context, ball, d.RigidTransform([0.0, 0.0, RADIUS + gap]))
    plant.SetFreeBodySpatialVelocity(context=context, body=ball,
                                     V_JpJc=d.SpatialVelocity([0.0] * 3, [0.0, 0.0, -speed]))
    h = plant.time_step()
    if h == 0.0:
        simulator.get_mutable_integrator().set_target_accuracy(1e-8)
        h = 1e-6
    t = 0.0
    while True:
        t += h
        simulator.AdvanceTo(t)
        if plant.GetVelocities(context)[5] > 0 and plant.GetPositions(context)[6] > RADIUS + gap:
            return plant.GetVelocities(context)[5] / speed


@pytest.mark.parametrize('timestep', [1e-3, 0.0])
def test_drake_gives_what_the_export_says(timestep):
    target = steel_on_cast_iron()
    result = export_contact('drake', target, timestep)
    assert result.engine_restitution_source == 'measured'
    system = snippet_plant(result.snippet, target.mass, timestep)
    for speed, said in zip(SPEEDS, result.engine_restitution):
        for gap in (0.0013, 0.37 * speed * (timestep or 1e-5)):   # phases a user's drop may have
            assert abs(snippet_throw(system, speed, gap) - said) < 0.01


def test_continuous_plant_is_the_law():
    target = steel_on_cast_iron()
    result = export_contact('drake', target, 0.0)
    k = result.parameters['point_contact_stiffness']
    dissipation = result.parameters['hunt_crossley_dissipation']
    law = drake_law_restitution(k, dissipation, target.mass, SPEEDS)
    assert result.engine_restitution == pytest.approx(law, abs=1e-4)
    # this test's own integration of the law: e, the time the force is > 0 and its peak
    e, duration, peak = np.transpose([ode_contact(
        lambda x, xd: k * x * (1.0 + dissipation * xd), target.mass, v) for v in SPEEDS])
    assert result.engine_restitution == pytest.approx(e, abs=1e-4)
    assert result.engine_peak_force == pytest.approx(peak, rel=0.01)
    assert result.engine_duration == pytest.approx(duration, rel=0.03)

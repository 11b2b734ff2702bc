"""Drake without pydrake: the e(v) the export predicts is Drake's point-contact law f = k x (1 +
d xdot) exactly (this test's own integration), and the ball's properties against a ground of its
own give the pair Drake's series rule combines to."""
import pytest
from .test_export import SPEEDS, ode_restitution, steel_on_cast_iron

from contact_sim.export import drake_plant, export_contact


@pytest.mark.parametrize('timestep', [1e-3, 0.0])
def test_predicted_is_drakes_law_exactly(monkeypatch, timestep):
    monkeypatch.setattr(drake_plant, 'importable', lambda: False)   # as without pydrake
    target = steel_on_cast_iron()
    result = export_contact('drake', target, timestep)
    k = result.parameters['point_contact_stiffness']
    d = result.parameters['hunt_crossley_dissipation']
    direct = [ode_restitution(lambda x, xd: k * x * (1.0 + d * xd), target.mass, v)
              for v in SPEEDS]
    assert result.engine_restitution_source == 'predicted'
    assert result.parameters['time_step'] == timestep
    assert result.engine_restitution == pytest.approx(direct, abs=1e-6)


def drake_combined(k1, d1, k2, d2):
    """Drake's combination of two geometries' point-contact properties (contact_properties.cc):
    stiffness in series, dissipation weighted by the other's stiffness."""
    return k1 * k2 / (k1 + k2), (k2 * d1 + k1 * d2) / (k1 + k2)


@pytest.mark.parametrize('ground', [(1e6, 0.0), (3e5, 0.5), (2e5, 0.2)])
def test_ball_properties_give_the_pair(ground):
    k, d = 1e5, 0.3
    k1, d1 = drake_plant.ball_properties(k, d, *ground)
    assert drake_combined(k1, d1, *ground) == pytest.approx((k, d), rel=1e-12)
    assert drake_combined(*drake_plant.pair_properties(k, d), *drake_plant.pair_properties(k, d)
                          ) == pytest.approx((k, d), rel=1e-12)


@pytest.mark.parametrize('ground', [(1e5, 0.0), (5e4, 0.0), (2e5, 5.0)])
def test_a_ground_that_cannot_give_the_pair_is_refused(ground):
    with pytest.raises(ValueError):
        drake_plant.ball_properties(1e5, 0.3, *ground)

"""What time step reaches a tolerance: none for a linear law below half the target's spread
(no step tried), the largest step that meets it otherwise, and the best error when none does."""
import numpy as np
import pytest

from contact_sim.export import drake_plant, export_contact, timestep_for_tolerance
from contact_sim.validation import InputError

from .test_export import steel_on_cast_iron


def test_a_linear_law_below_half_the_spread_tries_no_step():
    target = steel_on_cast_iron()
    search = timestep_for_tolerance('gazebo', target, 0.05)
    assert search.timestep is None and search.tried == ()
    assert search.floor == pytest.approx(np.ptp(target.restitution) / 2)
    assert search.best_error == search.floor
    assert export_contact('gazebo', target, 1e-3).max_abs_error >= search.floor - 1e-9


def test_the_largest_step_that_meets_it():
    target = steel_on_cast_iron()
    floor = np.ptp(target.restitution) / 2
    search = timestep_for_tolerance('mujoco', target, floor + 0.005, (1e-3, 1e-2))
    assert search.tried[0][0] == 1e-2   # largest first
    assert search.timestep == search.tried[-1][0]
    assert export_contact('mujoco', target, search.timestep).max_abs_error <= floor + 0.005


def test_none_meets_it_gives_the_best_error(monkeypatch):
    monkeypatch.setattr(drake_plant, 'importable', lambda: False)   # the predicted law
    target = steel_on_cast_iron()
    search = timestep_for_tolerance('drake', target, 0.01, (1e-3, 1e-4))
    assert search.timestep is None and search.floor is None
    assert [t for t, _ in search.tried] == [1e-3, 1e-4]
    assert search.best_error == pytest.approx(export_contact('drake', target, 1e-4).max_abs_error)
    assert search.best_error > 0.01


@pytest.mark.parametrize('tolerance', [0.0, -0.1, float('nan')])
def test_a_bad_tolerance_is_refused(tolerance):
    with pytest.raises(InputError) as error:
        timestep_for_tolerance('gazebo', steel_on_cast_iron(), tolerance)
    assert error.value.field == 'tolerance'

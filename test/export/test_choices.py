"""The export's choices the command line reads without the engines (``export.choices``)."""
from contact_sim.export import ENGINE_NAMES, ENGINES, TIMESTEPS, timestep_for_tolerance


def test_the_engine_names_are_the_engines_in_their_order():
    assert ENGINE_NAMES == tuple(ENGINES)
    assert all(ENGINES[name].name == name for name in ENGINE_NAMES)


def test_the_tolerance_search_tries_the_time_steps_largest_first():
    assert list(TIMESTEPS) == sorted(TIMESTEPS, reverse=True)
    assert timestep_for_tolerance.__defaults__ == (TIMESTEPS,)

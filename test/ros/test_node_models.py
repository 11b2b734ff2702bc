"""One model per change (issue 33, item 8): the node validates a parameter change once, keeps
what the validation built (the ``Model`` and a fresh drop) and applies it. Before, a change built
a throwaway ``DropSimulation`` to check, then the model again to apply it; the start built two,
and ``~/reset`` a third. The loop's settings (``real_time_factor``) build no model.

The node runs in this process (its own context, the package's domain), so that the builds can be
counted; it is never spun, so it publishes nothing.
"""
import pytest

import rclpy

import contact_sim as cs  # noqa: E402
from contact_sim.ros import params as cs_params  # noqa: E402
from rclpy.parameter import Parameter  # noqa: E402
from std_srvs.srv import Trigger  # noqa: E402


class Counted:
    """Counts the calls of ``function`` (a model validated, a drop built)."""

    def __init__(self, function):
        self.function, self.calls = function, 0

    def __call__(self, *args, **kwargs):
        self.calls += 1
        return self.function(*args, **kwargs)


@pytest.fixture
def counted(ros_env, monkeypatch):
    from contact_sim.ros.node import ContactSimNode
    models = Counted(cs_params._build_model)
    drops = Counted(cs.DropSimulation)
    monkeypatch.setattr(cs_params, '_build_model', models)
    monkeypatch.setattr(cs, 'DropSimulation', drops)
    context = rclpy.Context()
    context.init()
    node = ContactSimNode(context=context, parameter_overrides=[
        Parameter('publish_clock', value=False)], cli_args=['--ros-args', '-r',
                                                             '__node:=counted'])
    try:
        yield node, models, drops
    finally:
        node.destroy_node()
        context.try_shutdown()


def test_one_model_is_built_per_accepted_change(counted):
    node, models, drops = counted

    def built():
        counts = (models.calls, drops.calls)
        models.calls = drops.calls = 0
        return counts

    assert built() == (1, 1)        # the start: one model, whose drop runs
    (result,) = node.set_parameters([Parameter('stiffness', value=5e9)])
    assert result.successful, result.reason
    assert built() == (1, 1)        # validated once; its drop kept for the next ~/reset
    assert node.get_parameter('stiffness').value == 5e9
    (result,) = node.set_parameters([Parameter('contact_law', value='bouncy')])
    assert not result.successful and "contact_law = 'bouncy'" in result.reason
    assert built() == (1, 0)        # refused: validated once, nothing built
    (result,) = node.set_parameters([Parameter('real_time_factor', value=2.0)])
    assert result.successful, result.reason
    assert built() == (0, 0)        # the loop's settings: no model
    result = node.set_parameters_atomically([Parameter('initial_height', value=0.5),
                                             Parameter('real_time_factor', value=1.0)])
    assert result.successful, result.reason
    assert built() == (1, 1)        # one change of two parameters: one model
    # ~/reset runs the drop the last change built; a second one needs a new drop, no model
    for expected in ((0, 0), (0, 1)):
        response = node._on_reset(Trigger.Request(), Trigger.Response())
        assert response.success and 'drop from 0.5 m' in response.message, response.message
        assert 'k = 5e+09' in response.message, response.message
        assert built() == expected


class Said:
    """A logger that keeps what it is told (the node's ``get_logger()`` in a test)."""

    def __init__(self, logger):
        self.logger, self.warnings = logger, []

    def warning(self, text, **kwargs):
        self.warnings.append(text)

    def __getattr__(self, name):
        return getattr(self.logger, name)


def test_a_law_waiting_for_its_stiffness_is_said_once_not_at_every_change(counted):
    # found by a hostile client: 50,000 accepted changes of gravity while a linear law waited
    # for its stiffness logged the note 50,000 times
    node = counted[0]
    said = Said(node.get_logger())
    node.get_logger = lambda: said

    def notes():
        return [text for text in said.warnings if 'waits for its stiffness' in text]

    assert node.set_parameters([Parameter('contact_law', value='linear')])[0].successful
    assert len(notes()) == 1, said.warnings
    for gravity in (9.0, 9.5, 9.81):
        (result,) = node.set_parameters([Parameter('gravity', value=gravity)])
        assert result.successful, result.reason
    assert node.set_parameters([Parameter('real_time_factor', value=2.0)])[0].successful
    assert node.set_parameters([Parameter('gravity', value=9.7)])[0].successful
    assert len(notes()) == 1, said.warnings       # still waiting: said once
    assert node.set_parameters([Parameter('contact_law', value='hunt_crossley')])[0].successful
    assert node.set_parameters([Parameter('contact_law', value='linear')])[0].successful
    assert len(notes()) == 2, said.warnings   # waiting again: said again

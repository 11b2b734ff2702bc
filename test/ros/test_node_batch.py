"""The node's batched publishing helpers against their per-message originals: the one-call CDR
packer against ``CdrTemplate.encode``, ``sample_columns`` against ``contact_samples``."""
import math

import numpy as np
import pytest


from contact_sim import Samples  # noqa: E402
from contact_sim.ros import messages as cs_msgs  # noqa: E402


@pytest.mark.parametrize('topic', [t for t in cs_msgs.TOPICS if t.fields or t.kind == 'clock'],
                         ids=lambda t: t.key)
def test_the_packer_gives_the_template_bytes(topic):
    rng = np.random.default_rng(7)
    template = topic.template('plate_frame')
    pack = template.packer()
    assert pack is not template.encode        # the one-call form for every topic of the table
    for _ in range(500):
        ns = int(rng.integers(0, 2 ** 31 * 10 ** 9))
        values = rng.normal(size=len(topic.fields)) * 10.0 ** rng.integers(-9, 9)
        assert pack(ns, *values.tolist()) == template.encode(ns, *values.tolist())


def test_a_packer_of_any_other_layout_is_the_encoder():
    from geometry_msgs.msg import WrenchStamped
    template = cs_msgs.CdrTemplate(WrenchStamped, ('wrench.force.z', 'wrench.force.x'), 'p')
    assert template.packer() == template.encode      # fields out of order: the general form


def _columns(out):
    return [list(c) for c in zip(*out)] if out else [[], [], [], []]


@pytest.mark.parametrize('case', ['plain', 'ties', 'nonfinite', 'after'])
def test_sample_columns_selects_as_contact_samples(case):
    rng = np.random.default_rng(3)
    t = np.sort(rng.uniform(1.0, 2.0, 400))
    if case in ('ties', 'nonfinite'):   # runs of samples within a nanosecond, ties of force
        t[50:54] = t[50] + np.array([0.0, 1e-10, 2e-10, 3e-10])
        t[200:203] = t[200]
    z, zdot, force = rng.normal(size=(3, t.size))
    force[51] = force[52] = 5.0
    if case == 'nonfinite':
        z[10], force[300] = math.nan, math.inf
    after = cs_msgs.to_ns(0.25 + t[100]) if case == 'after' else -1
    ns, zz, rate, ff, dropped = cs_msgs.sample_columns(t, z, zdot, force, 0.25, after)
    out, expected_dropped = cs_msgs.contact_samples(Samples(t, z, zdot, force), 0.25, after)
    assert [ns, zz, rate, ff] == _columns(out)
    assert dropped == expected_dropped == (2 if case == 'nonfinite' else 0)
    assert len(ns) < t.size if case != 'plain' else len(ns) == t.size

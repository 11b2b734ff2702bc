"""``contact_sim.ros.messages`` without a ROS process: the CDR encoders against the message
functions.
"""

import pytest

import rclpy  # noqa: E402,F401  (pinned: a missing install fails here)

import contact_sim as cs  # noqa: E402
from contact_sim.ros import messages as cs_msgs  # noqa: E402
from rclpy.serialization import serialize_message  # noqa: E402


def test_the_cdr_encoders_give_the_message_functions_messages():
    from rclpy.serialization import deserialize_message
    ns = 12_345_678_901
    cases = {'wrench': ((ns, 42.5), cs_msgs.wrench_msg(ns, 42.5, 'plate')),
             'contact': ((ns, 1e-6, 0.25, 1.0), cs_msgs.contact_msg(ns, 1e-6, 0.25, 7.0, 'plate')),
             'pose': ((ns, 0.0127 - 1e-6), cs_msgs.pose_msg(ns, 0.0127, 1e-6, 'plate')),
             'twist': ((ns, -0.25), cs_msgs.twist_msg(ns, 0.25, 'plate')),
             'clock': ((ns,), cs_msgs.clock_msg(ns)),
             'plate_pose': ((ns, -0.002), cs_msgs.plate_pose_msg(ns, -0.002, 'plate')),
             'plate_twist': ((ns, 0.3), cs_msgs.plate_twist_msg(ns, 0.3, 'plate')),
             'plate_wrench': ((ns, -42.5), cs_msgs.plate_wrench_msg(ns, 42.5, 'plate'))}
    assert set(cases) == {t.key for t in cs_msgs.TOPICS} - {'impact'}
    # the sphere's pose and twist over a moving plate: absolute, p + R1 - z and pdot - zdot
    assert cs_msgs.pose_msg(ns, 0.0127, 1e-6, 'plate', 0.003).pose.position.z == \
        pytest.approx(0.003 + 0.0127 - 1e-6)
    assert cs_msgs.twist_msg(ns, 0.25, 'plate', 0.5).twist.linear.z == 0.25
    for key, (args, expected) in cases.items():
        topic = cs_msgs.TOPIC[key]
        data = topic.template('plate').encode(*args)
        assert deserialize_message(data, topic.msg_type) == expected, key
        assert topic.times_of_cdr(data) == (ns, ns)
    impact = cs_msgs.impact_msg(cs.ImpactRecord(1.0, 1.0, 0.5, 0.5, 2e-4, 10.0, 1e-6), 0.5)
    assert cs_msgs.TOPIC['impact'].times_of_cdr(serialize_message(impact)) == (
        1_500_000_000, 1_500_200_000)

"""Size limits on ~/plate_command and ~/query_restitution, and refusals counted in the log, with
the package's node (issue 22: a 100,000-point trajectory stalled it for 2.3 s, a 100k-name
query for 1.9 s; a second bad trajectory within a second was dropped without a log line)."""

import rclpy  # noqa: E402,F401  (pinned: a missing install fails here)

from builtin_interfaces.msg import Duration  # noqa: E402
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint  # noqa: E402

from .harness import NODE, rosout_has  # noqa: E402


def test_oversized_inputs_are_refused_with_the_limit_and_refusals_are_counted(sim, client):
    publisher = client.node.create_publisher(JointTrajectory, f'{NODE}/plate_command', 10)
    try:
        client.spin_until(lambda: publisher.get_subscription_count() > 0, 'the node to subscribe')
        points = [JointTrajectoryPoint(positions=[0.0], time_from_start=Duration(sec=1 + i))
                  for i in range(100_000)]
        publisher.publish(JointTrajectory(joint_names=['plate_z'], points=points))
        client.spin_until(lambda: rosout_has(client, 'points has 100000 points: allowed at most '
                                                     '1000'), 'the size refusal')
        for _ in range(4):   # within a second of that refusal: held back, then counted
            publisher.publish(JointTrajectory(joint_names=['wrong'], points=points[:1]))
        client.spin_until(lambda: rosout_has(client, 'more refused in the last 1 s'),
                          'the count of the refusals held back')
        values = client.query([f'restitution:{1 + i * 1e-5}' for i in range(100_000)])
        assert list(values) == []
        client.spin_until(lambda: rosout_has(client, 'names has 100000 names: allowed at most '
                                                     '1000'), 'the query refusal')
        (value,) = client.query(['restitution:1'])      # a small query is answered
        assert 0.0 < value.double_value < 1.0
    finally:
        client.node.destroy_publisher(publisher)
    assert sim.popen.poll() is None, sim.output()

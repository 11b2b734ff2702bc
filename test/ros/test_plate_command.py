"""``~/plate_command`` as the node reads it (``plate_command.read_plate_command``), without a ROS
process: stamps and fields, refusals naming the field, and the README's ``ros2 topic pub`` lines.
The core's rules for the commands are tested in ``test/drop/test_plate_commands.py``."""
import re

import pytest
import yaml

import rclpy  # noqa: E402,F401  (pinned: a missing install fails here)

from .harness import NODE, PLATE_COMMAND_YAML, fill_message, readme  # noqa: E402


def test_read_plate_command_translates_stamps_and_fields():
    from builtin_interfaces.msg import Duration
    from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

    from contact_sim.ros.node import read_plate_command
    msg = JointTrajectory(joint_names=['plate_z'], points=[
        JointTrajectoryPoint(positions=[0.01], velocities=[0.0], accelerations=[99.0],
                             time_from_start=Duration(sec=1)),
        JointTrajectoryPoint(positions=[0.02], velocities=[0.5],
                             time_from_start=Duration(sec=1, nanosec=500_000_000))])
    # stamp 0: from receipt (the drop's time now = 3 s)
    assert read_plate_command(msg, 3.0, 100.0) == ([4.0, 4.5], [0.01, 0.02], [0.0, 0.5])
    # a stamp in simulated time (offset 100 s + the drop's time)
    msg.header.stamp.sec = 105
    assert read_plate_command(msg, 3.0, 100.0)[0] == [6.0, 6.5]
    for point in msg.points:
        point.velocities = []
    assert read_plate_command(msg, 3.0, 100.0)[2] is None          # estimated by the core
    msg.points[0].velocities = [0.0]
    with pytest.raises(ValueError, match=r'velocities are given for some points only'):
        read_plate_command(msg, 3.0, 100.0)
    msg.points[0].positions = [0.0, 1.0]
    with pytest.raises(ValueError, match=r'points\[0\]\.positions has 2 values: allowed 1'):
        read_plate_command(msg, 3.0, 100.0)
    msg.joint_names = ['paddle']
    with pytest.raises(ValueError, match=r"joint_names = \['paddle'\] is invalid: allowed "
                                         r"\['plate_z'\]"):
        read_plate_command(msg, 3.0, 100.0)
    with pytest.raises(ValueError, match='points is empty'):
        read_plate_command(JointTrajectory(joint_names=['plate_z']), 3.0, 0.0)


def test_the_readme_plate_commands_parse_as_yaml_and_drive_the_plate():
    """The README's `ros2 topic pub` lines: YAML 1.1 (yaml.safe_load, as the ros2 CLI reads it),
    the message's own fields, and accepted by the node's translation and the core's rules."""
    from trajectory_msgs.msg import JointTrajectory

    from contact_sim.drop.plate import command_motion
    from contact_sim.ros.node import read_plate_command
    lines = re.findall(r'ros2 topic pub --once (\S+) (\S+) "(.*)"', readme())
    assert len(lines) >= 2 and PLATE_COMMAND_YAML in [text for _, _, text in lines]
    for topic, type_name, text in lines:
        assert topic == f'{NODE}/plate_command'
        assert type_name == 'trajectory_msgs/msg/JointTrajectory'
        msg = fill_message(JointTrajectory(), yaml.safe_load(text))
        times, positions, velocities = read_plate_command(msg, 2.0, 0.0)
        command = command_motion(2.0, 0.0, 0.0, times, positions, velocities)
        assert command.dropped == 0 and command.motion is not None
        assert command.motion.state(times[-1])[0] == pytest.approx(positions[-1])

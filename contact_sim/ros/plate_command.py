"""``~/plate_command`` (trajectory_msgs/JointTrajectory, one prismatic joint ``plate_z``) as the
core's plate command: the node only translates the message here; the rules (times after now,
velocities given or estimated, the motion's limits) are ``plate.command_motion``'s.
"""

from .refusals import shorten

PLATE_JOINT = 'plate_z'  # the one joint of ~/plate_command: prismatic, m, up
MAX_POINTS = 1000        # points a trajectory: more would stall the node's ticks (100,000: 2.3 s)
# the core's fields of a plate command (plate.command_motion) as the message spells them
COMMAND_FIELDS = {'times': 'points[].time_from_start (after header.stamp)',
                  'positions': 'points[].positions', 'velocities': 'points[].velocities'}


def read_plate_command(msg, now, offset):
    """A ``trajectory_msgs/JointTrajectory`` as (times, positions, velocities or None) in the
    drop's time (s): point time = stamp + time_from_start, the stamp in simulated time (the
    node's /clock: ``offset`` + the drop's time), stamp 0 = ``now`` (receipt).  Accelerations and
    efforts are ignored.  ValueError naming the field for a wrong joint or a malformed point."""
    names = list(msg.joint_names)
    if names != [PLATE_JOINT]:
        raise ValueError(f'joint_names = {shorten(repr(names))} is invalid: allowed '
                         f'[{PLATE_JOINT!r}] (one prismatic joint, m, up)')
    if len(msg.points) > MAX_POINTS:
        raise ValueError(f'points has {len(msg.points)} points: allowed at most {MAX_POINTS} '
                         'a message (send a longer motion in pieces)')
    stamp = msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9
    base = now if stamp == 0.0 else stamp - offset
    times, positions, velocities = [], [], []
    for i, point in enumerate(msg.points):
        if len(point.positions) != 1:
            raise ValueError(f'points[{i}].positions has {len(point.positions)} values: allowed '
                             f'1 ({PLATE_JOINT})')
        if len(point.velocities) not in (0, 1):
            raise ValueError(f'points[{i}].velocities has {len(point.velocities)} values: '
                             f'allowed 0 (estimated) or 1 ({PLATE_JOINT})')
        times.append(base + point.time_from_start.sec + point.time_from_start.nanosec * 1e-9)
        positions.append(point.positions[0])
        velocities.append(point.velocities[0] if len(point.velocities) else None)
    if not times:
        raise ValueError('points is empty: allowed at least one point')
    given = [v is not None for v in velocities]
    if any(given) and not all(given):
        raise ValueError('points[].velocities are given for some points only: allowed on every '
                         'point or on none (then estimated)')
    return times, positions, (velocities if all(given) else None)

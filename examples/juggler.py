#!/usr/bin/env python3
"""A paddle juggler for contact_sim_node: keeps the ball bouncing to a target apex by moving the
plate through ``~/plate_command`` (trajectory_msgs/JointTrajectory, joint ``plate_z``).

A stroke planner.  As soon as the ball is in flight after a bounce (or at the start of a drop)
the juggler predicts, from the ball's absolute state on ``~/pose`` and ``~/twist`` (vacuum
ballistics), when its lowest point will come down to the plate's rest level p = 0 and how fast
(v-), and sends the whole stroke for that impact at once, a flight ahead, stamped in simulated
time, so transport latency does not matter:

    (t_hit - T, -u T/2, 0) -> (t_hit, 0, u) -> (t_hit + T, u T/2, 0) -> (t_hit + T + 0.2 s, 0, 0)

a constant acceleration u/T up to the plate speed u at the impact, the same deceleration after
it, then back to rest at 0.  The speed u follows the impact law of a restitution e relative to
the plate: the ball leaves at v+ = u + e (u + v-), and v+ = sqrt(2 g H) reaches the target apex H
(``target_apex``, of the lowest point above p = 0): u = (v+ - e v-) / (1 + e), within +-
``max_plate_speed``.  e is learnt from the last stroke (the ball's launch speed back at p = 0,
extrapolated from its first state in flight).  A ball at rest on the plate is thrown: the plate
accelerates up for 0.1 s and brakes at 3 g, faster than gravity, which releases the ball.

    python examples/juggler.py --ros-args -p target_apex:=0.3
    (with contact_sim_node running; -p node:=/contact_sim names the simulator's node, whose
    sphere_radius and gravity the juggler asks for through its parameter service)
"""
import math
import time

import rclpy
from builtin_interfaces.msg import Duration, Time
from geometry_msgs.msg import PoseStamped, TwistStamped
from rcl_interfaces.srv import GetParameters
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy
from rclpy.signals import SignalHandlerOptions
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

from contact_sim.ros.startup import spin_until_signal

JOINT = 'plate_z'
RETURN_TIME = 0.2        # s: back to rest at p = 0 after a stroke
LAUNCH_TIME = 0.1        # s: the throw's upward acceleration phase from rest
REST_GAP = 1e-3          # m: the ball is on the plate within this gap
REST_SPEED = 0.05        # m/s: ... and moving with it within this speed
ASK_AGAIN = 2.0          # s of wall time: a parameter request unanswered this long is sent again


def _ns(stamp):
    return stamp.sec * 1_000_000_000 + stamp.nanosec


def _stamp(seconds):
    ns = int(round(seconds * 1e9))
    return Time(sec=ns // 1_000_000_000, nanosec=ns % 1_000_000_000)


def _point(dt, position, velocity):
    ns = int(round(dt * 1e9))
    return JointTrajectoryPoint(positions=[position], velocities=[velocity],
                                time_from_start=Duration(sec=ns // 1_000_000_000,
                                                         nanosec=ns % 1_000_000_000))


class Juggler(Node):
    """Plans one stroke per flight of the ball and sends it on ``<node>/plate_command``."""

    def __init__(self):
        super().__init__('juggler')
        self.target = self.declare_parameter('target_apex', 0.3).value     # m
        self.u_max = self.declare_parameter('max_plate_speed', 2.0).value   # m/s
        node = self.declare_parameter('node', '/contact_sim').value
        # the simulator's sphere radius R1 (m) and gravity (m/s^2), asked of it (not copied)
        self.radius = self.g = None
        self._ask = self.create_client(GetParameters, f'{node}/get_parameters')
        self._asking, self._asked = None, 0.0   # the request waiting (future) and when (s)
        self._ask_timer = self.create_timer(0.2, self._ask_simulator)
        state_qos = QoSProfile(depth=10, reliability=ReliabilityPolicy.BEST_EFFORT)
        self.create_subscription(PoseStamped, f'{node}/pose', self._on_pose, state_qos)
        self.create_subscription(TwistStamped, f'{node}/twist', self._on_twist, state_qos)
        self.create_subscription(PoseStamped, f'{node}/plate_pose', self._on_plate, state_qos)
        self.command = self.create_publisher(JointTrajectory, f'{node}/plate_command', 10)
        self.restitution = 0.8       # relative to the plate; learnt from each stroke
        self.plate = 0.0             # the plate's height (m) at the last plate pose
        self.heights = {}            # stamp (ns) -> the ball's centre height (m)
        self.velocity = {}           # stamp (ns) -> the ball's upward velocity (m/s)
        self.hit = None              # (t_hit, u, v-) of the stroke sent, in s of /clock time
        self.rest_since = None
        self.last_launch = -math.inf
        self.strokes = 0

    def _ask_simulator(self):
        """Ask the simulator for sphere_radius and gravity: every 0.2 s until it answers, then
        every 2 s (a change of them takes effect at its next ~/reset)."""
        if self._asking is not None and not self._asking.done() \
                and time.monotonic() - self._asked > ASK_AGAIN:
            # unanswered: a server just discovered may drop the reply (its reply writer has
            # not matched this client yet); ask again
            self._ask.remove_pending_request(self._asking)
            self._asking = None
        if self._asking is None and self._ask.service_is_ready():
            self._asking = self._ask.call_async(
                GetParameters.Request(names=['sphere_radius', 'gravity']))
            self._asked = time.monotonic()
        elif self._asking is not None and self._asking.done():
            values = [v.double_value for v in self._asking.result().values]
            self._asking = None
            if len(values) == 2 and values[0] > 0.0 and values[1] > 0.0 \
                    and values != [self.radius, self.g]:
                first = self.g is None
                self.radius, self.g = values
                self.get_logger().info(f'simulator: sphere_radius {self.radius:g} m, gravity '
                                       f'{self.g:g} m/s^2')
                if first:
                    self._ask_timer.cancel()
                    self._ask_timer = self.create_timer(2.0, self._ask_simulator)

    def _on_plate(self, msg):
        self.plate = msg.pose.position.z

    def _on_pose(self, msg):
        self._pair(_ns(msg.header.stamp), self.heights, msg.pose.position.z)

    def _on_twist(self, msg):
        self._pair(_ns(msg.header.stamp), self.velocity, msg.twist.linear.z)

    def _pair(self, ns, store, value):
        """Keep a pose or a twist until its partner of the same stamp arrives."""
        store[ns] = value
        if ns in self.heights and ns in self.velocity and self.radius is not None:
            height, v = self.heights.pop(ns), self.velocity.pop(ns)
            self._on_state(ns * 1e-9, height - self.radius, v)
        for old in (self.heights, self.velocity):
            while len(old) > 100:
                old.pop(next(iter(old)))

    def _on_state(self, t, y, v):
        """The ball's lowest point at height y (m) moving up at v (m/s) at time t (s)."""
        if self.g is None:
            return                   # the simulator has not told its gravity yet
        if self.hit is not None and t < self.hit[0] + 0.02:
            return                   # the stroke sent is still ahead
        gap = y - self.plate
        if gap <= REST_GAP:
            self._maybe_launch(t, v)
            return
        self.rest_since = None
        if self.hit is not None:     # first state in flight after the stroke: learn e
            _, u, v_minus = self.hit
            launch = math.sqrt(max(v * v + 2.0 * self.g * y, 0.0)) if y > 0.0 else v
            if v > 0.0 and u + v_minus > 0.0:
                e = (launch - u) / (u + v_minus)
                if 0.2 <= e <= 1.0:
                    self.restitution = e
            self.hit = None
        self._plan(t, y, v)

    def _plan(self, t, y, v):
        """The stroke for the ball's next arrival at p = 0 (lowest point at height y moving up
        at v at time t)."""
        if y <= 0.0:
            return
        v_minus = math.sqrt(v * v + 2.0 * self.g * y)
        t_hit = t + (v + v_minus) / self.g
        e = self.restitution
        v_plus = math.sqrt(2.0 * self.g * self.target)
        u = max(-self.u_max, min(self.u_max, (v_plus - e * v_minus) / (1.0 + e)))
        ramp = max(abs(u) / (3.0 * self.g), 0.01)     # s: the stroke's half length T
        start = t_hit - ramp
        half = 0.5 * u * ramp
        msg = JointTrajectory(joint_names=[JOINT])
        msg.header.stamp = _stamp(start)
        msg.points = [_point(0.0, -half, 0.0), _point(ramp, 0.0, u),
                      _point(2.0 * ramp, half, 0.0), _point(2.0 * ramp + RETURN_TIME, 0.0, 0.0)]
        self.command.publish(msg)
        self.hit = (t_hit, u, v_minus)
        self.strokes += 1

    def _maybe_launch(self, t, v):
        """The ball rests on the plate: throw it (once it has rested 0.3 s)."""
        if abs(v) > REST_SPEED or t - self.last_launch < 2.0:
            self.rest_since = None
            return
        if self.rest_since is None:
            self.rest_since = t
            return
        if t - self.rest_since < 0.3:
            return
        u = math.sqrt(2.0 * self.g * self.target)
        brake = u / (3.0 * self.g)
        up = 0.5 * u * LAUNCH_TIME
        msg = JointTrajectory(joint_names=[JOINT])      # stamp 0: from receipt
        msg.points = [_point(LAUNCH_TIME, up, u), _point(LAUNCH_TIME + brake,
                                                         up + 0.5 * u * brake, 0.0),
                      _point(LAUNCH_TIME + brake + RETURN_TIME, 0.0, 0.0)]
        self.command.publish(msg)
        self.last_launch, self.rest_since, self.hit = t, None, None
        self.get_logger().info(f'ball at rest: thrown at {u:.3g} m/s')


def main(args=None):
    # Ctrl-C and SIGTERM only set a flag, checked between executor turns (spin_until_signal):
    # with rclpy's own handlers, a KeyboardInterrupt raised while rclpy converts a message it
    # takes surfaces as "RuntimeError: Unable to convert call argument" (3 stops in 40, measured)
    rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO)
    node = None
    try:
        node = Juggler()
        spin_until_signal(node)
    except (KeyboardInterrupt, ExternalShutdownException):   # Ctrl-C before the spin began
        pass
    finally:
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()
    return 0


if __name__ == '__main__':
    import sys
    sys.exit(main())

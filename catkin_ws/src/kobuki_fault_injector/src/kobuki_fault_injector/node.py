"""``rosrun kobuki_fault_injector fault_injector __ns:=/faulty``: the fault injector node.

Sits between the robot's consumers and its base driver, all names relative to the namespace::

    cmd_vel (Twist)          -> [fault] -> mobile_base/commands/velocity (Twist)
    mobile_base/odom (Odometry) -> [fault] -> odom (Odometry)

Service ``fault_injector`` (``kobuki_fault_injector/FaultInjector``): ``left_actuator``,
``right_actuator``, ``both_actuators``, ``odometry`` or ``cancel``; see
:mod:`kobuki_fault_injector.faults` for what each does. The active fault (``none`` without one)
is published latched on ``fault_injector/status`` (std_msgs/String) and, once a second and on
every change, on ``/diagnostics`` (level WARN while a fault is active, OK otherwise). A velocity
command with a non-finite component is replaced by a stop (with a rate-limited warning).
After a roscore restart the node registers its topics and service again
(:mod:`rason.ros.master_watch`).
"""

from __future__ import annotations

import dataclasses
import math
import sys
import threading

import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from std_msgs.msg import String

from kobuki_fault_injector.faults import VALID_REQUESTS, FaultState, Velocity
from kobuki_fault_injector.srv import (
    FaultInjector,
    FaultInjectorRequest,
    FaultInjectorResponse,
)
from rason.ros.guard import guarded
from rason.ros.master_watch import watch_master
from rason.ros.params import exit_on_help, load_or_exit

USAGE = "rosrun kobuki_fault_injector fault_injector [__ns:=/robot]"
SUMMARY = f"""Breaks the robot's wheels or encoder on request, between its consumers and its base:
  cmd_vel -> [fault] -> mobile_base/commands/velocity;  mobile_base/odom -> [fault] -> odom
service fault_injector (kobuki_fault_injector/FaultInjector): {", ".join(VALID_REQUESTS)}
status: fault_injector/status (latched) and /diagnostics"""


@dataclasses.dataclass(frozen=True)
class FaultInjectorParams:
    """The node's private parameters: none (everything is relative to its namespace)."""


def twist_to_velocity(msg: Twist) -> Velocity:
    return Velocity(msg.linear.x, msg.linear.y, msg.linear.z,
                    msg.angular.x, msg.angular.y, msg.angular.z)


def velocity_to_twist(vel: Velocity) -> Twist:
    msg = Twist()
    msg.linear.x, msg.linear.y, msg.linear.z = vel.linear_x, vel.linear_y, vel.linear_z
    msg.angular.x, msg.angular.y, msg.angular.z = vel.angular_x, vel.angular_y, vel.angular_z
    return msg


class FaultInjectorNode:
    """Topics, service and diagnostics around a :class:`FaultState`."""

    def __init__(self) -> None:
        self.lock = threading.Lock()
        self.state = FaultState()
        self.diagnostic_name = f"{rospy.get_namespace().strip('/') or 'robot'}: fault_injector"

        # -- topics (relative names: run the node inside the robot's namespace) ------------
        self.cmd_out = rospy.Publisher("mobile_base/commands/velocity", Twist, queue_size=10)
        self.odom_out = rospy.Publisher("odom", Odometry, queue_size=50)
        self.status_pub = rospy.Publisher("fault_injector/status", String, queue_size=1,
                                          latch=True)
        self.diagnostics_pub = rospy.Publisher("/diagnostics", DiagnosticArray, queue_size=10)
        # Guarded callbacks: a bad message costs a rate-limited warning, never the node.
        rospy.Subscriber("cmd_vel", Twist, guarded("fault_injector cmd_vel")(self.on_cmd_vel),
                         queue_size=10)
        rospy.Subscriber("mobile_base/odom", Odometry,
                         guarded("fault_injector odom")(self.on_odom), queue_size=50)
        rospy.Service("fault_injector", FaultInjector, self.on_request)

        self.publish_status()
        rospy.Timer(rospy.Duration(1.0),
                    guarded("fault_injector diagnostics")(lambda _event: self.publish_diagnostics()))

    # -- callbacks --------------------------------------------------------------------------
    def on_cmd_vel(self, msg: Twist) -> None:
        velocity = twist_to_velocity(msg)
        if not all(math.isfinite(v) for v in dataclasses.astuple(velocity)):
            self.cmd_out.publish(Twist())          # a corrupt command stops the base
            raise ValueError(f"non-finite velocity command {dataclasses.astuple(velocity)}: "
                             "sent a stop instead")
        with self.lock:
            out = self.state.command(velocity)
        self.cmd_out.publish(velocity_to_twist(out))

    def on_odom(self, msg: Odometry) -> None:
        with self.lock:
            out = self.state.odom(msg)
        if out is not msg:
            # A frozen encoder still reports, with the pose and twist it had: keep the live
            # stamp so consumers see a live topic whose values no longer change.
            frozen = Odometry()
            frozen.header.frame_id = out.header.frame_id
            frozen.header.stamp = msg.header.stamp
            frozen.child_frame_id = out.child_frame_id
            frozen.pose = out.pose
            frozen.twist = out.twist
            out = frozen
        self.odom_out.publish(out)

    def on_request(self, req: FaultInjectorRequest) -> FaultInjectorResponse:
        with self.lock:
            before = self.state.active
            message = self.state.request(req.fault)
            changed = self.state.active != before
        rospy.loginfo("fault_injector: request %r: %s", req.fault, message)
        if changed:
            self.publish_status()
        return FaultInjectorResponse(return_message=message)

    # -- status -----------------------------------------------------------------------------
    def publish_status(self) -> None:
        self.status_pub.publish(String(data=self.state.status))
        self.publish_diagnostics()

    def publish_diagnostics(self) -> None:
        active = self.state.active
        status = DiagnosticStatus(
            level=DiagnosticStatus.WARN if active else DiagnosticStatus.OK,
            name=self.diagnostic_name,
            message=f"fault injected: {active}" if active else "no fault injected",
            hardware_id="kobuki",
            values=[KeyValue(key="fault", value=self.state.status),
                    KeyValue(key="valid_faults", value=", ".join(VALID_REQUESTS))])
        array = DiagnosticArray(status=[status])
        array.header.stamp = rospy.Time.now()
        self.diagnostics_pub.publish(array)


def main() -> int:
    exit_on_help(sys.argv, FaultInjectorParams, USAGE, SUMMARY)
    rospy.init_node("fault_injector")
    load_or_exit(FaultInjectorParams, "fault_injector")
    FaultInjectorNode()
    watch_master()              # a restarted roscore gets the topics and the service again
    rospy.loginfo("fault_injector ready in namespace %s", rospy.get_namespace())
    rospy.spin()
    return 0

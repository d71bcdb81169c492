"""``rosrun kobuki_fault_injector fault_injector __ns:=/faulty``: the fault injector node.

Sits between the robot's consumers and its base driver, all names relative to the namespace::

    cmd_vel (Twist)          -> [fault] -> mobile_base/commands/velocity (Twist)
    mobile_base/odom (Odometry) -> [fault] -> odom (Odometry)

The odometry names are parameters (``~odom_input``, ``~odom_output``; ``--help`` lists them):
the defaults are this simulator's default profile (kobuki_node's own odometry name). Under the
stock driver names (turtlebot_bringup remaps the driver's odometry to ``odom``) run it with
``_odom_input:=odom _odom_output:=fault_injector/odom`` and point the odometry readers at
``fault_injector/odom`` (``odom:=fault_injector/odom``). Parameters, not remaps: rospy applies
remaps one after the other, so ``mobile_base/odom:=odom odom:=fault_injector/odom`` would
subscribe the node to its own output. On a robot with turtlebot's velocity mux add
``mobile_base/commands/velocity:=cmd_vel_mux/input/navi`` (docs/drivers.md). When the odometry
input stays silent for 3 s while another Odometry topic of the namespace flows, the node warns,
naming both (:mod:`rosnode_kit.input_watch`).

Service ``fault_injector`` (``kobuki_fault_injector/FaultInjector``): ``left_actuator``,
``right_actuator``, ``both_actuators``, ``odometry`` or ``cancel``; see
:mod:`kobuki_fault_injector.faults` for what each does. The active fault (``none`` without one)
is published latched on ``fault_injector/status`` (std_msgs/String) and, once a second and on
every change, on ``/diagnostics`` (level WARN while a fault is active, OK otherwise). A velocity
command with a non-finite component is replaced by a stop (with a rate-limited warning).
After a roscore restart the node registers its topics and service again
(:mod:`rosnode_kit.master_watch`).
"""

from __future__ import annotations

import dataclasses
import math
import sys
import threading
from dataclasses import dataclass

import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from std_msgs.msg import String

from kobuki_fault_injector.faults import (
    MAX_REQUEST_NAME,
    VALID_REQUESTS,
    FaultState,
    Velocity,
)
from kobuki_fault_injector.srv import (
    FaultInjector,
    FaultInjectorRequest,
    FaultInjectorResponse,
)
from rosnode_kit.badinput import shorten
from rosnode_kit.guard import guarded
from rosnode_kit.input_watch import watch_input
from rosnode_kit.master_watch import watch_master
from rosnode_kit.params import ParamError, exit_on_help, load_or_exit, param
from rosnode_kit.signals import init_node

#: How to wire the odometry under the stock driver names (the miswiring warning ends with it).
STOCK_HINT = ("Under the stock driver names (the driver publishes odom) run the injector with "
              "_odom_input:=odom _odom_output:=fault_injector/odom and its readers with "
              "odom:=fault_injector/odom (docs/drivers.md).")


def twist_to_velocity(msg: Twist) -> Velocity:
    return Velocity(msg.linear.x, msg.linear.y, msg.linear.z,
                    msg.angular.x, msg.angular.y, msg.angular.z)


def velocity_to_twist(vel: Velocity) -> Twist:
    msg = Twist()
    msg.linear.x, msg.linear.y, msg.linear.z = vel.linear_x, vel.linear_y, vel.linear_z
    msg.angular.x, msg.angular.y, msg.angular.z = vel.angular_x, vel.angular_y, vel.angular_z
    return msg


@dataclass(frozen=True)
class InjectorParams:
    """The fault injector's private parameters."""

    odom_input: str = param("mobile_base/odom", "the base driver's odometry, read (stock driver "
                            "names: odom)")
    odom_output: str = param("odom", "the odometry as the fault leaves it, for the decomposer "
                             "and the synthesizer (stock driver names: fault_injector/odom)")

    def __post_init__(self) -> None:
        if rospy.names.canonicalize_name(self.odom_input) == \
                rospy.names.canonicalize_name(self.odom_output):
            raise ParamError(f"~odom_input and ~odom_output are both {self.odom_input!r}: the "
                             "node would read its own output")


class FaultInjectorNode:
    """Topics, service and diagnostics around a :class:`FaultState`."""

    def __init__(self, params: InjectorParams | None = None) -> None:
        params = params or InjectorParams()
        self.lock = threading.Lock()
        self.state = FaultState()
        self.diagnostic_name = f"{rospy.get_namespace().strip('/') or 'robot'}: fault_injector"

        # -- topics (relative names: run the node inside the robot's namespace) ------------
        self.cmd_out = rospy.Publisher("mobile_base/commands/velocity", Twist, queue_size=10)
        self.odom_out = rospy.Publisher(params.odom_output, Odometry, queue_size=50)
        self.status_pub = rospy.Publisher("fault_injector/status", String, queue_size=1,
                                          latch=True)
        self.diagnostics_pub = rospy.Publisher("/diagnostics", DiagnosticArray, queue_size=10)
        # Guarded callbacks: a bad message costs a rate-limited warning, never the node.
        rospy.Subscriber("cmd_vel", Twist, guarded("fault_injector cmd_vel")(self.on_cmd_vel),
                         queue_size=10)
        self.odom_watch = watch_input(params.odom_input, Odometry, hint=STOCK_HINT)
        rospy.Subscriber(params.odom_input, Odometry,
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
        self.odom_watch.heard(rospy.get_time())
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
        rospy.loginfo("fault_injector: request %s: %s", shorten(repr(req.fault), MAX_REQUEST_NAME),
                      message)
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


def main(argv: list[str] | None = None) -> int:
    """Entry point of ``rosrun kobuki_fault_injector fault_injector``."""
    argv = argv if argv is not None else sys.argv
    exit_on_help(argv, InjectorParams,
                 "rosrun kobuki_fault_injector fault_injector __ns:=/ROBOT [_name:=value ...]",
                 __doc__.split("\n")[0].split(": ", 1)[-1])
    init_node("fault_injector", argv=argv)
    FaultInjectorNode(load_or_exit(InjectorParams, "fault_injector"))
    watch_master()              # a restarted roscore gets the topics and the service again
    rospy.loginfo("fault_injector ready in namespace %s", rospy.get_namespace())
    rospy.spin()
    return 0

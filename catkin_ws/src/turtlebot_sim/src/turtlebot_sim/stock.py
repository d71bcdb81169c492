"""The stock-driver profile's messages: what kobuki_node (turtlebot_bringup's minimal launch) and
a Kinect through openni/freenect + rgbd_launch publish, built from the simulation's numbers.

No ROS node here (see :mod:`turtlebot_sim.node`); docs/drivers.md lists every topic beside the
real driver it mirrors.
"""

from __future__ import annotations

import math

import numpy as np
from geometry_msgs.msg import TransformStamped
from kobuki_msgs.msg import BumperEvent, CliffEvent, SensorState, WheelDropEvent
from sensor_msgs.msg import CameraInfo, Image, JointState
from tf2_msgs.msg import TFMessage

from turtlebot_sim import kobuki, msgs
from turtlebot_sim.base_events import CLIFF_BITS, WHEEL_DROP_BITS, WHEELS, BumperChange, Side
from turtlebot_sim.world import WheelState

#: kobuki_node's odometry covariances (odometry.cpp, gyro heading as by default): x, y 0.1,
#: yaw 0.05, z/roll/pitch 1e10 ("unused"); the twist covariance is left at zero.
POSE_COVARIANCE = [0.0] * 36
POSE_COVARIANCE[0] = POSE_COVARIANCE[7] = 0.1
POSE_COVARIANCE[14] = POSE_COVARIANCE[21] = POSE_COVARIANCE[28] = 1e10
POSE_COVARIANCE[35] = 0.05
TWIST_COVARIANCE = [0.0] * 36

ODOM_FRAME = "odom"
BASE_FRAME = "base_footprint"
WHEEL_JOINTS = ("wheel_left_joint", "wheel_right_joint")
#: openni/freenect with depth registration: RGB and registered depth in the RGB optical frame.
OPTICAL_FRAME = "camera_rgb_optical_frame"
#: The Kinect's RGB focal length at 640 px wide (openni's default calibration), and its rate.
KINECT_FX_VGA = 525.0
KINECT_RATE = 30.0
#: turtlebot's 3D-sensor settings stamp the depth image this much before the RGB image (s).
DEPTH_TIME_OFFSET = -0.055
#: The battery kobuki_node reports in 0.1 V (a charged 4S pack: 16.5 V).
BATTERY_DV = 165
#: Cliff sensor readings over a floor and over a cliff (ADC counts).
FLOOR_BOTTOM = 1500
CLIFF_BOTTOM = 20
#: Ticks the uint16 encoder counters wrap at.
ENCODER_WRAP = 1 << 16


def kinect_hfov_deg(width: int) -> float:
    """Horizontal FOV whose focal length is openni's 525 px at VGA, scaled to ``width`` pixels."""
    fx = KINECT_FX_VGA * width / 640.0
    return math.degrees(2.0 * math.atan(width / 2.0 / fx))


def odometry(t: float, x: float, y: float, yaw: float, v: float, w: float):
    """kobuki_node's nav_msgs/Odometry (after turtlebot_bringup's remap to ``odom``)."""
    return msgs.odometry(t, ODOM_FRAME, BASE_FRAME, x, y, yaw, v, w,
                         pose_covariance=POSE_COVARIANCE, twist_covariance=TWIST_COVARIANCE)


def transform(t: float, x: float, y: float, yaw: float) -> TransformStamped:
    """kobuki_node's ``odom`` -> ``base_footprint`` transform (its ``publish_tf``)."""
    tf = TransformStamped()
    tf.header.stamp = msgs.stamp(t)
    tf.header.frame_id = ODOM_FRAME
    tf.child_frame_id = BASE_FRAME
    tf.transform.translation.x = x
    tf.transform.translation.y = y
    tf.transform.rotation = msgs.yaw_quaternion(yaw)
    return tf


def tf_message(transforms: list[TransformStamped]) -> TFMessage:
    return TFMessage(transforms=transforms)


def joint_states(t: float, wheels: WheelState) -> JointState:
    """kobuki_node's wheel joint states (effort zero, as it sends them)."""
    msg = JointState(name=list(WHEEL_JOINTS),
                     position=[wheels.left_angle, wheels.right_angle],
                     velocity=[wheels.left_rate, wheels.right_rate], effort=[0.0, 0.0])
    msg.header.stamp = msgs.stamp(t)
    return msg


def encoder(angle: float) -> int:
    """A wheel's uint16 encoder counter for an unwrapped joint angle (rad)."""
    return kobuki.WheelOdometry.ticks(angle) % ENCODER_WRAP


def pwm(rate: float) -> int:
    """A wheel's drive in percent of the maximum (int8), from its rate (rad/s)."""
    full = kobuki.MAX_V / kobuki.WHEEL_RADIUS
    return int(max(-100, min(100, round(100.0 * rate / full))))


def sensor_state(t: float, wheels: WheelState, bumper_bits: int, cliffs: set[Side],
                 drops: set[Side]) -> SensorState:
    """kobuki_node's ``mobile_base/sensors/core``: encoders, bumper, cliff and wheel drop bits
    (the cliff sensors over a cliff read ``CLIFF_BOTTOM``); a charged battery, undocked."""
    bottom = [CLIFF_BOTTOM if side in cliffs else FLOOR_BOTTOM
              for side in (Side.RIGHT, Side.CENTER, Side.LEFT)]
    msg = SensorState(
        time_stamp=int(t * 1000.0) % ENCODER_WRAP, bumper=bumper_bits,
        wheel_drop=sum(WHEEL_DROP_BITS[s] for s in drops),
        cliff=sum(CLIFF_BITS[s] for s in cliffs),
        left_encoder=encoder(wheels.left_angle), right_encoder=encoder(wheels.right_angle),
        left_pwm=pwm(wheels.left_rate), right_pwm=pwm(wheels.right_rate), buttons=0,
        charger=SensorState.DISCHARGING, battery=BATTERY_DV, bottom=bottom,
        current=[0, 0], over_current=0, digital_input=0, analog_input=[0, 0, 0, 0])
    msg.header.stamp = msgs.stamp(t)
    return msg


def bumper_event(change: BumperChange) -> BumperEvent:
    return BumperEvent(bumper=int(change.bumper), state=int(change.state))


def cliff_event(side: Side, on: bool) -> CliffEvent:
    return CliffEvent(sensor=int(side), state=CliffEvent.CLIFF if on else CliffEvent.FLOOR,
                      bottom=CLIFF_BOTTOM if on else FLOOR_BOTTOM)


def wheel_drop_event(side: Side, on: bool) -> WheelDropEvent:
    return WheelDropEvent(wheel=WHEELS[side],
                          state=WheelDropEvent.DROPPED if on else WheelDropEvent.RAISED)


def bayer_grbg(rgb: np.ndarray) -> np.ndarray:
    """HxWx3 RGB -> HxW Bayer GRBG mosaic (rows G R G R ..., B G B G ...), as the Kinect sends."""
    h, w, _ = rgb.shape
    out = np.empty((h, w), dtype=np.uint8)
    out[0::2, 0::2] = rgb[0::2, 0::2, 1]
    out[0::2, 1::2] = rgb[0::2, 1::2, 0]
    out[1::2, 0::2] = rgb[1::2, 0::2, 2]
    out[1::2, 1::2] = rgb[1::2, 1::2, 1]
    return out


def bayer_image(t: float, mosaic: np.ndarray) -> Image:
    """``camera/rgb/image_raw``: encoding bayer_grbg8."""
    h, w = mosaic.shape
    msg = Image(height=h, width=w, encoding="bayer_grbg8", is_bigendian=0, step=w,
                data=np.ascontiguousarray(mosaic).tobytes())
    msg.header.stamp = msgs.stamp(t)
    msg.header.frame_id = OPTICAL_FRAME
    return msg


def depth_mm(z: np.ndarray) -> np.ndarray:
    """Depth along the optical axis (m, NaN = none) -> uint16 millimetres, 0 = none."""
    mm = np.nan_to_num(z, nan=0.0) * 1000.0
    return np.clip(np.round(mm), 0, 65535).astype(np.uint16)


def depth_image(t: float, mm: np.ndarray) -> Image:
    """``camera/depth_registered/image_raw``: encoding 16UC1, millimetres, little-endian."""
    h, w = mm.shape
    msg = Image(height=h, width=w, encoding="16UC1", is_bigendian=0, step=2 * w,
                data=np.ascontiguousarray(mm, dtype="<u2").tobytes())
    msg.header.stamp = msgs.stamp(t)
    msg.header.frame_id = OPTICAL_FRAME
    return msg


def camera_info(t: float, width: int, height: int, fx: float, fy: float, cx: float,
                cy: float) -> CameraInfo:
    """A distortion-free pinhole CameraInfo (plumb_bob with zero coefficients, as openni's
    default calibration)."""
    msg = CameraInfo(height=height, width=width, distortion_model="plumb_bob",
                     D=[0.0] * 5, K=[fx, 0.0, cx, 0.0, fy, cy, 0.0, 0.0, 1.0],
                     R=[1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
                     P=[fx, 0.0, cx, 0.0, 0.0, fy, cy, 0.0, 0.0, 0.0, 1.0, 0.0])
    msg.header.stamp = msgs.stamp(t)
    msg.header.frame_id = OPTICAL_FRAME
    return msg

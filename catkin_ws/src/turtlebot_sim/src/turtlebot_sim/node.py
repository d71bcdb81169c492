"""``rosrun turtlebot_sim sim``: the simulated TurtleBot 2 robots speaking kobuki_node's topics.

Private parameters: :class:`SimParams` (``rosrun turtlebot_sim sim --help`` prints them).

Topics of the default profile (``_drivers:=sim``; ``<r>`` = each robot's name, relative to the
node's namespace, so ``__ns:=/test1`` gives ``/test1/faulty/...``; all stamps are sim time;
/clock every physics step):
    /clock                                   rosgraph_msgs/Clock        (published)
    /<r>/mobile_base/commands/velocity       geometry_msgs/Twist        (subscribed)
    /<r>/mobile_base/odom                    nav_msgs/Odometry odom -> base_footprint, wheels
    /<r>/mobile_base/events/bumper           kobuki_msgs/BumperEvent    (on contact changes)
    /<r>/mobile_base/events/cliff            kobuki_msgs/CliffEvent     (only with base_events)
    /<r>/mobile_base/events/wheel_drop       kobuki_msgs/WheelDropEvent (only with base_events)
    /<r>/ground_truth/odom                   nav_msgs/Odometry world -> <r>/base_footprint
    /<r>/camera/rgb/image_raw                sensor_msgs/Image rgb8      (robots with a Kinect)
    /<r>/camera/depth_registered/points      sensor_msgs/PointCloud2 x y z rgb, organised

``_drivers:=stock`` publishes the real drivers' topics on wall time instead, without /clock:
docs/drivers.md has the table.

Under the default profile the node does not set ``/use_sim_time``: set it before starting the
other nodes. After a roscore restart it registers its topics again (:mod:`rosnode_kit.master_watch`).
"""

from __future__ import annotations

import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from enum import StrEnum
from pathlib import Path

import rospkg
import rospy
import yaml
from geometry_msgs.msg import Twist
from kobuki_msgs.msg import BumperEvent, ButtonEvent, CliffEvent, SensorState, WheelDropEvent
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import CameraInfo, Image, JointState, PointCloud2
from tf2_msgs.msg import TFMessage

from rosnode_kit.master_watch import watch_master
from rosnode_kit.params import ParamError, exit_on_help, exit_rejected, load_or_exit, param
from rosnode_kit.signals import init_node
from turtlebot_sim import config as worldcfg
from turtlebot_sim import msgs, stock
from turtlebot_sim.base_events import BaseEventScript, BumperSwitches, ScriptedEvent, Side
from turtlebot_sim.render import Frame, RenderPool
from turtlebot_sim.stats import Stats
from turtlebot_sim.world import World

#: The world used without ~world: the case study's, found through the ROS package path
DEFAULT_WORLD = ("rason_diagnosis", "worlds/case_study.yaml")

#: Wall seconds the loop may lag behind the real-time factor before it stops trying to catch up.
MAX_LAG = 0.25


class Drivers(StrEnum):
    """Which drivers' topics the simulation speaks (docs/drivers.md)."""

    SIM = "sim"        # this simulator's own names, sim time and /clock (the default)
    STOCK = "stock"    # kobuki_node + turtlebot_bringup and openni + rgbd_launch, wall time


class RobotIO:
    """One robot's publishers, subscriber and command bookkeeping (both profiles).

    ``stamp_of`` turns sim seconds into the stamp's seconds (the identity on sim time; the wall
    clock's seconds under the stock profile).
    """

    def __init__(self, world: World, name: str, has_camera: bool, timeout: float,
                 stamp_of: Callable[[float], float], cliff_and_drop: bool = False):
        self.world = world
        self.name = name
        self.timeout = timeout
        self.stamp_of = stamp_of
        self.last_cmd = -1.0e9       # sim time of the last velocity command
        self.has_camera = has_camera
        self.truth = rospy.Publisher(f"{name}/ground_truth/odom", Odometry, queue_size=10)
        self.bumpers = BumperSwitches()
        self.bumper = rospy.Publisher(f"{name}/mobile_base/events/bumper", BumperEvent,
                                      queue_size=100)
        self.cmd = rospy.Subscriber(f"{name}/mobile_base/commands/velocity", Twist,
                                    self.on_cmd_vel, queue_size=10)
        self.cliffs: set[Side] = set()
        self.drops: set[Side] = set()
        self.cliff = self.wheel_drop = None
        if cliff_and_drop:      # stock: always, as kobuki_node; sim: for a world's base_events
            self.cliff = rospy.Publisher(f"{name}/mobile_base/events/cliff", CliffEvent,
                                         queue_size=100)
            self.wheel_drop = rospy.Publisher(f"{name}/mobile_base/events/wheel_drop",
                                              WheelDropEvent, queue_size=100)

    def raise_event(self, event: ScriptedEvent) -> None:
        """A scripted cliff or wheel drop (the world file's ``base_events``) begins or ends."""
        assert self.cliff is not None and self.wheel_drop is not None
        held = self.cliffs if event.kind == "cliff" else self.drops
        (held.add if event.on else held.discard)(event.side)
        if event.kind == "cliff":
            self.cliff.publish(stock.cliff_event(event.side, event.on))
        else:
            self.wheel_drop.publish(stock.wheel_drop_event(event.side, event.on))
        rospy.loginfo("turtlebot_sim: %s %s %s %s", self.name, event.kind, event.side.name,
                      "raised" if event.on else "cleared")

    def on_cmd_vel(self, msg: Twist) -> None:
        """A velocity command: applied at once, valid for ``timeout`` sim seconds."""
        self.world.set_cmd_vel(self.name, msg.linear.x, msg.angular.z)
        self.last_cmd = self.world.time

    def check_timeout(self) -> None:
        """Stop the robot (like kobuki_node) when commands stopped coming."""
        if self.last_cmd > -1.0e9 and self.world.time - self.last_cmd > self.timeout:
            self.world.set_cmd_vel(self.name, 0.0, 0.0)
            self.last_cmd = -1.0e9

    def check_bumpers(self) -> None:
        """A BumperEvent for each switch that a contact pressed or released since the last
        check, as kobuki_node sends them (the robot itself does not stop: the consumers do)."""
        for change in self.bumpers.update(self.world.contact_bearings(self.name)):
            self.bumper.publish(stock.bumper_event(change))
            rospy.loginfo("turtlebot_sim: %s bumper %s %s", self.name, change.bumper.name,
                          change.state.name)

    def publish_odometry(self) -> None:
        t = self.stamp_of(self.world.time)
        self.publish_base(t)
        gx, gy, gyaw = self.world.pose(self.name)
        gv, gw = self.world.velocity(self.name)
        self.truth.publish(msgs.odometry(t, "world", f"{self.name}/base_footprint",
                                         gx, gy, gyaw, gv, gw))

    def publish_base(self, t: float) -> None:
        """The base driver's periodic topics, stamped ``t``."""
        raise NotImplementedError

    def publish_frame(self, frame: Frame) -> None:
        """The topics of one Kinect frame."""
        raise NotImplementedError


class SimRobotIO(RobotIO):
    """The default profile: ``mobile_base/odom``, rgb8 image + cloud sharing one stamp."""

    def __init__(self, world: World, name: str, has_camera: bool, timeout: float,
                 stamp_of: Callable[[float], float], cliff_and_drop: bool = False):
        super().__init__(world, name, has_camera, timeout, stamp_of, cliff_and_drop)
        self.odom = rospy.Publisher(f"{name}/mobile_base/odom", Odometry, queue_size=10)
        self.optical_frame = f"{name}/camera_rgb_optical_frame"
        if has_camera:
            self.image = rospy.Publisher(f"{name}/camera/rgb/image_raw", Image, queue_size=2)
            self.points = rospy.Publisher(f"{name}/camera/depth_registered/points",
                                          PointCloud2, queue_size=2)

    def publish_base(self, t: float) -> None:
        x, y, yaw, v, w = self.world.odometry(self.name)
        self.odom.publish(msgs.odometry(t, "odom", "base_footprint", x, y, yaw, v, w))

    def publish_frame(self, frame: Frame) -> None:
        """Image and cloud of one Kinect frame, with the same stamp and frame id."""
        t = self.stamp_of(frame.stamp)
        self.image.publish(msgs.image(t, self.optical_frame, frame.rgb))
        self.points.publish(msgs.cloud(t, self.optical_frame, frame.cloud))


class StockRobotIO(RobotIO):
    """The stock-driver profile: kobuki_node under turtlebot_bringup's minimal launch and a
    Kinect through openni + rgbd_launch (docs/drivers.md has the table)."""

    def __init__(self, world: World, name: str, has_camera: bool, timeout: float,
                 stamp_of: Callable[[float], float], tf: rospy.Publisher):
        super().__init__(world, name, has_camera, timeout, stamp_of, cliff_and_drop=True)
        self.tf = tf
        self.odom = rospy.Publisher(f"{name}/odom", Odometry, queue_size=10)
        self.joints = rospy.Publisher(f"{name}/joint_states", JointState, queue_size=10)
        self.core = rospy.Publisher(f"{name}/mobile_base/sensors/core", SensorState,
                                    queue_size=10)
        # Advertised as kobuki_node does; nobody presses the simulated buttons.
        self.button = rospy.Publisher(f"{name}/mobile_base/events/button", ButtonEvent,
                                      queue_size=100)
        if has_camera:
            intr = world.intrinsics
            self.info = (intr.width, intr.height, intr.fx, intr.fy, intr.cx, intr.cy)
            self.image = rospy.Publisher(f"{name}/camera/rgb/image_raw", Image, queue_size=2)
            self.image_info = rospy.Publisher(f"{name}/camera/rgb/camera_info", CameraInfo,
                                              queue_size=2)
            self.depth = rospy.Publisher(f"{name}/camera/depth_registered/image_raw", Image,
                                         queue_size=2)
            self.depth_info = rospy.Publisher(f"{name}/camera/depth_registered/camera_info",
                                              CameraInfo, queue_size=2)

    def publish_base(self, t: float) -> None:
        x, y, yaw, v, w = self.world.odometry(self.name)
        self.tf.publish(stock.tf_message([stock.transform(t, x, y, yaw)]))
        self.odom.publish(stock.odometry(t, x, y, yaw, v, w))
        wheels = self.world.wheels(self.name)
        self.joints.publish(stock.joint_states(t, wheels))
        if self.core.get_num_connections() > 0:     # kobuki_node skips it without subscribers
            self.core.publish(stock.sensor_state(t, wheels, self.bumpers.bits, self.cliffs,
                                                 self.drops))

    def publish_frame(self, frame: Frame) -> None:
        """Bayer image and registered depth of one frame, each with its camera_info; the depth
        stamped ``DEPTH_TIME_OFFSET`` before the image, as turtlebot's Kinect settings do."""
        t = self.stamp_of(frame.stamp)
        t_depth = t + stock.DEPTH_TIME_OFFSET
        if self.depth.get_num_connections() or self.depth_info.get_num_connections():
            self.depth.publish(stock.depth_image(t_depth, stock.depth_mm(frame.cloud[:, :, 2])))
            self.depth_info.publish(stock.camera_info(t_depth, *self.info))
        if self.image.get_num_connections() or self.image_info.get_num_connections():
            self.image.publish(stock.bayer_image(t, stock.bayer_grbg(frame.rgb)))
            self.image_info.publish(stock.camera_info(t, *self.info))


@dataclass(frozen=True)
class SimParams:
    """The simulator node's private parameters."""

    world: str = param("", "path of the world file (YAML, see turtlebot_sim.config); empty: "
                       f"the case study's, $(rospack find {DEFAULT_WORLD[0]})/{DEFAULT_WORLD[1]}")
    drivers: str = param(Drivers.SIM.value, "'sim': this simulator's topics on sim time with "
                         "/clock; 'stock': kobuki_node + turtlebot_bringup and openni + "
                         "rgbd_launch topics on wall time, no /clock (docs/drivers.md)")
    real_time_factor: float = param(1.0, "sim seconds per wall second; 0 = as fast as possible "
                                    "(the stock profile runs at 1: wall time)", minimum=0.0)
    camera_rate: float | None = param(None, "Kinect frames per sim second (default: the world "
                                      "file's camera.rate; stock: 30, the Kinect's); 0 = no "
                                      "camera", minimum=0.0)
    camera_width: int | None = param(None, "Kinect image width in pixels, the height 3/4 of it: "
                                     "640 (VGA), 320 (QVGA) or 160 (QQVGA) as openni's image "
                                     "modes; the camera_info follows (default: the world file's "
                                     "camera.width and height)", minimum=16, maximum=1280)
    seed: int | None = param(None, "randomisation seed: poses, lighting, colours, noise "
                             "(default: the world file's seed)")
    render_workers: int = param(1, "Kinect rendering processes (2 help at 30 Hz on an idle "
                                "machine)", minimum=1, maximum=16)
    odom_rate: float = param(50.0, "odometry and ground-truth rate (sim Hz)", minimum=1.0)
    cmd_timeout: float = param(0.6, "sim seconds without a velocity command before a robot "
                               "stops", minimum=0.0)
    stats_period: float = param(10.0, "wall seconds between 'turtlebot_sim stats:' log lines "
                                "(rtf, frames, ms per rendered frame, time waiting for the "
                                "renderer)", minimum=0.1)

    def __post_init__(self) -> None:
        if self.drivers not in set(Drivers):
            raise ParamError(f"~drivers must be one of {', '.join(Drivers)}, "
                             f"not {self.drivers!r}")
        if self.drivers == Drivers.STOCK and self.real_time_factor != 1.0:
            raise ParamError("~drivers stock runs on wall time: ~real_time_factor must be 1")


def resolve_world(params: SimParams, path: Path) -> dict:
    """The world config of a run: the file, the seed, the camera size and, under the stock
    profile, the Kinect's own focal length (openni's 525 px at VGA, scaled to the width)."""
    cfg = worldcfg.resolve(path, params.seed)
    if params.camera_width is not None:
        cfg["camera"]["width"] = params.camera_width
        cfg["camera"]["height"] = params.camera_width * 3 // 4
    if params.drivers == Drivers.STOCK:
        cfg["camera"]["hfov_deg"] = stock.kinect_hfov_deg(int(cfg["camera"]["width"]))
    return cfg


class SimNode:
    """The physics loop: step, publish /clock, odometry and Kinect frames, keep the pace."""

    def __init__(self, params: SimParams, config: dict, source: Path) -> None:
        self.drivers = Drivers(params.drivers)
        self.world = World(config)
        cfg = self.world.config
        self.rtf = params.real_time_factor
        default_rate = (stock.KINECT_RATE if self.drivers == Drivers.STOCK
                        else float(cfg["camera"]["rate"]))
        self.camera_rate = params.camera_rate if params.camera_rate is not None else default_rate
        workers = params.render_workers
        odom_rate = params.odom_rate
        timeout = params.cmd_timeout
        self.odom_every = max(1, round(1.0 / (odom_rate * self.world.dt)))
        #: Stamp seconds minus sim seconds: 0 on sim time; the wall clock's epoch under the
        #: stock profile (moved forward when the loop gives up catching up, see run()).
        self.stamp_offset = 0.0
        self.script = BaseEventScript(cfg["base_events"])
        self.robots: dict[str, RobotIO]
        self.clock: rospy.Publisher | None = None
        if self.drivers == Drivers.STOCK:
            self.stamp_offset = time.time() - self.world.time
            tf = rospy.Publisher("/tf", TFMessage, queue_size=100)
            self.robots = {name: StockRobotIO(self.world, name, name in self.world.cameras,
                                              timeout, self.stamp_of, tf)
                           for name in self.world.names}
        else:
            self.clock = rospy.Publisher("/clock", Clock, queue_size=10)
            self.robots = {name: SimRobotIO(self.world, name, name in self.world.cameras,
                                            timeout, self.stamp_of, name in self.script.robots())
                           for name in self.world.names}
        self.pool: RenderPool | None = None
        if self.world.cameras and self.camera_rate > 0:
            self.pool = RenderPool(cfg, workers=workers)
        self.next_frame = 0.0
        self.stats = Stats(params.stats_period)
        rospy.loginfo("turtlebot_sim: world %s, drivers %s, robots %s, cameras %s at %.1f Hz, "
                      "real-time factor %s, seed %s", source, self.drivers,
                      self.world.names, self.world.cameras, self.camera_rate,
                      self.rtf or "max", cfg["seed"])
        rospy.loginfo("turtlebot_sim: run each robot's nodes in its namespace: %s",
                      ", ".join(f"__ns:={rospy.get_namespace()}{name}"
                                for name in sorted(self.world.names)))
        if self.drivers == Drivers.SIM and not rospy.get_param("/use_sim_time", False):
            rospy.logwarn("turtlebot_sim: /use_sim_time is not true: the other nodes will not "
                          "follow the simulation's /clock (rosparam set /use_sim_time true "
                          "before starting them)")

    def stamp_of(self, sim_seconds: float) -> float:
        """The stamp (s) of a sim instant: sim time itself, or wall time under stock drivers."""
        return sim_seconds + self.stamp_offset

    def run(self) -> None:
        """Step until shutdown."""
        wall0 = time.monotonic()
        first = True
        while not rospy.is_shutdown():
            for robot in self.robots.values():
                robot.check_timeout()
            self.world.step()
            if self.clock is not None:
                self.clock.publish(msgs.clock(self.world.time))
            if self.world.steps % self.odom_every == 0:
                for event in self.script.due(self.world.time):
                    self.robots[event.robot].raise_event(event)
                for robot in self.robots.values():
                    robot.check_bumpers()
                    robot.publish_odometry()
            if self.pool is not None:
                self.camera()
            if first:
                rospy.loginfo("turtlebot_sim: running")
                first = False
                self.stats.reset(self.world.time)
            elif self.stats.due():
                rospy.loginfo(self.stats.line(self.world.time))
                self.stats.reset(self.world.time)
            if self.rtf > 0:
                ahead = wall0 + self.world.time / self.rtf - time.monotonic()
                if ahead > 0.001:
                    time.sleep(ahead)
                elif ahead < -MAX_LAG:      # fell behind (load, renderer): no sprint to catch up
                    wall0 = time.monotonic() - self.world.time / self.rtf
                    if self.drivers == Drivers.STOCK:    # stamps stay on the wall clock
                        self.stamp_offset = time.time() - self.world.time

    def camera(self) -> None:
        """Queue the Kinect frames that are due; publish the finished ones.

        On sim time a lagging renderer sets the pace (the physics waits); on wall time (stock)
        a frame due while every render worker is busy is dropped, as a real driver drops it.
        """
        assert self.pool is not None
        if self.world.time + 1e-9 >= self.next_frame:
            self.next_frame += 1.0 / self.camera_rate
            states = self.world.base_states()
            for name in self.world.cameras:
                if self.drivers == Drivers.STOCK and self.pool.busy():
                    self.stats.dropped += 1
                    continue
                while self.pool.busy():        # the renderer sets the pace when it lags
                    start = time.monotonic()
                    frames = self.pool.collect(block=True)
                    self.stats.waited += time.monotonic() - start
                    self.publish(frames)
                self.pool.submit(self.world.time, name, states)
        self.publish(self.pool.collect())

    def publish(self, frames: list[Frame]) -> None:
        for frame in frames:
            self.robots[frame.robot].publish_frame(frame)
            self.stats.frames += 1
            self.stats.render_ms += frame.render_ms

    def close(self) -> None:
        """Log the last figures, stop the render workers, disconnect pybullet."""
        rospy.loginfo(self.stats.line(self.world.time))
        if self.pool is not None:
            self.pool.close()
        self.world.close()


def world_path(given: str) -> Path:
    """The world file to load: ``~world``, or :data:`DEFAULT_WORLD` when it is empty."""
    if given:
        return Path(given)
    package, relative = DEFAULT_WORLD
    try:
        return Path(rospkg.RosPack().get_path(package)) / relative
    except rospkg.ResourceNotFound:
        raise ParamError(f"~world not given, and the default world's package {package} is not "
                         "on the ROS package path: give _world:=FILE.yaml", "world") from None


def open_world(params: SimParams) -> dict:
    """The world config of ``params`` (:func:`resolve_world`); a :class:`ParamError` (one line)
    for a missing or bad file."""
    path = world_path(params.world)
    if not path.is_file():
        raise ParamError(f"~world: no such world file: {path}", "world")
    try:
        return resolve_world(params, path)
    except (OSError, ValueError, KeyError, TypeError, yaml.YAMLError) as err:
        raise ParamError(f"~world: {path} is not a valid world file: "
                         f"{' '.join(str(err).split())}", "world") from None


def main(argv: list[str] | None = None) -> int:
    """Entry point of ``rosrun turtlebot_sim sim``."""
    argv = argv if argv is not None else sys.argv
    exit_on_help(argv, SimParams, "rosrun turtlebot_sim sim [_world:=FILE.yaml] [_name:=value ...]",
                 __doc__.split("\n")[0].split(": ", 1)[-1])
    init_node("turtlebot_sim", argv=argv)
    params = load_or_exit(SimParams, "turtlebot_sim")
    try:
        config = open_world(params)
    except ParamError as err:
        exit_rejected(err, "turtlebot_sim")
    node = SimNode(params, config, world_path(params.world))
    watch_master()              # a restarted roscore gets the topics again
    try:
        node.run()
    except (KeyboardInterrupt, rospy.ROSInterruptException):
        pass
    finally:
        node.close()
    return 0

"""``rosrun turtlebot_sim sim``: the simulated TurtleBot 2 robots speaking kobuki_node's topics.

Private parameters: :class:`SimParams` (``rosrun turtlebot_sim sim --help`` prints them).

Topics (``<r>`` = each robot's name, relative to the node's namespace, so ``__ns:=/test1`` gives
``/test1/faulty/...``; all stamps are sim time; /clock every physics step):
    /clock                                   rosgraph_msgs/Clock        (published)
    /<r>/mobile_base/commands/velocity       geometry_msgs/Twist        (subscribed)
    /<r>/mobile_base/odom                    nav_msgs/Odometry odom -> base_footprint, wheels
    /<r>/ground_truth/odom                   nav_msgs/Odometry world -> <r>/base_footprint
    /<r>/camera/rgb/image_raw                sensor_msgs/Image rgb8      (robots with a Kinect)
    /<r>/camera/depth_registered/points      sensor_msgs/PointCloud2 x y z rgb, organised

The node does not set ``/use_sim_time``: set it before starting the other nodes. After a roscore
restart it registers its topics again (:mod:`rason.ros.master_watch`).
"""

from __future__ import annotations

import sys
import time
from dataclasses import dataclass
from pathlib import Path

import rospkg
import rospy
import yaml
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import Image, PointCloud2

from rason.ros.master_watch import watch_master
from rason.ros.params import ParamError, exit_on_help, exit_rejected, load_or_exit, param
from turtlebot_sim import msgs
from turtlebot_sim.render import Frame, RenderPool
from turtlebot_sim.world import World

#: The world used without ~world: the case study's, found through the ROS package path
DEFAULT_WORLD = ("rason_diagnosis", "worlds/case_study.yaml")

#: Wall seconds the loop may lag behind the real-time factor before it stops trying to catch up.
MAX_LAG = 0.25


class RobotIO:
    """One robot's publishers, subscriber and command bookkeeping."""

    def __init__(self, world: World, name: str, has_camera: bool, timeout: float):
        self.world = world
        self.name = name
        self.timeout = timeout
        self.last_cmd = -1.0e9       # sim time of the last velocity command
        self.odom = rospy.Publisher(f"{name}/mobile_base/odom", Odometry, queue_size=10)
        self.truth = rospy.Publisher(f"{name}/ground_truth/odom", Odometry, queue_size=10)
        self.optical_frame = f"{name}/camera_rgb_optical_frame"
        self.image = self.points = None
        if has_camera:
            self.image = rospy.Publisher(f"{name}/camera/rgb/image_raw", Image, queue_size=2)
            self.points = rospy.Publisher(f"{name}/camera/depth_registered/points",
                                          PointCloud2, queue_size=2)
        self.cmd = rospy.Subscriber(f"{name}/mobile_base/commands/velocity", Twist,
                                    self.on_cmd_vel, queue_size=10)

    def on_cmd_vel(self, msg: Twist) -> None:
        """A velocity command: applied at once, valid for ``timeout`` sim seconds."""
        self.world.set_cmd_vel(self.name, msg.linear.x, msg.angular.z)
        self.last_cmd = self.world.time

    def check_timeout(self) -> None:
        """Stop the robot (like kobuki_node) when commands stopped coming."""
        if self.last_cmd > -1.0e9 and self.world.time - self.last_cmd > self.timeout:
            self.world.set_cmd_vel(self.name, 0.0, 0.0)
            self.last_cmd = -1.0e9

    def publish_odometry(self) -> None:
        t = self.world.time
        x, y, yaw, v, w = self.world.odometry(self.name)
        self.odom.publish(msgs.odometry(t, "odom", "base_footprint", x, y, yaw, v, w))
        gx, gy, gyaw = self.world.pose(self.name)
        gv, gw = self.world.velocity(self.name)
        self.truth.publish(msgs.odometry(t, "world", f"{self.name}/base_footprint",
                                         gx, gy, gyaw, gv, gw))

    def publish_frame(self, frame: Frame) -> None:
        """Image and cloud of one Kinect frame, with the same stamp and frame id."""
        assert self.image is not None and self.points is not None
        self.image.publish(msgs.image(frame.stamp, self.optical_frame, frame.rgb))
        self.points.publish(msgs.cloud(frame.stamp, self.optical_frame, frame.cloud))


class Stats:
    """Running figures, logged every ``period`` wall seconds (what the benchmark reads)."""

    def __init__(self, period: float = 10.0):
        self.period = period
        self.reset(0.0)

    def reset(self, sim_time: float) -> None:
        self.wall0 = time.monotonic()
        self.sim0 = sim_time
        self.frames = 0
        self.render_ms = 0.0
        self.waited = 0.0

    def due(self) -> bool:
        return time.monotonic() - self.wall0 >= self.period

    def line(self, sim_time: float) -> str:
        wall = time.monotonic() - self.wall0
        sim = sim_time - self.sim0
        per_frame = self.render_ms / self.frames if self.frames else 0.0
        return (f"turtlebot_sim stats: rtf {sim / wall:.3f} sim {sim:.2f} s wall {wall:.2f} s "
                f"frames {self.frames} ({self.frames / max(sim, 1e-9):.1f}/sim s) "
                f"render {per_frame:.1f} ms/frame, waited {self.waited:.2f} s for the renderer")


@dataclass(frozen=True)
class SimParams:
    """The simulator node's private parameters."""

    world: str = param("", "path of the world file (YAML, see turtlebot_sim.config); empty: "
                       f"the case study's, $(rospack find {DEFAULT_WORLD[0]})/{DEFAULT_WORLD[1]}")
    real_time_factor: float = param(1.0, "sim seconds per wall second; 0 = as fast as possible",
                                    minimum=0.0)
    camera_rate: float | None = param(None, "Kinect frames per sim second (default: the world "
                                      "file's camera.rate); 0 = no camera", minimum=0.0)
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


class SimNode:
    """The physics loop: step, publish /clock, odometry and Kinect frames, keep the pace."""

    def __init__(self, params: SimParams, world: World, source: Path) -> None:
        self.world = world
        cfg = self.world.config
        self.rtf = params.real_time_factor
        self.camera_rate = (params.camera_rate if params.camera_rate is not None
                            else float(cfg["camera"]["rate"]))
        workers = params.render_workers
        odom_rate = params.odom_rate
        timeout = params.cmd_timeout
        self.odom_every = max(1, round(1.0 / (odom_rate * self.world.dt)))

        self.clock = rospy.Publisher("/clock", Clock, queue_size=10)
        self.robots = {name: RobotIO(self.world, name, name in self.world.cameras, timeout)
                       for name in self.world.names}
        self.pool: RenderPool | None = None
        if self.world.cameras and self.camera_rate > 0:
            self.pool = RenderPool(cfg, workers=workers)
        self.next_frame = 0.0
        self.stats = Stats(params.stats_period)
        rospy.loginfo("turtlebot_sim: world %s, robots %s, cameras %s at %.1f Hz, "
                      "real-time factor %s, seed %s", source, self.world.names,
                      self.world.cameras, self.camera_rate, self.rtf or "max", cfg["seed"])
        rospy.loginfo("turtlebot_sim: run each robot's nodes in its namespace: %s",
                      ", ".join(f"__ns:={rospy.get_namespace()}{name}" for name in sorted(self.world.names)))
        if not rospy.get_param("/use_sim_time", False):
            rospy.logwarn("turtlebot_sim: /use_sim_time is not true: the other nodes will not "
                          "follow the simulation's /clock (rosparam set /use_sim_time true "
                          "before starting them)")

    def run(self) -> None:
        """Step until shutdown."""
        wall0 = time.monotonic()
        first = True
        while not rospy.is_shutdown():
            for robot in self.robots.values():
                robot.check_timeout()
            self.world.step()
            self.clock.publish(msgs.clock(self.world.time))
            if self.world.steps % self.odom_every == 0:
                for robot in self.robots.values():
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

    def camera(self) -> None:
        """Queue the Kinect frames that are due; publish the finished ones."""
        assert self.pool is not None
        if self.world.time + 1e-9 >= self.next_frame:
            self.next_frame += 1.0 / self.camera_rate
            states = self.world.base_states()
            for name in self.world.cameras:
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


def open_world(params: SimParams) -> World:
    """The world of ``params``; a :class:`ParamError` (one line) for a missing or bad file."""
    path = world_path(params.world)
    if not path.is_file():
        raise ParamError(f"~world: no such world file: {path}", "world")
    try:
        return World.from_yaml(path, seed=params.seed)
    except (OSError, ValueError, KeyError, TypeError, yaml.YAMLError) as err:
        raise ParamError(f"~world: {path} is not a valid world file: "
                         f"{' '.join(str(err).split())}", "world") from None


def main(argv: list[str] | None = None) -> int:
    """Entry point of ``rosrun turtlebot_sim sim``."""
    argv = argv if argv is not None else sys.argv
    exit_on_help(argv, SimParams, "rosrun turtlebot_sim sim [_world:=FILE.yaml] [_name:=value ...]",
                 __doc__.split("\n")[0].split(": ", 1)[-1])
    rospy.init_node("turtlebot_sim", argv=argv)
    params = load_or_exit(SimParams, "turtlebot_sim")
    try:
        world = open_world(params)
    except ParamError as err:
        exit_rejected(err, "turtlebot_sim")
    node = SimNode(params, world, world_path(params.world))
    watch_master()              # a restarted roscore gets the topics again
    try:
        node.run()
    except (KeyboardInterrupt, rospy.ROSInterruptException):
        pass
    finally:
        node.close()
    return 0

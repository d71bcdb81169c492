"""How the case study's robot-side nodes are wired under each driver profile (docs/drivers.md).

``sim`` (the default): the simulator's own names on sim time. ``stock``: the real drivers' names
on wall time; the fault injector reads the driver's ``odom`` and publishes its copy on
``fault_injector/odom`` for the decomposer and the synthesizer, and Helper's Kinect goes through
Debian's image pipeline (image_proc's debayer and depth_image_proc's point_cloud_xyzrgb
nodelets) into the synthesizer, as rgbd_launch wires it on a robot.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from turtlebot_sim.node import Drivers

#: The Kinect rate of the stock demo (Hz): 30 does not fit this 2-core machine (docs/drivers.md).
STOCK_DEMO_RATE = 15.0
#: The odometry the injector publishes for its readers under the stock names.
INJECTED_ODOM = "fault_injector/odom"


@dataclass(frozen=True)
class NodeLine:
    """One extra ``rosrun`` of a profile: package, executable, namespace, remaps."""

    package: str
    executable: str
    ns: str
    args: tuple[str, ...] = ()


@dataclass(frozen=True)
class Wiring:
    """Everything the demo does differently per driver profile."""

    drivers: Drivers
    sim_time: bool                       # /use_sim_time and the sim's /clock
    ready_topic: str                     # what shows the simulator is up
    injector_params: dict[str, object]   # the fault injector's topic parameters
    odom_reader_args: tuple[str, ...]    # remaps of the decomposer and the synthesizer
    synthesizer_args: tuple[str, ...]    # the synthesizer's other remaps
    synthesizer_params: dict[str, object] = field(default_factory=dict)
    vision_nodes: tuple[NodeLine, ...] = ()   # between the camera and the synthesizer
    odom_topic: str = "odom"             # the odometry the agents' nodes read (robot-relative)
    image_topic: str = "camera/rgb/image_raw"   # a colour image for the run's picture
    #: the cloud for the picture's detection overlay; None: no overlay (a 9.8 MB cloud per frame
    #: into the demo process costs the wall-clock run too much on this machine)
    cloud_topic: str | None = "camera/depth_registered/points"

    camera_rate: float | None = None     # the sim's ~camera_rate (None: the profile's own)

    def sim_params(self) -> dict[str, object]:
        """The simulator's parameters for this profile."""
        rate = {} if self.camera_rate is None else {"camera_rate": self.camera_rate}
        return {"drivers": self.drivers.value, **rate}


SIM = Wiring(Drivers.SIM, sim_time=True, ready_topic="/clock", injector_params={},
             odom_reader_args=(), synthesizer_args=())

STOCK = Wiring(
    Drivers.STOCK, sim_time=False, ready_topic="/faulty/odom",
    injector_params={"odom_input": "odom", "odom_output": INJECTED_ODOM},
    odom_reader_args=(f"odom:={INJECTED_ODOM}",),
    synthesizer_args=("camera/rgb/image_raw:=camera/rgb/image_color",),
    # the cloud carries the depth image's stamp, 0.055 s before the colour image's
    synthesizer_params={"slop": 0.1},
    vision_nodes=(
        NodeLine("nodelet", "nodelet", "/helper/camera/rgb", ("standalone", "image_proc/debayer")),
        NodeLine("nodelet", "nodelet", "/helper/camera",
                 ("standalone", "depth_image_proc/point_cloud_xyzrgb",
                  "rgb/image_rect_color:=rgb/image_color",
                  "depth_registered/image_rect:=depth_registered/image_raw")),
    ),
    odom_topic=INJECTED_ODOM, image_topic="camera/rgb/image_color", cloud_topic=None,
    camera_rate=STOCK_DEMO_RATE)

WIRINGS = {w.drivers.value: w for w in (SIM, STOCK)}


def rosrun_line(package: str, executable: str, ns: str, args: tuple[str, ...] = (),
                params: dict[str, object] | None = None) -> str:
    """A ``rosrun`` line as docs/drivers.md writes it: arguments, namespace, ``_param:=value``,
    then the remaps."""
    positional = [a for a in args if ":=" not in a]
    remaps = [a for a in args if ":=" in a]
    private = [f"_{key}:={value}" for key, value in (params or {}).items()]
    return " ".join(["rosrun", package, executable, *positional, f"__ns:={ns}", *private,
                     *remaps])


def robot_side_lines(wiring: Wiring, robot: str = "faulty") -> list[str]:
    """The rosrun lines of the robot-side nodes under ``wiring``: ``robot``'s injector and
    decomposer, and Helper's image pipeline and synthesizer (docs/drivers.md shows STOCK's)."""
    ns = f"/{robot}"
    lines = [rosrun_line("kobuki_fault_injector", "fault_injector", ns,
                         params=wiring.injector_params),
             rosrun_line("rason", "motion_decomposer", ns, wiring.odom_reader_args)]
    lines += [rosrun_line(n.package, n.executable, n.ns, n.args) for n in wiring.vision_nodes]
    lines.append(rosrun_line("rason_vision", "robot_synthesizer", "/helper",
                             (*wiring.odom_reader_args, *wiring.synthesizer_args),
                             wiring.synthesizer_params))
    return lines

"""How the case study's robot-side nodes are wired under each driver profile (docs/drivers.md).

``sim`` (the default): the simulator's own names on sim time. ``stock``: the real drivers' names
on wall time; the fault injector reads the driver's ``odom`` and publishes its copy on
``fault_injector/odom`` for the decomposer and the synthesizer, and Helper's Kinect goes through
Debian's image pipeline (image_proc's debayer and depth_image_proc's point_cloud_xyzrgb
nodelets) into the synthesizer, as rgbd_launch wires it on a robot (``STOCK``), or the
synthesizer reads the driver's Bayer and 16UC1 depth images itself (``STOCK_RAW``, ``--vision
raw``).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from enum import StrEnum

from turtlebot_sim.node import Drivers

#: The Kinect rate of the stock demo (Hz): 30 does not fit this 2-core machine (docs/drivers.md).
STOCK_DEMO_RATE = 15.0
#: The odometry the injector publishes for its readers under the stock names.
INJECTED_ODOM = "fault_injector/odom"


class VisionPath(StrEnum):
    """How Helper's Kinect reaches the synthesizer under the stock profile (``--vision``)."""

    NODELETS = "nodelets"   # Debian's debayer + point_cloud_xyzrgb in front, as rgbd_launch
    RAW = "raw"             # the synthesizer reads the Bayer image and 16UC1 depth image itself


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
    #: the stock profile's image path; None under sim (its rgb8 and cloud go straight in)
    vision: VisionPath | None = None

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
    camera_rate=STOCK_DEMO_RATE, vision=VisionPath.NODELETS)

#: The stock profile without the nodelets: the synthesizer debayers ``camera/rgb/image_raw``
#: and reads ``camera/depth_registered/image_raw`` with its camera_info; its default ``~slop``
#: (0.075 s) covers the depth image's 0.055 s offset.
STOCK_RAW = replace(STOCK, synthesizer_args=(), synthesizer_params={"depth_input": "image"},
                    vision_nodes=(), image_topic="camera/rgb/image_raw", vision=VisionPath.RAW)

WIRINGS = {w.drivers.value: w for w in (SIM, STOCK)}


def wiring_for(drivers: str, vision: str | None = None) -> Wiring:
    """The wiring of ``--drivers`` and ``--vision`` (stock's default: the nodelets, what
    rgbd_launch starts on a TurtleBot); ValueError for ``vision`` under the sim profile."""
    wiring = WIRINGS[drivers]
    if vision is None:
        return wiring
    if wiring.vision is None:
        raise ValueError(f"--vision {vision} needs --drivers stock: the {drivers} profile "
                         "publishes rgb8 and a cloud, read as they are")
    return STOCK_RAW if VisionPath(vision) is VisionPath.RAW else STOCK


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

"""Pictures of a run: top-down paths and Helper's camera frame at the feedback moment."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from rason_vision.convert import cloud_to_xyz, image_to_rgb
from rason_vision.detector import detect

if TYPE_CHECKING:
    from rason_diagnosis.monitor import RunMonitor
    from rason_diagnosis.scenario import RunResult


def odometry_in_world(odom: np.ndarray, truth: np.ndarray) -> np.ndarray:
    """Faulty's odometry path (odom frame, starts at 0,0,0) placed at its true start pose."""
    if len(odom) == 0 or len(truth) == 0:
        return odom
    x0, y0, th0 = truth[0, 1], truth[0, 2], truth[0, 3]
    c, s = math.cos(th0 - odom[0, 3]), math.sin(th0 - odom[0, 3])
    dx, dy = odom[:, 1] - odom[0, 1], odom[:, 2] - odom[0, 2]
    out = odom.copy()
    out[:, 1] = x0 + c * dx - s * dy
    out[:, 2] = y0 + s * dx + c * dy
    return out


def save_run_picture(monitor: RunMonitor, result: RunResult, path) -> None:
    """Write a PNG: paths on the left, the camera frame with the detected cylinders on the right."""
    fig, (top, cam) = plt.subplots(1, 2, figsize=(13, 5.5), gridspec_kw={"width_ratios": [1, 1.2]})
    faulty = monitor.paths["faulty_true"].array()
    helper = monitor.paths["helper_true"].array()
    odom = odometry_in_world(monitor.paths["faulty_odom"].array(), faulty)
    for data, style, label in ((faulty, "-", "Faulty, true path"),
                               (odom, "--", "Faulty, its odometry"),
                               (helper, "-", "Helper, true path")):
        if len(data):
            top.plot(data[:, 1], data[:, 2], style, lw=2, label=label)
            top.plot(data[0, 1], data[0, 2], "o", color=top.lines[-1].get_color())
            end = data[-1]
            top.arrow(end[1], end[2], 0.15 * math.cos(end[3]), 0.15 * math.sin(end[3]),
                      head_width=0.05, color=top.lines[-1].get_color())
    top.set_aspect("equal")
    top.grid(alpha=0.3)
    top.set_xlabel("x (m)")
    top.set_ylabel("y (m)")
    top.legend(loc="best", fontsize=8)
    verdict = "correct" if result.correct else "WRONG"
    top.set_title(f"fault {result.fault}, seed {result.seed}: diagnosis "
                  f"{result.diagnosis} ({verdict})", fontsize=10)

    frame = monitor.last_frame()
    cam.set_axis_off()
    if frame is None:
        cam.set_title("no camera frame received")
    else:
        _draw_frame(cam, *frame)
    fig.tight_layout()
    fig.savefig(path, dpi=90, bbox_inches="tight")  # keep the two-line camera title
    plt.close(fig)


def _draw_frame(ax, image_msg, cloud_msg) -> None:
    rgb = image_to_rgb(image_msg)
    ax.imshow(rgb)
    title = "Helper's camera at the feedback moment"
    if cloud_msg is not None:
        found = detect(rgb, cloud_to_xyz(cloud_msg))
        for blobs in found.blobs.values():
            for blob in blobs:
                x0, y0, w, h = blob.bbox
                ax.add_patch(plt.Rectangle((x0, y0), w, h, fill=False, lw=1, ls=":",
                                           color="white"))
        det = found.detection
        if det is not None:
            for blob, colour in ((det.green, "lime"), (det.orange, "orange")):
                x0, y0, w, h = blob.bbox
                ax.add_patch(plt.Rectangle((x0, y0), w, h, fill=False, lw=2, color=colour))
            title += (f"\nrobot(faulty, {det.angle:.1f}, {det.depth:.2f}, {det.yaw:.1f})")
        else:
            title += "\n(no robot detected)"
    ax.set_title(title, fontsize=10)

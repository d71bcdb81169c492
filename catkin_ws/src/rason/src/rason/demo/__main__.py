"""``./run.sh demo``: for now, start a private roscore and report that the workspace is ready."""

from __future__ import annotations

import sys

from rason.harness import RosHarness


def main() -> int:
    with RosHarness() as ros:
        print(f"roscore running at {ros.master_uri}; nodes known: {sorted(ros.nodes())}")
        print("rason workspace ready: source env.sh, then rosrun rason ... (see README)")
    ros.cleanup_logs()
    return 0


if __name__ == "__main__":
    sys.exit(main())

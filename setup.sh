#!/usr/bin/env bash
# Installs everything rason needs on a Debian 12 machine, as root. Idempotent: each step checks
# whether it is already done, so a second run on a set-up machine takes seconds.
#   ./setup.sh            install what is missing, then build the catkin workspace
#   ./setup.sh --force    redo every step
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
VENV="$ROOT/.venv"
FORCE=0
[ "${1:-}" = "--force" ] && FORCE=1

APT_PACKAGES=(
  # ROS 1 from Debian's packages (see README: ROS_DISTRO=Debian, everything under /usr)
  python3-roslaunch python3-rosmaster rosout rosbash python3-rospy python3-rostopic
  python3-rosservice python3-rosnode python3-rosbag python3-rosmsg python3-message-filters
  catkin ros-message-generation python3-genpy python3-genmsg
  ros-std-msgs ros-geometry-msgs ros-nav-msgs ros-sensor-msgs ros-diagnostic-msgs
  python3-std-msgs python3-geometry-msgs python3-sensor-msgs python3-nav-msgs python3-diagnostic-msgs
  libstd-msgs-dev libgeometry-msgs-dev libnav-msgs-dev libsensor-msgs-dev libdiagnostic-msgs-dev
  # build tools and Debian's Python venv
  cmake g++ make python3-venv
  # rason.asl's reasoning cycle compiled to C by mypyc (pinned with mypy): Python's headers
  python3-dev
  # the mind inspector's browser test (headless, driven by selenium)
  chromium chromium-driver
  # ./run.sh demo --hosts: a robot host's firewall (nft), as on the robots (README)
  nftables
  # the stock-driver profile (docs/drivers.md): /tf messages, and Debian's own image pipeline
  # between the Kinect topics and the vision (the -dev packages carry the nodelet plugin lists)
  python3-tf2-msgs ros-tf2-msgs libnodeletlib-tools libimage-proc-dev libdepth-image-proc-dev
  # the motion decomposer's ~reload service (std_srvs/Trigger, docs/agent-node.md)
  ros-std-srvs python3-std-srvs
)

step() { printf '\n==> setup: %s\n' "$*"; }
# progress LOG PID [SKIP]: wait for the background job PID, printing every PROGRESS_PERIOD (5)
# seconds the time so far and LOG's last line (catkin_make's "[ 40%] Built target ...", mypyc's
# module lines) but none matching the extended regex SKIP, so a long build is never silent;
# returns the job's exit status.
progress() {
  local log=$1 pid=$2 skip=${3:-} start=$SECONDS period=${PROGRESS_PERIOD:-5} last
  local next=$((start + period))
  while kill -0 "$pid" 2>/dev/null; do
    sleep 0.2     # the job's end is seen within 0.2 s; the lines still come every period
    if kill -0 "$pid" 2>/dev/null && (( SECONDS >= next )); then
      next=$((SECONDS + period))
      last=$(shown "$log" "$skip" | tail -n 1 | tr -d '\r' | cut -c1-100)
      printf '    %4d s  %s\n' $((SECONDS - start)) "$last"
    fi
  done
  local status=0
  wait "$pid" || status=$?
  printf '    %4d s  %s\n' $((SECONDS - start)) "$([ $status = 0 ] && echo done || echo "failed ($status)")"
  return $status
}
# shown LOG [SKIP]: LOG's lines but those matching the extended regex SKIP (none if empty)
shown() {
  if [ -n "${2:-}" ]; then grep -avE -- "$2" "$1" 2>/dev/null || true; else cat "$1" 2>/dev/null || true; fi
}
# pip's notes about this machine's pip configuration (an extra index or find-links folder it
# lists, a location of it that does not exist): not progress, and no error of the install
PIP_NOTES="^Looking in (indexes|links): |^WARNING: Location '[^']*' is ignored: it is neither a file nor a directory\.$"
fail() { printf '\n!!! setup failed at step: %s\n' "$CURRENT_STEP" >&2; exit 1; }
trap fail ERR

CURRENT_STEP="check root"
if [ "$(id -u)" != 0 ]; then echo "setup.sh must run as root (apt-get install)" >&2; exit 1; fi

CURRENT_STEP="Debian packages"
missing=()
for p in "${APT_PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ] || [ $FORCE = 1 ]; then
  step "apt-get update"
  apt-get update -q
  step "apt-get install ${#missing[@]} Debian packages: ${missing[*]:-all}"
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${APT_PACKAGES[@]}"
else
  step "Debian packages: all ${#APT_PACKAGES[@]} present"
fi

CURRENT_STEP="Python venv"
if [ ! -x "$VENV/bin/python3" ] || [ $FORCE = 1 ]; then
  step "venv $VENV from /usr/bin/python3 (--system-site-packages)"
  /usr/bin/python3 -m venv --system-site-packages --clear "$VENV"
else
  step "venv present"
fi

CURRENT_STEP="PyPI packages (requirements.txt)"
stamp="$VENV/.requirements.sha256"
want=$(sha256sum "$ROOT/requirements.txt" | cut -d' ' -f1)
if [ ! -f "$stamp" ] || [ "$(cat "$stamp")" != "$want" ] || [ $FORCE = 1 ]; then
  step "pip install -r requirements.txt (log: $VENV/pip.log)"
  # in the background under progress: with -q a first install printed nothing for its whole run
  "$VENV/bin/python3" -m pip install --disable-pip-version-check --progress-bar off \
    -r "$ROOT/requirements.txt" > "$VENV/pip.log" 2>&1 &
  progress "$VENV/pip.log" $! "$PIP_NOTES" || { shown "$VENV/pip.log" "$PIP_NOTES" | tail -40 >&2; false; }
  echo "$want" > "$stamp"
else
  step "PyPI packages up to date"
fi

CURRENT_STEP="catkin_make"
step "catkin_make (Python: $VENV/bin/python3)"
cd "$ROOT/catkin_ws"
PATH="$VENV/bin:$PATH" catkin_make -DPYTHON_EXECUTABLE="$VENV/bin/python3" -DCATKIN_ENABLE_TESTING=OFF \
  > "$ROOT/catkin_ws/catkin_make.log" 2>&1 &
progress "$ROOT/catkin_ws/catkin_make.log" $! || { tail -40 "$ROOT/catkin_ws/catkin_make.log" >&2; false; }

CURRENT_STEP="compiled modules"
# rason.asl's hot modules compiled with mypyc; a no-op when the build for these sources exists
step "rason.asl compiled with mypyc (python -m rason.asl native build)"
PYTHONPATH="$ROOT/catkin_ws/src/rason/src" RASON_NATIVE=0 "$VENV/bin/python3" -m rason.asl native build \
  --log "$ROOT/catkin_ws/native.log" > /dev/null &
progress "$ROOT/catkin_ws/native.log" $!
CURRENT_STEP="bytecode"
# the workspace's Python compiled to bytecode now, as pip does for installed packages: a start
# then costs the same whether or not PYTHONDONTWRITEBYTECODE=1 stops Python writing it itself
step "bytecode of the workspace's Python (python -m compileall)"
"$VENV/bin/python3" -m compileall -q -j 0 "$ROOT"/catkin_ws/src/*/src \
  "$ROOT/catkin_ws/devel/lib/python3/dist-packages" > "$ROOT/catkin_ws/compileall.log" 2>&1 &
progress "$ROOT/catkin_ws/compileall.log" $! || { tail -20 "$ROOT/catkin_ws/compileall.log" >&2; false; }
step "done: source $ROOT/env.sh to use rosrun, rostopic, rosservice"

# Source this file to use rason with the real ROS tools in your shell:
#   source env.sh      then: roscore, rosrun rason agent ..., rostopic echo ..., rosservice call ...
# It activates the project's venv, sources the catkin workspace and points ROS at a local master.
# ROS_MASTER_URI / ROS_IP / ROS_HOME already set in your shell are kept.
_rason_root="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
if [ ! -f "$_rason_root/catkin_ws/devel/setup.bash" ]; then
  echo "rason: workspace not built yet; run $_rason_root/setup.sh (as root) first" >&2
  return 1 2>/dev/null || exit 1
fi
# shellcheck disable=SC1091
source "$_rason_root/.venv/bin/activate"
# shellcheck disable=SC1091
source "$_rason_root/catkin_ws/devel/setup.bash"
export ROS_MASTER_URI="${ROS_MASTER_URI:-http://127.0.0.1:11311}"
export ROS_IP="${ROS_IP:-127.0.0.1}"
export RASON_ROOT="$_rason_root"
unset _rason_root

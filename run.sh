#!/usr/bin/env bash
# The one entry point of rason. Sets the machine up on first use (./setup.sh), then:
#
#   ./run.sh demo [OPTIONS]         the cooperative fault diagnosis in simulation, once
#       --fault NAME                the fault to inject: both_actuators, odometry, left_actuator,
#                                   right_actuator or none
#       --seed N                    the seed of the run's variation
#       --world FILE.yaml           your own world file (robot poses, room, lighting)
#       --colours FILE.yaml         the synthesizer's colour ranges (rosrun rason_vision
#                                   calibrate; default: the world's vision.colours)
#       --json                      print the result as JSON at the end
#       --record                    also record a bag of the run
#       --drivers sim|stock         the simulator's topics: its own (sim time) or the real
#                                   Kobuki and Kinect drivers' (wall time; docs/drivers.md)
#       --vision nodelets|raw       with --drivers stock: Debian's debayer + point-cloud
#                                   nodelets before the synthesizer (default), or none
#       --real                      only the workstation side, against robots already up
#                                   (docs/real-robot.md)
#       --robots-timeout S          with --real: seconds to wait for the robots' nodes
#       --key FILE                  with --real: the fleet's key, as the robots' decomposers
#                                   have it (without --real every run makes its own key)
#       --out DIR                   the folder for the picture and logs
#       --hosts                     the workstation and each robot on a host of its own (root)
#       --cut HOST@Ts+Ds            cut HOST's link T s after the agents start, for D s (--hosts)
#       --quiet                     do not stream the agents' console
#       --timeout S                 simulated seconds allowed
#       --inspector-port N          the mind inspector's port (0: any free port)
#       --inspector, --no-inspector with or without the mind inspector (default: with)
#       --hold                      after the result, keep every node (the inspector too)
#                                   up until Ctrl-C
#   ./run.sh campaign [OPTIONS]     every fault and none, N runs each: report.md, runs.csv, plots
#       --runs N                    runs per fault (default 10)
#       --layouts fixed|random      the thesis' layout, or a seeded random layout per run index
#       --out DIR                   the folder for the report
#       --faults NAME...            only these faults
#       --world FILE.yaml           every run in this world (e.g. worlds/harsh.yaml)
#       --colours FILE.yaml         as for demo
#       --first-seed N              the seed of the first run
#       --hosts                     every run across hosts of its own (root)
#       --drivers sim|stock         as for demo
#       --vision nodelets|raw       as for demo
#       --report-only               rewrite report.md and the plots from --out's runs.csv
#       --mission                   run the mission instead of the demo: completion, time against
#                                   the fault-free mission, waypoint errors, contacts, who reached
#                                   the waypoints (default --out out/campaign-mission)
#       --no-recovery               with --mission: only the baseline, without recovery
#       --baseline                  with --mission: with recovery and without, side by side
#   ./run.sh mission [OPTIONS]      Faulty visits the world's waypoints; a fault strikes on the way and
#                                   the team diagnoses it and recovers (docs/mission.md)
#       --fault NAME                as for demo (default: drawn by the seed, none included)
#       --at SECONDS                inject it this long after Faulty's first motion (simulated)
#       --seed N, --world FILE.yaml, --out DIR, --json, --quiet, --timeout S   as for demo
#       --no-recovery               the baseline: after the diagnosis Faulty gives the mission up
#       --inspector-port N, --inspector, --no-inspector   as for demo (the inspector's mission view)
#       --hold                      as for demo
#   ./run.sh bench NAME [ARGS...]   a benchmark of benchmarks/ (./run.sh bench lists them)
#   ./run.sh test [PYTEST_ARGS...]  the whole test suite (what CI runs), or a part: a file, -k NAME
#                                   (on 2 workers; RASON_TEST_WORKERS=0: in one process;
#                                   docs/layout.md)
#   ./run.sh env                    a shell with ROS and the workspace ready (or: source env.sh)
#   ./run.sh help                   this text (also -h, --help)
# Each command's own --help gives its options with their defaults (./run.sh demo --help).
set -eo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
cd "$ROOT"

usage() {
  # the comment block at the top of this file, without its '#'
  awk 'NR == 1 { next } !/^#/ { exit } { sub(/^# ?/, ""); print }' "$0"
}

list_benchmarks() {
  local file name
  for file in "$ROOT"/benchmarks/*.py; do
    name="$(basename "$file" .py)"
    [ "${name#_}" = "$name" ] || continue     # _name.py: shared code, not a benchmark
    # the first line of its docstring
    printf '  %-20s %s\n' "$name" "$(grep -m1 -o '"""[^"]*' "$file" | cut -c4-)"
  done
}

#: pytest workers for ./run.sh test: N xdist workers (2, the default: the two cores), each with
#: its own roscore, or 0 for one process (docs/layout.md#the-suites-run)
TEST_WORKERS="${RASON_TEST_WORKERS:-2}"

test_workers() {
  # pytest-xdist options for ./run.sh test ARGS: TEST_WORKERS workers for the suite, each
  # with its own roscore; the end-to-end runs stay on one of them (their xdist group, see
  # tests/conftest.py). None when ARGS name tests by path (one file runs fast serially) or
  # already choose (-n, --dist, -p no:xdist) or need one process (--pdb, --collect-only).
  local arg
  for arg in "$@"; do
    case "$arg" in
      -n|-n*|--numprocesses*|--dist*|no:xdist|--pdb|--trace|--co|--collect-only) return ;;
      -*) ;;
      *) if [[ "$arg" == *::* ]] || [ -e "$arg" ]; then return; fi ;;
    esac
  done
  [ "$TEST_WORKERS" = 0 ] || echo "-n $TEST_WORKERS --dist loadgroup"
}

#: set by the traps of ensure_setup: the exit status of an interrupt that came meanwhile
INTERRUPTED=""

ensure_setup() {
  # Ctrl-C and SIGTERM during setup and env.sh are recorded and end the run right after them
  # (exit 130, 143). Without the traps an interrupt sent to this script alone (kill -INT PID;
  # a terminal's Ctrl-C reaches setup too) was lost: bash waits for a running command before
  # it acts on a signal, setup never got it and ended well, so bash took it as handled and went
  # on to start the demo (1 of 30 `./run.sh demo` runs as root, SIGINT 4.3 s in)
  trap 'INTERRUPTED=130' INT
  trap 'INTERRUPTED=143' TERM
  if [ "$(id -u)" = 0 ]; then
    "$ROOT/setup.sh" | sed -u 's/^/  /'
  elif [ ! -f "$ROOT/catkin_ws/devel/setup.bash" ]; then
    echo "rason is not set up yet: run sudo $ROOT/setup.sh once" >&2; exit 1
  fi
  # shellcheck disable=SC1091
  source "$ROOT/env.sh"
  trap - INT TERM      # from here an interrupt ends this script at once, or the command
  if [ -n "$INTERRUPTED" ]; then
    echo "./run.sh: interrupted during setup: nothing started" >&2; exit "$INTERRUPTED"
  fi
}

cmd="${1:-help}"; shift || true
case "$cmd" in
  test)
    ensure_setup
    if [ "${1:-}" = "--fast" ]; then
      # the inner loop: no roscore, no node (the `ros` marker, see tests/conftest.py), not the
      # few long ones (`slow`, see pytest.ini), fewer examples in the larger property tests
      # (tests/draws.py)
      shift; RASON_TEST_FAST=1 exec python3 -m pytest -m "not ros and not slow" "$@"
    fi
    # shellcheck disable=SC2046  # test_workers gives words (options) or nothing
    exec python3 -m pytest $(test_workers "$@") "$@"
    ;;
  demo)
    ensure_setup
    exec python3 -m rason_diagnosis "$@"
    ;;
  mission)
    ensure_setup
    exec python3 -m rason_diagnosis.mission "$@"
    ;;
  campaign)
    ensure_setup
    exec python3 -m rason_diagnosis.campaign "$@"
    ;;
  bench)
    if [ $# -eq 0 ] || [ ! -f "$ROOT/benchmarks/$1.py" ] || [ "${1#_}" != "$1" ]; then
      if [ $# -eq 0 ]; then
        echo "./run.sh bench: which benchmark? usage: ./run.sh bench NAME [ARGS...]" >&2
      else
        echo "./run.sh bench: no benchmark named '$1' (no benchmarks/$1.py)" >&2
      fi
      echo "NAME is one of (./run.sh bench NAME --help for its options):" >&2
      list_benchmarks >&2
      exit 2
    fi
    ensure_setup
    name="$1"; shift
    exec python3 "$ROOT/benchmarks/$name.py" "$@"
    ;;
  env)
    ensure_setup
    echo "rason environment ready (ROS_MASTER_URI=$ROS_MASTER_URI). Start a master with: roscore &"
    exec bash --rcfile <(printf 'source ~/.bashrc 2>/dev/null; source %q\nPS1="(rason) $PS1"\n' "$ROOT/env.sh") -i
    ;;
  help|-h|--help)
    usage
    ;;
  *)
    echo "unknown command: $cmd" >&2; usage >&2; exit 2
    ;;
esac

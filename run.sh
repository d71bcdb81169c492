#!/usr/bin/env bash
# The one entry point of rason. Sets the machine up on first use (./setup.sh), then:
#   ./run.sh test [PYTEST_ARGS...]   run the whole test suite (what CI runs)
#   ./run.sh demo [--fault NAME] [--seed N] [--record]
#                                    the cooperative fault diagnosis in simulation
#   ./run.sh campaign [--runs N] [--out DIR]   all scenarios, N runs each, report + plots
#   ./run.sh bench NAME [ARGS...]    a benchmark from benchmarks/ (e.g. reasoning_cycle)
#   ./run.sh env                     a shell with ROS and the workspace ready (or: source env.sh)
set -eo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
cd "$ROOT"

ensure_setup() {
  if [ "$(id -u)" = 0 ]; then
    "$ROOT/setup.sh" | sed -u 's/^/  /'
  elif [ ! -f "$ROOT/catkin_ws/devel/setup.bash" ]; then
    echo "rason is not set up yet: run sudo $ROOT/setup.sh once" >&2; exit 1
  fi
  # shellcheck disable=SC1091
  source "$ROOT/env.sh"
}

cmd="${1:-help}"; shift || true
case "$cmd" in
  test)
    ensure_setup
    if [ "${1:-}" = "--fast" ]; then
      # the inner loop: no roscore, no node (the `ros` marker, see tests/conftest.py), and not
      # the few long ones (`slow`); see pytest.ini
      shift; exec python3 -m pytest -m "not ros and not slow" "$@"
    fi
    exec python3 -m pytest "$@"
    ;;
  demo)
    ensure_setup
    exec python3 -m rason_diagnosis "$@"
    ;;
  campaign)
    ensure_setup
    exec python3 -m rason_diagnosis.campaign "$@"
    ;;
  bench)
    ensure_setup
    name="${1:?usage: ./run.sh bench NAME [ARGS...]; NAME is one of: $(ls benchmarks | sed -n 's/\.py$//p' | tr '\n' ' ')}"; shift
    exec python3 "$ROOT/benchmarks/$name.py" "$@"
    ;;
  env)
    ensure_setup
    echo "rason environment ready (ROS_MASTER_URI=$ROS_MASTER_URI). Start a master with: roscore &"
    exec bash --rcfile <(printf 'source ~/.bashrc 2>/dev/null; source %q\nPS1="(rason) $PS1"\n' "$ROOT/env.sh") -i
    ;;
  help|-h|--help)
    sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//'
    ;;
  *)
    echo "unknown command: $cmd" >&2; sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2
    ;;
esac

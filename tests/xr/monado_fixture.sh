#!/usr/bin/env bash
# CTest fixture for the OpenXR tests: Monado (../shared/tools/monado.sh) built once and its
# service started headless (simulated HMD, null compositor, lavapipe) before the tests that need
# it, stopped after them. Without ../shared it does nothing and those tests skip.
#
#   monado_fixture.sh start MONADO_DIR RUNTIME_DIR   build (once) and start; pid in RUNTIME_DIR
#   monado_fixture.sh stop  MONADO_DIR RUNTIME_DIR   stop the service started by `start`
set -euo pipefail
cmd="${1:?start|stop}" dir="${2:?monado dir}" xdg="${3:?runtime dir}"
script="$(cd "$(dirname "$0")/../.." && pwd)/../shared/tools/monado.sh"
pidfile="$xdg/monado.pid"

stop() {
  if [ -f "$pidfile" ]; then
    pid="$(cat "$pidfile")"
    kill "$pid" 2>/dev/null || true
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -9 "$pid" 2>/dev/null || true
    rm -f "$pidfile"
  fi
  rm -f "$xdg/monado_comp_ipc"
}

case "$cmd" in
start)
  if [ ! -f "$script" ]; then
    echo "monado fixture: ../shared/tools/monado.sh is absent: the OpenXR tests skip"
    exit 0
  fi
  mkdir -p "$xdg" && chmod 700 "$xdg"
  stop # a service left by an interrupted run
  echo "monado fixture: building Monado in $dir (once, about 2.5 minutes on 2 cores)"
  bash "$script" build "$dir"
  export XDG_RUNTIME_DIR="$xdg"
  eval "$(bash "$script" start "$dir")"
  echo "$MONADO_PID" >"$pidfile"
  echo "monado fixture: service $MONADO_PID, XR_RUNTIME_JSON=$XR_RUNTIME_JSON"
  ;;
stop)
  stop
  ;;
*)
  echo "usage: monado_fixture.sh start|stop MONADO_DIR RUNTIME_DIR" >&2
  exit 2
  ;;
esac

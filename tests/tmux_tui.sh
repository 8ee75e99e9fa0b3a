#!/usr/bin/env bash
# The explorer in a real terminal: tmux at 100x30. It checks that the
# panels and lambda show, that -> raises lambda by 0.05, that ? shows the
# help and that q quits with status 0. Builds nothing itself.
#
#   tests/tmux_tui.sh [path/to/shakedown]    (default target/release/shakedown)
set -u

bin=${1:-target/release/shakedown}
if [ ! -x "$bin" ]; then
  echo "tmux_tui: no executable at '$bin' (build it first: cargo build --release)" >&2
  exit 1
fi
if ! command -v tmux >/dev/null 2>&1; then
  echo "tmux_tui: tmux is not installed" >&2
  exit 1
fi
bin=$(cd "$(dirname "$bin")" && pwd)/$(basename "$bin")

work=$(mktemp -d)
session="shakedown-tui-test-$$"
# A private server, so the test neither sees nor disturbs the user's tmux.
tm() { tmux -L "$session" "$@"; }
cleanup() {
  tm kill-server >/dev/null 2>&1
  rm -rf "$work"
}
trap cleanup EXIT

fail() {
  echo "tmux_tui: FAIL: $*" >&2
  if [ -f "$work/screen" ]; then
    echo "--- last screen ---" >&2
    cat "$work/screen" >&2
    echo "-------------------" >&2
  fi
  exit 1
}

capture() { tm capture-pane -p -t "$session" >"$work/screen" 2>/dev/null; }

# Wait up to $2 seconds (default 10) for the screen to match regex $1.
wait_for() {
  local pattern=$1 limit=${2:-10} waited=0
  while [ "$waited" -lt $((limit * 10)) ]; do
    capture
    if grep -Eq -- "$pattern" "$work/screen"; then
      return 0
    fi
    sleep 0.1
    waited=$((waited + 1))
  done
  return 1
}

lambda_shown() {
  grep -Eo 'lambda = [0-9]+\.[0-9]+' "$work/screen" | head -n 1 | awk '{print $3}'
}

tm new-session -d -s "$session" -x 100 -y 30 \
  "sh -c '\"$bin\"; echo EXIT:\$? > \"$work/exit\"'" \
  || fail "could not start tmux"

wait_for 'lambda = [0-9]' 15 || fail "the status line with lambda did not appear"
for panel in "Load plane" "Slip zones" "Tractions" "Locked-in slip" "Dissipation"; do
  grep -q "$panel" "$work/screen" || fail "panel '$panel' is not on screen"
done
before=$(lambda_shown)
[ -n "$before" ] || fail "could not read lambda"
echo "tmux_tui: panels shown, lambda = $before"

expected=$(awk -v l="$before" 'BEGIN { printf "%.2f", l + 0.05 }')
tm send-keys -t "$session" Right
wait_for "lambda = $expected" 5 || fail "after ->, lambda is $(lambda_shown), expected $expected"
grep -q "restarted from O" "$work/screen" || fail "the restart after -> is not announced"
echo "tmux_tui: -> raised lambda to $expected"

tm send-keys -t "$session" '?'
wait_for 'Keys' 5 || fail "? did not open the help"
for text in "run or pause" "one increment" "to the steady state" "quit"; do
  grep -q "$text" "$work/screen" || fail "the help lacks '$text'"
done
echo "tmux_tui: ? shows the help"

tm send-keys -t "$session" q
for _ in $(seq 1 50); do
  [ -f "$work/exit" ] && break
  sleep 0.1
done
[ -f "$work/exit" ] || fail "q did not end the program"
status=$(cat "$work/exit")
[ "$status" = "EXIT:0" ] || fail "q ended the program with $status, expected EXIT:0"
echo "tmux_tui: q quit with status 0"
echo "tmux_tui: ok"

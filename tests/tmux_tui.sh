#!/usr/bin/env bash
# The explorer in a real terminal: tmux at 100x30. It checks that the
# panels and lambda show, that -> raises lambda by 0.05, that ? shows the
# help, that , scrubs back into history, that L shows the event log, that
# Esc in the sweep view goes back (and q then asks), that q quits with
# status 0; then that --ascii draws ASCII only and Ctrl-C exits 130; and
# that SIGTERM leaves a sane terminal (icanon echo, main screen); and that
# Ctrl-Z and SIGTSTP give the terminal back to an interactive shell (prompt,
# main screen, icanon echo) and `fg` redraws the panels; that pausing at an
# advancing stick shows its episode slip; the guided tour's first two
# stops; the sweep table scrolling to the selected row; a save that will
# not overwrite without y; a custom transient's waypoints; the fretting
# profile (f) at 80x24; and the regime map's lambda_2 points arriving with
# the map. Builds nothing itself.
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

tm send-keys -t "$session" Escape
wait_for 'Load plane' 5 || fail "Esc did not close the help"

# Scrub back: pause, then three increments back.
tm send-keys -t "$session" Space
sleep 0.3
tm send-keys -t "$session" , , ,
wait_for ' history (cycle|transient) ' 5 || fail ", did not scrub back into history"
echo "tmux_tui: , scrubs back into history"
tm send-keys -t "$session" End

# The event log.
tm send-keys -t "$session" L
wait_for 'Event log' 5 || fail "L did not open the event log"
echo "tmux_tui: L shows the event log"
tm send-keys -t "$session" L
wait_for 'Load plane' 5 || fail "L did not close the event log"

# The sweep view: Esc goes back to stepping and does not quit.
tm send-keys -t "$session" v
wait_for 'sweep view' 10 || fail "v did not open the sweep view"
tm send-keys -t "$session" Escape
wait_for 'Load plane' 5 || fail "Esc in the sweep view did not go back to stepping"
[ -f "$work/exit" ] && fail "Esc in the sweep view ended the program"
echo "tmux_tui: Esc in the sweep view goes back"

tm send-keys -t "$session" q
# The sweep started by v may still be running: q asks first.
sleep 0.5
capture
if grep -q 'y/n' "$work/screen"; then
  tm send-keys -t "$session" y
fi
for _ in $(seq 1 50); do
  [ -f "$work/exit" ] && break
  sleep 0.1
done
[ -f "$work/exit" ] || fail "q did not end the program"
status=$(cat "$work/exit")
[ "$status" = "EXIT:0" ] || fail "q ended the program with $status, expected EXIT:0"
echo "tmux_tui: q quit with status 0"
tm kill-session -t "$session" >/dev/null 2>&1

# --ascii: nothing outside ASCII on screen; Ctrl-C exits 130.
rm -f "$work/exit"
tm new-session -d -s "$session" -x 100 -y 30 \
  "sh -c '\"$bin\" tui --ascii; echo EXIT:\$? > \"$work/exit\"; sleep 30'" \
  || fail "could not start tmux (ascii)"
wait_for 'lambda = [0-9]' 15 || fail "--ascii: the status line did not appear"
sleep 0.5
capture
if LC_ALL=C grep -q '[^ -~]' "$work/screen"; then
  fail "--ascii drew characters outside ASCII"
fi
echo "tmux_tui: --ascii draws ASCII only"
tm send-keys -t "$session" C-c
for _ in $(seq 1 50); do
  [ -f "$work/exit" ] && break
  sleep 0.1
done
[ -f "$work/exit" ] || fail "Ctrl-C did not end the program"
status=$(cat "$work/exit")
[ "$status" = "EXIT:130" ] || fail "Ctrl-C ended the program with $status, expected EXIT:130"
echo "tmux_tui: Ctrl-C exits 130"
tm kill-session -t "$session" >/dev/null 2>&1

# SIGTERM: the terminal is given back (canonical mode, echo, main screen).
rm -f "$work/exit"
tm new-session -d -s "$session" -x 100 -y 30 \
  "sh -c '\"$bin\"; echo EXIT:\$? > \"$work/exit\"; stty -a > \"$work/stty\"; sleep 30'" \
  || fail "could not start tmux (SIGTERM)"
wait_for 'lambda = [0-9]' 15 || fail "SIGTERM run: the status line did not appear"
shell_pid=$(tm display -p -t "$session" '#{pane_pid}')
pid=$(ps -o pid= --ppid "$shell_pid" | head -n 1 | tr -d ' ')
[ -n "$pid" ] || fail "could not find the explorer's process"
kill -TERM "$pid"
for _ in $(seq 1 50); do
  [ -f "$work/stty" ] && break
  sleep 0.1
done
[ -f "$work/stty" ] || fail "SIGTERM did not end the program"
status=$(cat "$work/exit")
[ "$status" = "EXIT:143" ] || fail "SIGTERM ended the program with $status, expected EXIT:143"
grep -Eq '(^| )icanon' "$work/stty" || fail "after SIGTERM the terminal is not in canonical mode: $(cat "$work/stty")"
grep -Eq '(^| )echo( |$)' "$work/stty" || fail "after SIGTERM the terminal does not echo: $(cat "$work/stty")"
alt=$(tm display -p -t "$session" '#{alternate_on}')
[ "$alt" = "0" ] || fail "after SIGTERM the alternate screen is still on"
echo "tmux_tui: SIGTERM restores the terminal (icanon echo, main screen), status 143"
tm kill-session -t "$session" >/dev/null 2>&1

# Ctrl-Z and SIGTSTP: the terminal goes back to an interactive shell
# (prompt, main screen, icanon echo), and `fg` redraws the explorer. Run
# from the shell directly, and through a wrapper that waits for it (as
# `cargo run` does): the whole job must stop, or the shell never gets the
# terminal back.

# Wait until the explorer ($pid) and its job are stopped and the terminal
# is handed back: the shell reports the job stopped on the main screen,
# and runs stty, which finds canonical mode and echo.
stopped_and_restored() { # $1: how it was stopped
  local waited=0 state="" alt=""
  while [ "$waited" -lt 100 ]; do
    state=$(ps -o stat= -p "$pid" | tr -d ' ')
    alt=$(tm display -p -t "$session" '#{alternate_on}')
    case "$state" in T*) [ "$alt" = "0" ] && break ;; esac
    sleep 0.1
    waited=$((waited + 1))
  done
  case "$state" in T*) ;; *) fail "after $1 the explorer is not stopped (state '$state')" ;; esac
  [ "$alt" = "0" ] || fail "after $1 the alternate screen is still on"
  wait_for 'Stopped' 5 || fail "after $1 the shell did not report the job stopped"
  rm -f "$work/stty"
  tm send-keys -t "$session" "stty -a > \"$work/stty\"" Enter
  for _ in $(seq 1 50); do
    [ -s "$work/stty" ] && break
    sleep 0.1
  done
  [ -s "$work/stty" ] || fail "after $1 the shell did not run stty (it has not got the terminal back)"
  grep -Eq '(^| )icanon' "$work/stty" || fail "after $1 the terminal is not in canonical mode: $(cat "$work/stty")"
  grep -Eq '(^| )echo( |$)' "$work/stty" || fail "after $1 the terminal does not echo: $(cat "$work/stty")"
}

# `fg` takes the terminal again and draws every panel afresh: the
# alternate screen is empty when re-entered, so what shows was redrawn.
# (`clear` first, so the next stop's report is the only one on screen.)
fg_redraws() { # $1: how it was stopped
  tm send-keys -t "$session" "clear; fg" Enter
  wait_for 'Slip zones' 10 || fail "after $1 and fg the explorer did not redraw"
  for panel in "Load plane" "Tractions" "Locked-in slip" "Dissipation" "lambda = "; do
    wait_for "$panel" 5 || fail "after $1 and fg '$panel' is not on screen"
  done
  [ "$(tm display -p -t "$session" '#{alternate_on}')" = "1" ] \
    || fail "after $1 and fg the explorer is not on the alternate screen"
  case "$(ps -o stat= -p "$pid" | tr -d ' ')" in
    T*) fail "after $1 and fg the explorer is still stopped" ;;
  esac
}

# $1: the command line that starts the explorer; $2: how many processes
# deep the explorer is below the shell (1 direct, 2 through a wrapper).
suspend_and_resume() {
  local line=$1 depth=$2 parent status
  rm -f "$work/exit" "$work/screen"
  tm new-session -d -s "$session" -x 100 -y 30 \
    "env PS1='tstp-prompt\$ ' bash --norc --noprofile -i" \
    || fail "could not start tmux (SIGTSTP)"
  wait_for 'tstp-prompt\$' 10 || fail "SIGTSTP run: the shell prompt did not appear"
  # The command alone on the line: a list (`bin; echo`) would run on when
  # the job stops. Its exit status is `fg`'s, read after it quits.
  tm send-keys -t "$session" "$line" Enter
  wait_for 'lambda = [0-9]' 15 || fail "SIGTSTP run ($line): the status line did not appear"
  parent=$(tm display -p -t "$session" '#{pane_pid}')
  for _ in $(seq 1 "$depth"); do
    pid=$(ps -o pid= --ppid "$parent" | head -n 1 | tr -d ' ')
    [ -n "$pid" ] || fail "could not find the explorer's process ($line)"
    parent=$pid
  done

  tm send-keys -t "$session" C-z
  stopped_and_restored "Ctrl-Z ($line)"
  echo "tmux_tui: Ctrl-Z gives the terminal back (prompt, main screen, icanon echo): $line"
  fg_redraws "Ctrl-Z ($line)"
  echo "tmux_tui: fg after Ctrl-Z redraws the panels: $line"

  kill -TSTP "$pid"
  stopped_and_restored "SIGTSTP ($line)"
  echo "tmux_tui: SIGTSTP gives the terminal back (prompt, main screen, icanon echo): $line"
  fg_redraws "SIGTSTP ($line)"
  echo "tmux_tui: fg after SIGTSTP redraws the panels: $line"

  # It still answers keys, and quits normally.
  tm send-keys -t "$session" q
  for _ in $(seq 1 50); do
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.1
  done
  kill -0 "$pid" 2>/dev/null && fail "q after fg did not end the program ($line)"
  tm send-keys -t "$session" "echo EXIT:\$? > \"$work/exit\"" Enter
  for _ in $(seq 1 50); do
    [ -s "$work/exit" ] && break
    sleep 0.1
  done
  [ -s "$work/exit" ] || fail "the shell did not report the exit status after q ($line)"
  status=$(cat "$work/exit")
  [ "$status" = "EXIT:0" ] || fail "q after fg ended the program with $status, expected EXIT:0 ($line)"
  echo "tmux_tui: q after fg quits with status 0: $line"
  tm kill-session -t "$session" >/dev/null 2>&1
}

suspend_and_resume "\"$bin\"" 1
suspend_and_resume "sh -c '\"$bin\"; exit \$?'" 2

# start "ARGS" [W H]: the explorer alone in a fresh session, run in the
# scratch folder (so a save lands there), its status written on exit.
start() {
  rm -f "$work/exit" "$work/screen"
  tm new-session -d -s "$session" -x "${2:-100}" -y "${3:-30}" \
    "sh -c 'cd \"$work\" && \"$bin\" $1; echo EXIT:\$? > \"$work/exit\"; sleep 30'" \
    || fail "could not start tmux ($1)"
}
# Quit, answering y if a sweep map would be lost, and close the session.
quit() {
  tm send-keys -t "$session" q
  sleep 0.3
  capture
  grep -q 'y/n' "$work/screen" && tm send-keys -t "$session" y
  for _ in $(seq 1 50); do
    [ -f "$work/exit" ] && break
    sleep 0.1
  done
  [ -f "$work/exit" ] || fail "q did not end the program ($1)"
  tm kill-session -t "$session" >/dev/null 2>&1
}

# Advancing stick: k chooses its events, e pauses at them, and the slip
# panel shows what the nodes locked in during their slip episode.
start "tui --nodes 64 --steps 200"
wait_for 'lambda = [0-9]' 15 || fail "advancing stick run: the status line did not appear"
tm send-keys -t "$session" k
wait_for 'events: advancing stick' 5 || fail "k did not choose advancing-stick events"
tm send-keys -t "$session" e
wait_for 'episode slip max' 20 || fail "paused at an advancing stick, the episode slip is not shown"
grep -Eq 'Episode slip|episode of the' "$work/screen" || fail "the slip panel does not zoom on the episode"
echo "tmux_tui: an advancing-stick event shows its episode slip"
quit "advancing stick"

# The guided tour: its first two stops, n moving on, Esc handing over.
start "tui --tour --nodes 64 --steps 200" 80 24
wait_for 'Tour 1/8: the stick diamond' 15 || fail "--tour did not open on its first stop"
tm send-keys -t "$session" n
wait_for 'Tour 2/8: advancing stick' 10 || fail "n did not move the tour to its second stop"
grep -q 'e:on' "$work/screen" || fail "the second stop does not pause at events"
tm send-keys -t "$session" Escape
# The stepping view's own footer is back (a pause at an event may have
# replaced the notice that says so), and the caption is gone.
wait_for 'c cycle' 5 || fail "Esc did not hand the case over (the stepping keys are not back)"
grep -q 'Tour 2/8' "$work/screen" && fail "the caption stayed after Esc"
echo "tmux_tui: the tour's first two stops, and Esc hands over"
quit "tour"

# The sweep view at 80x24: the table of transients scrolls to the
# selected row; s asks for a name and will not overwrite without y.
printf 'mine\n' > "$work/sweep-fig3.csv"
start "tui --nodes 32 --steps 100" 80 24
wait_for 'lambda = [0-9]' 15 || fail "sweep run: the status line did not appear"
tm send-keys -t "$session" v
wait_for 'sweep view' 10 || fail "v did not open the sweep view"
for _ in $(seq 1 19); do tm send-keys -t "$session" Down; done
wait_for '>7,-7' 5 || fail "the selected row 7,-7 is not on screen (the table did not scroll)"
grep -Eq 'at this x \([0-9]+-[0-9]+ of [0-9]+\)' "$work/screen" || fail "the table does not say which rows it shows"
echo "tmux_tui: the sweep table scrolls to the selected row"
tm send-keys -t "$session" s
wait_for 'save as: sweep-fig3.csv' 5 || fail "s did not ask for the file name"
tm send-keys -t "$session" Enter
wait_for 'overwrite\? y/N' 5 || fail "saving over an existing file did not ask first"
tm send-keys -t "$session" n
wait_for 'not saved' 5 || fail "n to overwrite? did not say the file was kept"
[ "$(cat "$work/sweep-fig3.csv")" = "mine" ] || fail "the existing file was replaced without y"
echo "tmux_tui: a save refuses to overwrite without y"
quit "sweep"

# A custom transient through two points (issue 66): the waypoints are on
# the load plane, and the run steps.
start "tui --initial-path \"-9.64640782328964,-6.282185307179586;1.9767925857663062,4.769947109627885\" --lambda 4.82 --nodes 64 --steps 200"
wait_for 'lambda = 4.82' 15 || fail "--initial-path: the explorer did not open"
grep -q '◆1' "$work/screen" && grep -q '◆2' "$work/screen" \
  || fail "--initial-path: the waypoints are not drawn on the load plane"
wait_for 'incr [1-9]' 10 || fail "--initial-path: the run does not step"
echo "tmux_tui: --initial-path draws its waypoints and steps"
quit "initial path"

# The fretting profile at 80x24: f opens it, it comes once a cycle has
# completed (the worker computes it beside the run) and names the hot
# spot; f again gives the instant's panels back.
start "tui --nodes 32 --steps 100" 80 24
wait_for 'lambda = [0-9]' 15 || fail "profile run: the status line did not appear"
tm send-keys -t "$session" f
wait_for 'hot spot|nothing slips in cycle' 20 || fail "f did not show the fretting profile of a completed cycle"
grep -q 'Slip amplitude' "$work/screen" || fail "the profile's slip amplitude panel is not on screen"
tm send-keys -t "$session" f
wait_for 'Tractions' 5 || fail "f again did not bring the tractions panel back"
echo "tmux_tui: f shows the fretting profile with its hot spot, and hides it"
quit "profile"

# The regime map at 120x40: lambda_2(phi) is solved beside the map's runs
# and its points are drawn as they arrive, before the map is done.
start "tui --nodes 32 --steps 100" 120 40
wait_for 'lambda = [0-9]' 15 || fail "regime run: the status line did not appear"
tm send-keys -t "$session" g
wait_for 'lambda_2 = [0-9]' 30 || fail "no point of lambda_2 came with the regime map"
grep -Eq '[0-9]+/[0-9]+ runs' "$work/screen" || fail "the regime map's progress is not on screen"
echo "tmux_tui: the regime map's lambda_2 points arrive with the map"
quit "regime"

# The terminal disappears (an SSH connection drops, the tmux server is
# killed): the explorer gets SIGHUP and must end, not run on without a
# terminal. Its own tmux server, so killing it touches nothing else.
hup="${session}-hup"
tmux -L "$hup" new-session -d -s "$hup" -x 80 -y 24 "\"$bin\"" \
  || fail "could not start tmux (hang-up)"
for _ in $(seq 1 150); do
  tmux -L "$hup" capture-pane -p -t "$hup" 2>/dev/null | grep -q 'lambda = [0-9]' && break
  sleep 0.1
done
hup_shell=$(tmux -L "$hup" display -p -t "$hup" '#{pane_pid}')
[ -n "$hup_shell" ] || fail "could not find the hang-up run's pane"
# The pane runs the explorer itself or a shell around it.
hup_pid=$(ps -o pid= --ppid "$hup_shell" | head -n 1 | tr -d ' ')
[ -n "$hup_pid" ] || hup_pid=$hup_shell
tmux -L "$hup" kill-server
gone=""
for _ in $(seq 1 50); do
  if ! kill -0 "$hup_pid" 2>/dev/null; then gone=1; break; fi
  sleep 0.1
done
if [ -z "$gone" ]; then
  kill -9 "$hup_pid" 2>/dev/null
  fail "the explorer ran on after its terminal was gone (SIGHUP)"
fi
echo "tmux_tui: the explorer ends when its terminal goes away"
echo "tmux_tui: ok"

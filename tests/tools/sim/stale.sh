#!/bin/bash
# A server killed with SIGKILL leaves /dev/shm/sh2000-NAME behind: clients
# are refused (the owner is dead), and the next sh2000-sim on the name
# says so, replaces it and serves.
. "$(dirname "$0")/../ctl/testlib.sh"
NAME=simstale-$$
start_sim "$NAME" || finish
expect 0 "$CTL" -d "sim:$NAME" enable x
stop_sim KILL
checks=$((checks + 1))
[ -e "/dev/shm/sh2000-$NAME" ] || fail "SIGKILL left no object (test cannot show recovery)"
expect 3 "$CTL" -d "sim:$NAME" status && err_has "^sh2000ctl: sim:$NAME: "
"${RT_CARD[@]}" "$SIM" "$NAME" >"$T/out" 2>"$T/err" &
P=$!
SIM_PIDS="$SIM_PIDS $P"
wait_for "the ready line of the replacing sh2000-sim" file_has '^ready$' "$T/out"
checks=$((checks + 1))
grep -q "^sh2000-sim: sim:$NAME: replaced /sh2000-$NAME left by a server that is gone$" "$T/err" ||
	fail "no replacement message: $(cat "$T/err")"
# a fresh card: nothing enabled
expect 0 "$CTL" -d "sim:$NAME" status --json &&
	json_check /state = idle /axes/0/enabled = false
kill -TERM $P
wait $P
SIM_PIDS=""
checks=$((checks + 1))
[ ! -e "/dev/shm/sh2000-$NAME" ] || fail "/dev/shm/sh2000-$NAME left after SIGTERM"
finish

#!/bin/bash
# sh2000-sim NAME: prints where it serves and "ready", several clients see
# one card, a second server on the name is refused, SIGTERM and SIGINT stop
# it cleanly and remove /dev/shm/sh2000-NAME, as does SIGHUP.
. "$(dirname "$0")/../ctl/testlib.sh"
NAME=simserve-$$

# stdout: where, then ready; --ready-fd is tested by start_sim
"${RT_CARD[@]}" "$SIM" "$NAME" >"$T/out1" 2>"$T/err1" &
P=$!
SIM_PIDS="$SIM_PIDS $P"
wait_for "the ready line of sh2000-sim $NAME" file_has '^ready$' "$T/out1"
checks=$((checks + 1))
grep -q "^sh2000-sim: serving sim:$NAME at /sh2000-$NAME (pid $P, real time)$" "$T/out1" &&
	grep -q '^ready$' "$T/out1" || fail "stdout: $(cat "$T/out1") $(cat "$T/err1")"
checks=$((checks + 1))
[ -e "/dev/shm/sh2000-$NAME" ] || fail "no /dev/shm/sh2000-$NAME while serving"
# a second server on the same name: refused, exit 3, the first unharmed
expect 3 "$SIM" "$NAME" && err_has "^sh2000-sim: sim:$NAME: already served by pid $P$"
# two clients, one card: one enables and moves, the other sees it
expect 0 "${CTL_RT[@]}" -d "sim:$NAME" enable z
expect 0 "${CTL_RT[@]}" -d "sim:$NAME" move z=2
expect 0 "${CTL_RT[@]}" -d "sim:$NAME" status --json &&
	json_check /axes/2/enabled = true /axes/2/cmd_mm '~' 2,1e-3
# monitor_at_zero: the monitor's last report has z at 0
monitor_at_zero() {
	tail -n 1 "$T/watch" | "$JSONQ" /axes/2/cmd_mm 2>/dev/null |
		awk '{ v = $1 } END { exit !(NR == 1 && v < 1e-3 && v > -1e-3) }'
}
# a monitor polling while another process commands, from before the move
# until after it (SIGTERM ends a watch)
"${CTL_RT[@]}" -d "sim:$NAME" status --json --watch 0.02 >"$T/watch" 2>&1 &
W=$!
# opening a handle issues commands (the library reads the timing and the
# scales): let the monitor's open finish before the mover's begins
wait_for "the monitor's first report" test -s "$T/watch"
# 0.2 s of motion: about ten of the monitor's reports
expect 0 "${CTL_RT[@]}" -d "sim:$NAME" move z=0 --feed 10
wait_for "the monitor's report of z back at 0" monitor_at_zero
kill -TERM $W
wait $W
rc=$?
checks=$((checks + 1))
[ $rc = 0 ] || fail "monitor: exit $rc after SIGTERM: $(cat "$T/watch")"
checks=$((checks + 1))
"$JSONQ" /axes/2/cmd_mm <"$T/watch" | awk '$1 > 0.05 && $1 < 1.95 { mid = 1 } { n++ }
	END { exit !(mid && n >= 3) }' || fail "monitor did not see the motion: $(cat "$T/watch")"
kill -TERM $P
wait $P
rc=$?
SIM_PIDS=""
checks=$((checks + 1))
[ $rc = 0 ] || fail "exit $rc after SIGTERM"
checks=$((checks + 1))
grep -Eq "^sh2000-sim: stopped after [0-9]+ servo cycles, /sh2000-$NAME removed$" "$T/out1" ||
	fail "no stop line: $(cat "$T/out1")"
checks=$((checks + 1))
[ ! -e "/dev/shm/sh2000-$NAME" ] || fail "/dev/shm/sh2000-$NAME left after SIGTERM"
expect 3 "$CTL" -d "sim:$NAME" status

# SIGINT, --free-run, --quiet
start_sim "$NAME" --free-run || finish
checks=$((checks + 1))
[ ! -s "$T/sim.out" ] || fail "--quiet printed: $(cat "$T/sim.out")"
expect 0 "${CTL_RT[@]}" -d "sim:$NAME" status --json
stop_sim INT
checks=$((checks + 1))
[ "$sim_rc" = 0 ] || fail "exit $sim_rc after SIGINT"
checks=$((checks + 1))
[ ! -e "/dev/shm/sh2000-$NAME" ] || fail "/dev/shm/sh2000-$NAME left after SIGINT"

# SIGHUP (the terminal it runs in closed): the same clean stop
start_sim "$NAME" || finish
stop_sim HUP
checks=$((checks + 1))
[ "$sim_rc" = 0 ] || fail "exit $sim_rc after SIGHUP"
checks=$((checks + 1))
[ ! -e "/dev/shm/sh2000-$NAME" ] || fail "/dev/shm/sh2000-$NAME left after SIGHUP"
finish

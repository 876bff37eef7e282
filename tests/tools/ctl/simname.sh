#!/bin/bash
# sh2000ctl against a card served by sh2000-sim (sim:NAME, real time): every
# subcommand, state kept between invocations, estop from a second process
# while another one moves, estop/reset, cleanup.
. "$(dirname "$0")/testlib.sh"
NAME=ctlname-$$
start_sim "$NAME" || finish
D=(-d "sim:$NAME")

# moving_past MM: the card runs a motion and x's set-point is past MM (a
# move another process streams is under way)
moving_past() {
	local v
	v=$("${CTL_OP[@]}" "${D[@]}" status --json 2>/dev/null | "$JSONQ" /state /axes/0/cmd_mm) ||
		return 1
	awk -v v="$v" -v mm="$1" 'BEGIN { split(v, f, "\t"); exit !(f[1] == "running" && f[2] > mm) }'
}
# heartbeat_past H: the card's heartbeat (word 3) is no longer H
heartbeat_past() {
	run "${CTL_RT[@]}" "${D[@]}" dump 3 && h2=$(printf '%s\n' "$out" | awk '{print $2}') &&
		[ -n "$h2" ] && [ "$h2" != "$1" ]
}

expect 0 "${CTL_RT[@]}" "${D[@]}" info && out_has "^device +sim:$NAME$" && out_has "real time"
expect 0 "${CTL_RT[@]}" "${D[@]}" status --json && json_check /state = idle
# state persists: enable in one process, see it in the next
expect 0 "${CTL_RT[@]}" "${D[@]}" enable x y
expect 0 "${CTL_RT[@]}" "${D[@]}" status --json &&
	json_check /axes/0/enabled = true /axes/1/enabled = true /axes/2/enabled = false /axes/3/enabled = false
expect 0 "${CTL_RT[@]}" "${D[@]}" move x=12.5 y=-3 --feed 200 && out_has "^x 12\.[0-9]+ mm$"
expect 0 "${CTL_RT[@]}" "${D[@]}" jog y 1.5
expect 0 "${CTL_RT[@]}" "${D[@]}" jog x --velocity -50 --time 0.1
expect 0 "${CTL_RT[@]}" "${D[@]}" status --json &&
	json_check /axes/0/cmd_mm '~' 7.5,1e-3 /axes/1/cmd_mm '~' -1.5,1e-3
expect 0 "${CTL_RT[@]}" "${D[@]}" status && out_has "^x +7\.[0-9]+ +7\.500000 "
expect 0 "${CTL_RT[@]}" "${D[@]}" disable y
expect 1 "${CTL_RT[@]}" "${D[@]}" move y=0 && err_has "^sh2000ctl: sim:$NAME: axis y is not enabled"
# parameters persist
expect 0 "${CTL_RT[@]}" "${D[@]}" params x ferr_limit=0.5
expect 0 "${CTL_RT[@]}" "${D[@]}" params x ferr_limit && out_has "^ferr_limit = 0.5$"
# dump shows the card's words, the heartbeat (word 3) advancing
expect 0 "${CTL_RT[@]}" "${D[@]}" dump 1-3 && h1=$(printf '%s\n' "$out" | awk '{print $4}') &&
	out_has "^0x001: 5348 $(printf %04x $((PROTO_VERSION))) [0-9a-f]{4}$"
checks=$((checks + 1))
if [ -z "${h1:-}" ]; then
	fail "dump 1-3 showed no heartbeat"
else
	wait_for "the heartbeat (word 3) to advance from $h1" heartbeat_past "$h1"
fi
# watch: reports at the interval, each with a later card cycle
expect 0 "${CTL_RT[@]}" "${D[@]}" status --json --watch 0.05 --count 3
checks=$((checks + 1))
json_column /card_cycle | awk 'NR == 1 { first = $1 } NR > 1 && $1 <= prev { bad = 1 }
	{ prev = $1; n++ } END { exit bad || n != 3 || prev - first < 500 }' || fail "watch: $out"
# home (quick: move near the switch first)
expect 0 "${CTL_RT[@]}" "${D[@]}" move x=-295
expect 0 "${CTL_RT[@]}" "${D[@]}" home x --timeout 20 && out_has "^x homed at"
expect 0 "${CTL_RT[@]}" "${D[@]}" status --json && json_check /axes/0/homed = true
# stop at rest
expect 0 "${CTL_RT[@]}" "${D[@]}" stop
# emergency stop from a second process while a move streams: the move ends
# with exit 4, the state stays latched across invocations until reset
"${CTL_RT[@]}" "${D[@]}" move x=40 --feed 20 >"$T/move.out" 2>"$T/move.err" &
MP=$!
wait_for "the move to x=40 to run" moving_past -1000
expect 0 "${CTL_OP[@]}" "${D[@]}" estop
wait $MP
mrc=$?
checks=$((checks + 1))
[ $mrc = 4 ] && grep -q "^sh2000ctl: sim:$NAME: emergency stop latched" "$T/move.err" ||
	fail "move during estop: exit $mrc, $(cat "$T/move.err")"
expect 4 "${CTL_RT[@]}" "${D[@]}" status && out_has "^state +estop"
expect 4 "${CTL_RT[@]}" "${D[@]}" status --json && json_check /state = estop /error != null
expect 4 "${CTL_RT[@]}" "${D[@]}" move x=1 && err_has "emergency stop"
expect 0 "${CTL_RT[@]}" "${D[@]}" reset
expect 0 "${CTL_RT[@]}" "${D[@]}" status --json &&
	json_check /state = idle /axes/0/enabled = true
# a stop from a second process while a long move streams: the move ends as
# sh2000-upload's run does (the runner sees the card discard the ring): exit
# 7, "stopped by another program", nothing latched, the next move works
"${CTL_RT[@]}" "${D[@]}" move x=200 --feed 20 >"$T/move.out" 2>"$T/move.err" &
MP=$!
wait_for "the move to x=200 to run" moving_past -1000
expect 0 "${CTL_OP[@]}" "${D[@]}" stop
wait $MP
mrc=$?
checks=$((checks + 1))
[ $mrc = 7 ] && grep -q "^sh2000ctl: sim:$NAME: stopped by another program (a STOP command); the card is at rest on the path$" "$T/move.err" ||
	fail "move during a foreign stop: exit $mrc, $(cat "$T/move.err")"
checks=$((checks + 1))
[ "$(wc -l <"$T/move.err")" = 1 ] || fail "a foreign stop said more than one line: $(cat "$T/move.err")"
expect 0 "${CTL_RT[@]}" "${D[@]}" status --json && json_check /state = idle /error = null
expect 0 "${CTL_RT[@]}" "${D[@]}" move x=1 && out_has "^x (0\.99|1\.00)"
# SIGINT to a moving sh2000ctl stops the card (no fault left behind)
"${CTL_RT[@]}" "${D[@]}" move x=40 --feed 20 >"$T/move.out" 2>"$T/move.err" &
MP=$!
wait_for "the move to x=40 to run past x=3" moving_past 3
kill -INT $MP
wait $MP
mrc=$?
checks=$((checks + 1))
[ $mrc = 7 ] && grep -q "interrupted: card stopped" "$T/move.err" || fail "SIGINT move: exit $mrc, $(cat "$T/move.err")"
expect 0 "${CTL_RT[@]}" "${D[@]}" status --json &&
	json_check /state = idle /faults = '[]' /axes/0/cmd_mm in 2,39
# a mover killed: the card stops on its own (its queue runs dry, or no
# host heartbeat); status's error line says it once, without the device
# (its first line names it) and without the code's summary repeated
"${CTL_RT[@]}" "${D[@]}" move x=200 --feed 20 >"$T/move.out" 2>"$T/move.err" &
MP=$!
wait_for "the move to x=200 to run past x=3" moving_past 3
kill -KILL $MP
wait $MP
card_faulted() { "${CTL_RT[@]}" "${D[@]}" status >/dev/null 2>&1; [ $? = 4 ]; }
wait_for "the card to stop on its own" card_faulted
expect 4 "${CTL_RT[@]}" "${D[@]}" status &&
	out_has '^error   (card stopped: no host heartbeat or segments within its host timeout|segment queue ran dry mid-motion: .*)$' &&
	out_lacks "^error   .*sim:$NAME" && out_lacks '^error   card stopped: .*card stopped'
expect 0 "${CTL_RT[@]}" "${D[@]}" reset + enable x
# the server goes under a watch: the watch says the card stopped
# answering (and asks for its server), not which call found it
"${CTL_RT[@]}" "${D[@]}" status --watch 0.05 >"$T/watch.out" 2>"$T/watch.err" &
WP=$!
watch_ran() { [ -s "$T/watch.out" ]; }
wait_for "the watch to print" watch_ran
stop_sim TERM
wait $WP
wrc=$?
checks=$((checks + 1))
[ $wrc = 1 ] && grep -q "^sh2000ctl: sim:$NAME: the card is not answering: card heartbeat stuck .*is the sh2000-sim serving it still running?$" "$T/watch.err" ||
	fail "watch of a server that went: exit $wrc, $(cat "$T/watch.err")"
checks=$((checks + 1))
! grep -q "get parameter\|status: " "$T/watch.err" || fail "watch named a call: $(cat "$T/watch.err")"
checks=$((checks + 1))
[ "$sim_rc" = 0 ] || fail "sh2000-sim exit $sim_rc after SIGTERM"
checks=$((checks + 1))
[ ! -e "/dev/shm/sh2000-$NAME" ] || fail "/dev/shm/sh2000-$NAME left behind"
expect 3 "${CTL_RT[@]}" "${D[@]}" status && err_has "^sh2000ctl: sim:$NAME: "
finish

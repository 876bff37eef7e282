#!/bin/bash
# sh2000ctl home on a served card (sim:NAME, real time) ends like jog and
# move: a SIGINT while the card homes, or --timeout running out, stops the
# card (a controlled STOP) and waits for rest, so nothing is latched (the
# card needs a polling host while it homes: a tool that just went would
# leave a host heartbeat timeout). "homed at" gives the set-point apart
# from the encoder and the following error still settling.
. "$(dirname "$0")/testlib.sh"
NAME=ctlhome-$$
start_sim "$NAME" || finish
D=(-d "sim:$NAME")

# card_is STATE: the card's state now is STATE (for wait_for), asked as an
# operator beside the host that homes or moves
card_is() {
	[ "$("${CTL_OP[@]}" "${D[@]}" status --json 2>/dev/null | tail -n 1 |
		"$JSONQ" /state 2>/dev/null)" = "$1" ]
}
# at_rest_clean: idle, nothing latched, x not homed, x enabled
at_rest_clean() {
	expect 0 "${CTL_RT[@]}" "${D[@]}" status --json &&
		json_check /state = idle /faults = '[]' /error = null \
			/axes/0/homed = false /axes/0/enabled = true
}

expect 0 "${CTL_RT[@]}" "${D[@]}" enable x + move x=20
# SIGINT while homing: exit 7, the card stopped at rest, nothing latched
"${CTL_RT[@]}" "${D[@]}" home x >"$T/home.out" 2>"$T/home.err" &
HP=$!
wait_for "the card to home" card_is homing
kill -INT $HP
wait $HP
hrc=$?
checks=$((checks + 1))
[ $hrc = 7 ] && grep -q "^sh2000ctl: sim:$NAME: interrupted: homing stopped, card at rest$" "$T/home.err" ||
	fail "SIGINT home: exit $hrc, $(cat "$T/home.err")"
at_rest_clean
# stays clean: a card left homing without a host latches a heartbeat
# timeout within host_timeout_ms; wait longer than that and look again
expect 0 "${CTL_RT[@]}" "${D[@]}" params global host_timeout_ms && ht=${out#*= }
"${CTL_RT[@]}" "${D[@]}" status --json --watch "$(awk -v t="${ht:-100}" 'BEGIN { print 3 * t / 1000 }')" --count 2 >/dev/null 2>&1
at_rest_clean
# --timeout running out: exit 1 with the reason, the card stopped, clean
expect 1 "${CTL_RT[@]}" "${D[@]}" home x --timeout 0.2 &&
	err_has "^sh2000ctl: sim:$NAME: home: not homed after 0.2 s \(--timeout\): homing stopped, card at rest$"
at_rest_clean
"${CTL_RT[@]}" "${D[@]}" status --json --watch "$(awk -v t="${ht:-100}" 'BEGIN { print 3 * t / 1000 }')" --count 2 >/dev/null 2>&1
at_rest_clean
# to the end: set-point 0 at the home point, encoder and following error
# printed apart (they agree: set-point - encoder = following error)
expect 0 "${CTL_RT[@]}" "${D[@]}" move x=-290
expect 0 "${CTL_RT[@]}" "${D[@]}" home x --timeout 20 &&
	out_has "^x homed at 0\.000000 mm \(set-point; encoder -?[0-9.]+ mm, following error -?[0-9.]+ mm\)$"
checks=$((checks + 1))
printf '%s\n' "$out" | awk '{ gsub(/[(),;]/, ""); e = $8; f = $12; d = -e - f; if (d < 0) d = -d; exit !(d < 2e-6 && (e < 0 ? -e : e) < 0.01) }' ||
	fail "homed line: encoder and following error disagree: $out"
# while another program holds the motion: its holder, one "home:" prefix
"${CTL_RT[@]}" "${D[@]}" move x=40 --feed 20 >"$T/move.out" 2>"$T/move.err" &
MP=$!
wait_for "the move to run" card_is running
expect 1 "${CTL_OP[@]}" "${D[@]}" home x &&
	err_has "^sh2000ctl: sim:$NAME: home: the motion is held by sh2000ctl \(pid $MP\); it has to finish or close the card first$"
expect 0 "${CTL_OP[@]}" "${D[@]}" stop
wait $MP
# a disabled axis: the hint, not the card's raw refusal
expect 0 "${CTL_RT[@]}" "${D[@]}" disable x
expect 1 "${CTL_RT[@]}" "${D[@]}" home x &&
	err_has "^sh2000ctl: sim:$NAME: axis x is not enabled \(sh2000ctl enable x\): nothing moved$"
finish

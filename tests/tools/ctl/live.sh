#!/bin/bash
# Live parameters, as the protocol's parameter table owns them: while a
# program runs on a served card, the feed override (time_scale) is taken
# and the run slows; a parameter that is not live is refused with the
# table's reason, naming it and the live ones, and nothing is set.
. "$(dirname "$0")/testlib.sh"
: "${UPLOAD:?UPLOAD must name sh2000-upload}"
NAME=ctllive-$$
start_sim "$NAME" || finish
D=(-d "sim:$NAME")

# card_is STATE: the card's state now is STATE (for wait_for); like the
# parameter changes, asked as an operator beside the streaming upload
card_is() {
	[ "$("${CTL_OP[@]}" "${D[@]}" status --json 2>/dev/null | tail -n 1 |
		"$JSONQ" /state 2>/dev/null)" = "$1" ]
}

expect 0 "${CTL_RT[@]}" "${D[@]}" enable x
# 40 mm at 10 mm/s: 4 s planned, at full rate
printf 'G21 G90 G64\nG1 X40 F600\nM2\n' >"$T/slow.ngc"
"${RT_HOST[@]}" "$UPLOAD" -q "${D[@]}" "$T/slow.ngc" >"$T/up.out" 2>"$T/up.err" &
UP=$!
wait_for "the card to run the program" card_is running
expect 0 "${CTL_OP[@]}" "${D[@]}" params global time_scale=5000
expect 0 "${CTL_OP[@]}" "${D[@]}" params global time_scale && out_has "^time_scale = 5000$"
# not live: refused with the table's reason, nothing set
expect 0 "${CTL_OP[@]}" "${D[@]}" params x vmax && vmax_before=$out
expect 1 "${CTL_OP[@]}" "${D[@]}" params x vmax=100 &&
	err_has "^sh2000ctl: sim:$NAME: card is running: vmax cannot change while the card moves; only live parameters \(kp ti td kvff kaff ferr_limit host_timeout_ms status_period time_scale time_ramp_ms gantry_kp gantry_ti gantry_td gantry_skew_limit\) may change now; nothing set$"
expect 0 "${CTL_OP[@]}" "${D[@]}" params x vmax && [ "$out" = "$vmax_before" ] ||
	fail "vmax changed after a refusal: '$vmax_before' -> '$out'"
wait $UP
urc=$?
checks=$((checks + 1))
[ $urc = 0 ] || fail "sh2000-upload exit $urc: $(cat "$T/up.err")"
# the card's time against the plan: a run at half rate for most of its
# length takes well over the planned 4 s of card time
# (back from X40 to X0, the same 4 s)
printf 'G21 G90 G64\nG1 X0 F600\nM2\n' >"$T/back.ngc"
"${RT_HOST[@]}" "$UPLOAD" "${D[@]}" "$T/back.ngc" >"$T/up2.out" 2>"$T/up2.err" &
UP=$!
wait_for "the card to run the program" card_is running
expect 0 "${CTL_OP[@]}" "${D[@]}" params global time_scale=5000
wait $UP
checks=$((checks + 1))
read -r card planned < <(sed -nE 's/^  time +([0-9.]+) s of card time \(planned ([0-9.]+) s\)$/\1 \2/p' "$T/up2.out")
awk -v c="${card:-0}" -v p="${planned:-0}" 'BEGIN { exit !(p > 3.9 && c > 1.5 * p) }' ||
	fail "run at time_scale 5000: ${card:-?} s of card time for ${planned:-?} s planned (want > 1.5x): $(cat "$T/up2.out" "$T/up2.err")"
expect 0 "${CTL_OP[@]}" "${D[@]}" params global time_scale=10000
finish

#!/bin/bash
# sh2000ctl: every subcommand against the in-process `sim` card (a fresh
# card at every invocation: '+' chains commands on one card).
. "$(dirname "$0")/testlib.sh"
S=(-d sim)

expect 0 "$CTL" "${S[@]}" info && out_has "^device +sim$" &&
	out_has "^card protocol +$PMAJ\.$PMIN$" && out_has "coarse period 2000 us, 20 fine steps" &&
	out_has "^scale +x 100000, y 100000, z 100000, a 100000 counts/mm$" &&
	out_has "^port cycles +[0-9]+ clears"
expect 0 "$CTL" "${S[@]}" status && out_has "^state +idle +faults -" &&
	out_has "^x +0\.000000 +0\.000000 +0\.000000 +0 +- +-$"
expect 0 "$CTL" "${S[@]}" status --json &&
	json_check /device = sim /state = idle /faults = '[]' /faulted = false /error = null /queue_free = 64 \
		/axes/0/axis = x /axes/1/axis = y /axes/2/axis = z /axes/3/axis = a
expect 0 "$CTL" "${S[@]}" status --json --watch 0.01 --count 3 &&
	{ checks=$((checks + 1)); [ "$(printf '%s\n' "$out" | wc -l)" = 3 ] ||
		fail "watch --count 3 gave $(printf '%s\n' "$out" | wc -l) lines"; }
checks=$((checks + 1))
json_column /card_cycle | awk 'NR > 1 && $1 <= prev { bad = 1 } { prev = $1; n++ }
	END { exit bad || n != 3 }' || fail "watch: card cycles do not advance: $out"
expect 0 "$CTL" "${S[@]}" status --watch 0.01 --count 2 &&
	{ checks=$((checks + 1)); [ "$(printf '%s\n' "$out" | grep -c '^device')" = 2 ] ||
		fail "status --watch --count 2 printed $(printf '%s\n' "$out" | grep -c '^device') tables"; }

# enable / disable
expect 0 "$CTL" "${S[@]}" enable x,z + status --json &&
	json_check /axes/0/enabled = true /axes/1/enabled = false /axes/2/enabled = true /axes/3/enabled = false
expect 0 "$CTL" "${S[@]}" enable all + disable y a + status --json &&
	json_check /axes/0/enabled = true /axes/1/enabled = false /axes/2/enabled = true /axes/3/enabled = false

# move: absolute, coordinated, with and without feed
expect 0 "$CTL" "${S[@]}" enable x y + move x=10 y=-5 --feed 50 + status --json &&
	json_check /axes/0/cmd_mm '~' 10,1e-4 /axes/1/cmd_mm '~' -5,1e-4 \
		/axes/0/pos_mm '~' 10,0.01 /axes/1/pos_mm '~' -5,0.01 /state = idle
# (the encoder as the move ends: within a micrometre of the set-point,
# on either side while the servo settles)
expect 0 "$CTL" "${S[@]}" enable x + move x=20 && out_has "^x (20\.000|19\.999)[0-9]+ mm$"
# a disabled axis, a target outside the soft limits: nothing moves
expect 1 "$CTL" "${S[@]}" move x=1 && err_has "^sh2000ctl: sim: axis x is not enabled" &&
	err_has "new in every program: sh2000ctl -d sim enable x \+ \.\.\."
expect 1 "$CTL" "${S[@]}" enable x + params x soft_max=5 + move x=6 &&
	err_has "^sh2000ctl: sim: target: X 6.0000 mm is beyond the soft limit 5.0000 mm"
# into the hard limit (the model's switch is 305 mm from the start): a
# latched fault, exit 4
expect 4 "$CTL" "${S[@]}" enable x + move x=320 && err_has "^sh2000ctl: sim: axis x: limit switch \(axis faults 0x0004\): the card disabled the axis$"

# jog: a distance, a velocity for a time
expect 0 "$CTL" "${S[@]}" enable y + jog y -2.5 + status --json &&
	json_check /axes/1/cmd_mm '~' -2.5,1e-4
# the encoder where the jog ended (its set-point is exact: jog checks it),
# within 0.1 um of 3 mm, whichever side the motor settles on
expect 0 "$CTL" "${S[@]}" enable y + jog y 3 --speed 10 &&
	out_has "^y (3\.0000|2\.9999)[0-9]* mm$"
expect 0 "$CTL" "${S[@]}" enable z + jog z --velocity -20 --time 0.5 + status --json &&
	json_check /axes/2/cmd_mm in -10.5,-9.5
expect 1 "$CTL" "${S[@]}" jog z 1 && err_has "axis z is not enabled"
# soft limits: a target right at the limit is reached (the planner's
# overshooting control points are clamped, the card rejects none), a
# velocity jog ends at the limit, a jog from the limit outwards is refused
expect 0 "$CTL" "${S[@]}" enable x y + params x soft_min=-3 soft_max=2 + move x=-3 y=50 + \
	move x=2 y=0 --feed 300 + jog x -5 + status --json &&
	json_check /state = idle /axes/0/cmd_mm '~' -3,1e-6 /axes/1/cmd_mm '~' 0,1e-6
expect 0 "$CTL" "${S[@]}" enable x + params x soft_max=2 + jog x --velocity 20 --time 1 + \
	status --json && json_check /state = idle /axes/0/cmd_mm '~' 2,1e-6
expect 1 "$CTL" "${S[@]}" enable x + params x soft_max=2 + move x=2 + jog x --velocity 5 --time 1 &&
	err_has "^sh2000ctl: sim: axis x is at its soft limit: nothing moved$"
expect 1 "$CTL" "${S[@]}" enable x + params x soft_max=2 + jog x 2.5 &&
	err_has "target: X 2.5000 mm is beyond the soft limit 2.0000 mm"

# home (card time: the model's home switch is 300 mm below the start)
expect 0 "$CTL" "${S[@]}" enable x + move x=-290 + home x + status --json &&
	out_has "^x homed at" &&
	json_check /axes/0/state has homed /axes/0/homed = true /axes/0/pos_mm '~' 0,0.01
expect 0 "$CTL" "${S[@]}" enable a + move a=-290 + home a --index + status --json &&
	json_check /axes/3/state has homed /axes/3/state has index
expect 1 "$CTL" "${S[@]}" home x && err_has "^sh2000ctl: sim: axis x is not enabled \(the in-process card is new in every program: sh2000ctl -d sim enable x \+ \.\.\.\): nothing moved$"
# index: the latch armed while the card moves (the mark at the switch,
# 300 mm below the start), masked by the switch, missed, refused
expect 0 "$CTL" "${S[@]}" enable x + move x=-299.5 + index x --mask + \
	jog x --velocity -1 --time 2 + index x --wait + status --json &&
	out_has "^x index armed \(arm 1\)$" &&
	out_has "^x index at -300\.000000 mm \(cycle [0-9]+\)$" &&
	json_check /axes/0/state has index-latched
expect 1 "$CTL" "${S[@]}" enable x + index x --mask --within 0.5 + jog x -1 + index x --wait &&
	err_has "^sh2000ctl: x: no index mark within the arm's travel$"
expect 1 "$CTL" "${S[@]}" index x && err_has "^sh2000ctl: sim: index: .*axis not enabled"
expect 2 "$CTL" "${S[@]}" index x --within -1 && err_has "not a positive distance"

# stop, estop, reset
expect 0 "$CTL" "${S[@]}" enable x + stop + status --json && json_check /state = idle
expect 4 "$CTL" "${S[@]}" enable x + estop + status --json &&
	json_check /state = estop /fault_bits = 4 /faulted = true /error != null \
		/first_fault/fault = "emergency stop" /first_fault/bit = 4 \
		/first_fault/axis = null
expect 4 "$CTL" "${S[@]}" enable x + estop + status && out_has "^state +estop" &&
	out_has "^first fault: emergency stop, cycle [0-9]+$"
expect 4 "$CTL" "${S[@]}" enable x + estop + move x=1 && err_has "sim: cannot move: emergency stop"
expect 4 "$CTL" "${S[@]}" estop + enable x && err_has "^sh2000ctl: sim: enable: "
expect 0 "$CTL" "${S[@]}" enable x + estop + reset + status --json &&
	json_check /state = idle /faults = '[]' /axes/0/enabled = true /first_fault = null
expect 0 "$CTL" "${S[@]}" enable x + estop + reset + move x=1 && out_has "^x (1\.000|0\.999)"

# dump: offsets in hex, 8 words a line, the magic at word 1
expect 0 "$CTL" "${S[@]}" dump 0-9 && {
	checks=$((checks + 1))
	[ "$(printf '%s\n' "$out" | sed -n 1p | cut -c1-15)" = "0x000: 0000 534" ] ||
		fail "dump 0-9 first line: $out"
	printf '%s\n' "$out" | grep -Eq '^0x000:( [0-9a-f]{4}){8}$' || fail "dump line 1: $out"
	printf '%s\n' "$out" | grep -Eq '^0x008:( [0-9a-f]{4}){2}$' || fail "dump line 2: $out"
	[ "$(printf '%s\n' "$out" | wc -l)" = 2 ] || fail "dump 0-9: not 2 lines: $out"
}
expect 0 "$CTL" "${S[@]}" dump 1 0x40+3 1023 && {
	checks=$((checks + 1))
	[ "$out" = "$(printf '0x001: 5348\n0x040: 0000 0000 0000\n0x3ff: 0000')" ] ||
		fail "dump 1 0x40+3 1023: $out"
}
expect 0 "$CTL" "${S[@]}" dump && {
	checks=$((checks + 1))
	[ "$(printf '%s\n' "$out" | wc -l)" = 128 ] || fail "dump: not 128 lines"
	printf '%s\n' "$out" | grep -Evq '^0x[0-9a-f]{3}:( [0-9a-f]{4}){8}$' &&
		fail "dump: a line out of format"
	printf '%s\n' "$out" | tail -1 | grep -q '^0x3f8:' || fail "dump: last line not 0x3f8"
}
finish

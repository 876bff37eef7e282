#!/bin/bash
# sh2000-tune on a card served by sh2000-sim: after a step test and after
# one aborted on the following-error limit, sh2000ctl (a second program)
# finds the limits as they were, nothing latched, the axis still enabled
# and its set-point at the start.
. "$(dirname "$0")/../ctl/testlib.sh"
: "${TUNE:?TUNE must name sh2000-tune}"
name=tune$$
S=(-d "sim:$name")
start_sim "$name" || finish

expect 0 "$CTL" "${S[@]}" enable x + move x=1
expect 0 "$CTL" "${S[@]}" params x ferr_limit dac_limit
before=$out
expect 0 "$TUNE" "${S[@]}" x --step 0.02 --dac-max 500 --ferr-max 0.05 &&
	out_has '^back at the start +1\.000000 mm$'
expect 0 "$CTL" "${S[@]}" params x ferr_limit dac_limit
checks=$((checks + 1))
[ "$out" = "$before" ] || fail "limits after the step: $out, before: $before"
expect 5 "$TUNE" "${S[@]}" x --step -0.5 --ferr-max 0.0002 &&
	out_has '^back at the start +1\.000000 mm$'
expect 0 "$CTL" "${S[@]}" params x ferr_limit dac_limit
checks=$((checks + 1))
[ "$out" = "$before" ] || fail "limits after the abort: $out, before: $before"
expect 0 "$CTL" "${S[@]}" status --json &&
	json_check /state = idle /faults = '[]' /axes/0/enabled = true /axes/0/cmd_mm '~' 1,1e-9
stop_sim
finish

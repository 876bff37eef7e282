#!/bin/bash
# sh2000-sim --geometry KIND and --tool-file PATH: the served card's machine
# with the card model's default geometric errors, and the simulated
# interferometer's reading written when the server stops. Usage errors
# exit 2; the start line names the geometry; on a perfect machine the tool
# is where the carriages are, with the default errors it is microns away
# (X: pitch and squareness), and the same again after a move of X by 1 mm
# (the scale's pitch is not the tool's).
. "$(dirname "$0")/../ctl/testlib.sh"
NAME=simgeo-$$

expect 2 "$SIM" --geometry perfect n && err_has "--geometry: 'perfect' is not none or default"
expect 0 "$SIM" --help && out_has "--geometry KIND" && out_has "--tool-file PATH"

"${RT_CARD[@]}" "$SIM" --geometry default "$NAME" >"$T/out1" 2>"$T/err1" &
P=$!
SIM_PIDS="$SIM_PIDS $P"
wait_for "the ready line of sh2000-sim --geometry default" file_has '^ready$' "$T/out1"
checks=$((checks + 1))
grep -q "^sh2000-sim: serving sim:$NAME at /sh2000-$NAME (pid $P, real time, geometry default)$" "$T/out1" ||
	fail "stdout: $(cat "$T/out1") $(cat "$T/err1")"
kill -TERM $P
wait $P
SIM_PIDS=""

# tool X Y Z A of a server started with OPTIONS, after X moved by MM
tool_after() {
	local mm=$1
	shift
	start_sim "$NAME" --tool-file "$T/tool" "$@" || finish
	[ "$mm" = 0 ] ||
		expect 0 "${CTL_RT[@]}" -d "sim:$NAME" enable x + move x="$mm" --feed 100
	stop_sim
	checks=$((checks + 1))
	[ "$sim_rc" = 0 ] && grep -Eq '^tool( -?[0-9]+\.[0-9]{6}){4}$' "$T/tool" ||
		fail "--tool-file: exit $sim_rc, $(cat "$T/tool" "$T/sim.err" 2>&1)"
	cut -d' ' -f2- "$T/tool"
}
# far: |a - b| in X above lo and below hi (mm)
far() {
	awk -v a="$1" -v b="$2" -v lo="$3" -v hi="$4" \
		'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d > lo && d < hi) }'
}

perfect=$(tool_after 0)
wrong=$(tool_after 0 --geometry default)
checks=$((checks + 1))
far "${wrong%% *}" "${perfect%% *}" 0.002 0.1 ||
	fail "at rest: tool X $wrong with the default errors, $perfect without: not microns apart"
moved=$(tool_after 1 --geometry none)
checks=$((checks + 1))
far "${moved%% *}" "${perfect%% *}" 0.9999 1.0001 ||
	fail "perfect machine: X moved 1 mm, the tool $perfect -> $moved"
moved_wrong=$(tool_after 1 --geometry default)
checks=$((checks + 1))
far "${moved_wrong%% *}" "${wrong%% *}" 0.99 1.01 && ! far "${moved_wrong%% *}" "${wrong%% *}" 0.9999 1.0001 ||
	fail "default errors: X moved 1 mm by its scale, the tool $wrong -> $moved_wrong: not a pitch error"

# a tool file that cannot be written: said, exit 1
start_sim "$NAME" --tool-file "$T/no/such/dir/tool" || finish
stop_sim
checks=$((checks + 1))
[ "$sim_rc" = 1 ] && grep -q -- "--tool-file $T/no/such/dir/tool: No such file or directory" "$T/sim.err" ||
	fail "unwritable --tool-file: exit $sim_rc, $(cat "$T/sim.err")"
finish

#!/bin/bash
# sh2000-sim --gantry A+B[:C]: the served card's axes A and B drive one beam.
# Usage errors exit 2; the start line names the gantry; a card served with
# it has the beam's yaw stiffness: side z, disabled (DAC 0), is dragged
# along by the beam when side y moves, where a card served without it
# leaves z where it was.
. "$(dirname "$0")/../ctl/testlib.sh"
NAME=simgantry-$$

expect 2 "$SIM" --gantry y n && err_has "--gantry: 'y' is not A\+B or A\+B:C"
expect 2 "$SIM" --gantry y+y n && err_has "--gantry y\+y: the sides are not two different axes"
expect 2 "$SIM" --gantry y+q n && err_has "the sides are not two different axes"
expect 2 "$SIM" --gantry y+z:z n && err_has "--gantry y\+z:z: the carriage's axis 'z' is not an axis other than the sides"
expect 2 "$SIM" --gantry y+z/x n && err_has "is not A\+B or A\+B:C"
expect 0 "$SIM" --help && out_has "--gantry A\+B\[:C\]"

# the start line: sides and carriage (default: the first other axis)
"${RT_CARD[@]}" "$SIM" --gantry x+z "$NAME" >"$T/out1" 2>"$T/err1" &
P=$!
SIM_PIDS="$SIM_PIDS $P"
wait_for "the ready line of sh2000-sim --gantry x+z" file_has '^ready$' "$T/out1"
checks=$((checks + 1))
grep -q "^sh2000-sim: serving sim:$NAME at /sh2000-$NAME (pid $P, real time, gantry x+z carriage y)$" "$T/out1" ||
	fail "stdout: $(cat "$T/out1") $(cat "$T/err1")"
kill -TERM $P
wait $P
SIM_PIDS=""

# z_pos: the served card's axis z position, mm (status --json)
z_pos() {
	"${CTL_RT[@]}" -d "sim:$NAME" status --json | "$JSONQ" /axes/2/pos_mm
}
# z_dragged: z has moved more than 0.3 mm (the beam pulls it towards y)
z_dragged() {
	awk -v z="$(z_pos)" 'BEGIN { exit !(z > 0.3) }'
}

# y moves 1 mm: with the gantry z follows through the beam
start_sim "$NAME" --gantry y+z:- || finish
# the side carries the beam and the carriage (13 kg; the default loop is
# for 2): a gentle acceleration keeps its following error in bounds
expect 0 "${CTL_RT[@]}" -d "sim:$NAME" params y amax=200 + enable y + move y=1 --feed 100
wait_for "axis z dragged by the beam" z_dragged
stop_sim

# without it z stays where it was, to the count
start_sim "$NAME" || finish
expect 0 "${CTL_RT[@]}" -d "sim:$NAME" params y amax=200 + enable y + move y=1 --feed 100 + status --json &&
	json_check /axes/1/cmd_mm '~' 1,1e-6 /axes/2/pos_mm = 0
stop_sim
finish

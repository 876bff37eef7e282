#!/bin/bash
# The sides of a gantry pair move together: on a card served with
# --gantry y+z and the sample's pair (configs/sh2000-gantry), both sides
# enabled, a jog or move of one side alone and a program that moves them
# by different distances are refused with the pair named, nothing moved;
# the same distance on both runs; with one side disabled the other moves
# alone (and drags it, as the beam does).
. "$(dirname "$0")/testlib.sh"
NAME=ctlgantry-$$
PARAMS=$(cd "$(dirname "$0")/../../.." && pwd)/configs/sh2000-gantry/gantry.params
G=("${CTL_RT[@]}" -d "sim:$NAME")

start_sim "$NAME" --gantry y+z || finish
expect 0 "${G[@]}" params load "$PARAMS" + enable y z
expect 1 "${G[@]}" jog y 2 &&
	err_has "Y and Z are one gantry beam \(gantry_pair\): here Y has moved [0-9.]+ mm and Z 0\.000000 mm since the motion began"
expect 1 "${G[@]}" move z=1
# nothing moved: both set-points where they were
expect 0 "${G[@]}" status --json &&
	json_check /axes/1/cmd_mm = 0 /axes/2/cmd_mm = 0 /state = idle
expect 0 "${G[@]}" move y=1 z=1 + status --json &&
	json_check /axes/1/cmd_mm '~' 1,1e-6 /axes/2/cmd_mm '~' 1,1e-6
# a program: the first pass finds the block, nothing moves
printf 'G21 G90\nG1 Y2 Z2 F1200\nG1 Y3\nM2\n' >"$T/apart.ngc"
expect 5 "${RT_HOST[@]}" "$UPLOAD" -d "sim:$NAME" "$T/apart.ngc" &&
	err_has "apart\.ngc:3: error: Y and Z are one gantry beam" &&
	err_has "nothing moved"
expect 0 "${G[@]}" status --json &&
	json_check /axes/1/cmd_mm '~' 1,1e-6 /axes/2/cmd_mm '~' 1,1e-6
printf 'G21 G90\nG1 Y2 Z2 F1200\nM2\n' >"$T/together.ngc"
expect 0 "${RT_HOST[@]}" "$UPLOAD" -d "sim:$NAME" -q "$T/together.ngc"
# one side disabled: the pair is not coupled, the other side may move
expect 0 "${G[@]}" disable z + jog y 0.1
stop_sim
finish

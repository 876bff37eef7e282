#!/bin/bash
# sh2000ctl comp and sh2000-comp as a user runs them, on the in-process
# card (`-d sim`, one card per sh2000ctl run, sub-commands joined with +):
# load, show, clear; refusals name FILE:LINE, exit 5 and change nothing;
# a laser CSV made into a table; a calibration whose tables load.
# The helpers are the tools' tests' (tests/tools/ctl/testlib.sh).
: "${COMP:?COMP must name sh2000-comp}"
. "$(dirname "$0")/../tools/ctl/testlib.sh"

printf 'id 0x00c0ffee\npitch X\n-10 0\n0 0.001\n10 0.0005\n' >"$T/good.comp"
printf 'pitch X\n0 0\n1 0.001\n1 0.002\n' >"$T/order.comp"
printf 'pitch X\n0 0\n1 0.001\n1.001 0.011\n2 0.011\n' >"$T/jump.comp"

expect 0 "$CTL" -d sim comp load "$T/good.comp" + comp show "$T/good.comp"
out_has 'tables: active, 1 table\(s\), id 0x00c0ffee'
out_has 'good.comp: sum 0x[0-9a-f]+: the active tables'

for bad in order:4 jump:4; do
	name=${bad%%:*} line=${bad##*:}
	expect 5 "$CTL" -d sim comp load "$T/good.comp" + comp load "$T/$name.comp"
	err_has "$name.comp:$line: .*nothing changed on the card"
	# the same card after the refusal: still the good tables
	run "$CTL" -d sim comp load "$T/good.comp" + comp load "$T/$name.comp" + comp show
	out_has 'tables: active, 1 table\(s\), id 0x00c0ffee'
done

# the card judges soft limits on nominal positions and adds the tables
# after: load says each axis' correction inside the soft limits, and warns
# (exit unchanged) when a soft limit's corrected position lies beyond it
printf 'pitch X\n-100 0.5\n0 0.5\n100 0.5\n' >"$T/off.comp"
expect 0 "$CTL" -d sim params x soft_max=10 + comp load "$T/off.comp"
out_has 'axis x: the tables correct it by \+0\.500000\.\.\+0\.500000 mm inside the soft limits'
err_has 'warning: axis x at its soft_max 10\.000000 mm: the tables put the tool up to 0\.500000 mm beyond it \(at 10\.500000 mm\)'
expect 0 "$CTL" -d sim params x soft_min=-10 + comp load "$T/off.comp"
err_lacks 'warning'
# at soft_min -5 the table takes 0.00025 mm off; beyond +10 its slope
# runs out over 16 end segments (no soft_max): +0.0045 mm at most
printf 'pitch X\n-10 -0.0005\n0 0\n10 0.0005\n' >"$T/slope.comp"
expect 0 "$CTL" -d sim params x soft_min=-5 + comp load "$T/slope.comp"
err_has 'warning: axis x at its soft_min -5\.000000 mm: .* 0\.000250 mm beyond it \(at -5\.000250 mm\)'
out_has 'axis x: the tables correct it by -0\.000250\.\.\+0\.004500 mm'

expect 0 "$CTL" -d sim comp load "$T/good.comp" + comp clear + comp show
out_has 'tables: none'
expect 2 "$CTL" -d sim comp load

# a laser system's export: header, nominal and measured positions
printf 'nominal,measured\n0,0\n10,10.0004\n20,20.0007\n30,30.0009\n' >"$T/laser.csv"
expect 0 "$COMP" csv x "$T/laser.csv" -o "$T/laser.comp"
run cat "$T/laser.comp"
out_has '^pitch X'
out_has '^30.0000 -0.000900000'
expect 0 "$CTL" -d sim comp load "$T/laser.comp"
printf '0,0\n10,x\n' >"$T/broken.csv"
expect 5 "$COMP" csv x "$T/broken.csv"
err_has 'broken.csv:2:'
# a file that cannot be read is 1 in every tool; 5 is for errors in it
expect 1 "$COMP" csv x "$T/none.csv" -o "$T/none.comp"
err_has 'none.csv: cannot read: No such file'
expect 1 "$CTL" -d sim comp show "$T/none.comp"
err_has 'none.comp: No such file'
expect 1 "$CTL" -d sim comp load "$T/none.comp"
# a table keyword with no points is too few points, as one point is; a
# table is named as its keyword line says it
printf 'pitch X\n' >"$T/empty.comp"
printf 'pitch X\n0 0\n' >"$T/onepoint.comp"
printf 'cross Y X\n0 0\n' >"$T/onecross.comp"
for name in empty onepoint; do
	expect 5 "$CTL" -d sim comp load "$T/$name.comp"
	err_has "$name.comp:1: pitch table X: too few points: nothing changed"
done
expect 5 "$CTL" -d sim comp load "$T/onecross.comp"
err_has 'onecross.comp:1: cross table Y by X: too few points'
# a directory opens for reading: said as what it is
expect 1 "$CTL" -d sim comp load "$T"
err_has "$T: not a table file: Is a directory"
err_lacks 'out of memory'
expect 1 "$CTL" -d sim comp show "$T"
err_has "$T: not a table file: Is a directory"
# every export the card would refuse is refused here, naming the CSV's
# row, with nothing written: out of order, a repeat (also the first step,
# which the point before the table is made from), a repeat after rounding
# to counts, header only, one point, NaN, garbage, units, a jump the axis
# cannot follow, a correction over 1 mm
h='nominal,measured\n'
bad=(
	"order:4:not strictly increasing:${h}0,0\n50,50.001\n25,25.0005\n100,100.002\n"
	"repeat:4:not strictly increasing:${h}0,0\n50,50.001\n50,50.0005\n100,100.002\n"
	"firststep:3:not strictly increasing:${h}0,0\n0,0.001\n50,50.0005\n"
	"counts:3:not strictly increasing:${h}0,0\n0.00001,0.00001\n10,10.001\n"
	"header:1:0 points:${h}"
	"one:2:1 point:${h}0,0\n"
	"nan:3:two numbers:${h}0,0\n10,nan\n20,20\n"
	"garbage:3:two numbers:${h}0,0\nxyz\n10,10.001\n"
	"units:2:two numbers:${h}0 mm,0 mm\n10 mm,10.001 mm\n"
	"jump:4:a jump larger:${h}0,0\n1,0.999\n1.001,0.990\n2,1.989\n"
	"big:4:larger than 1 mm:${h}0,0\n100,98.5\n200,198\n"
)
for b in "${bad[@]}"; do
	IFS=: read -r name line why text <<<"$b"
	printf "$text" >"$T/$name.csv"
	rm -f "$T/$name.comp"
	expect 5 "$COMP" csv x "$T/$name.csv" -o "$T/$name.comp"
	err_has "$name.csv:$line: .*$why"
	[ ! -e "$T/$name.comp" ] || fail "$name.csv: $T/$name.comp written"
done
# a blank line and a comment in the export are not rows
printf "${h}0,0\n\n# re-zeroed\n10,10.0004\n" >"$T/blank.csv"
expect 0 "$COMP" csv x "$T/blank.csv" -o "$T/blank.comp"
expect 0 "$CTL" -d sim comp load "$T/blank.comp"
# the card whose scales and limits the table is checked against
expect 3 "$COMP" csv x "$T/laser.csv" -d /dev/sh2000-none -o "$T/none.comp"
[ ! -e "$T/none.comp" ] || fail "none.comp written without a card"
# without -d, the card $SH2000_DEVICE names, as for every tool; -d wins
SH2000_DEVICE=/dev/sh2000-none expect 3 "$COMP" csv x "$T/laser.csv" -o "$T/none.comp"
err_has "/dev/sh2000-none"
SH2000_DEVICE=/dev/sh2000-none expect 0 "$COMP" csv x "$T/laser.csv" -d sim -o "$T/none.comp"

# a table that moves the tool past the card's soft limit: sh2000-comp csv
# warns in sh2000ctl comp load's words (on a served card whose soft_max is
# set) and still writes it; on a card without soft limits it says nothing
printf "${h}0,0\n10,9.9995\n20,19.9995\n" >"$T/over.csv"
expect 0 "$COMP" csv x "$T/over.csv" -d sim -o "$T/over.comp"
err_lacks 'warning'
NAME=comp-$$
start_sim "$NAME" || finish
expect 0 "$CTL" -d "sim:$NAME" params x soft_max=20
expect 0 "$COMP" csv x "$T/over.csv" -d "sim:$NAME" -o "$T/over.comp"
err_has 'sh2000-comp: warning: axis x at its soft_max 20\.000000 mm: the tables put the tool up to 0\.000500 mm beyond it \(at 20\.000500 mm\): the card judges soft limits on nominal positions, then adds the correction'
run cat "$T/over.comp"
out_has '^pitch X'
stop_sim

# the simulated machine calibrated over a short travel: the tables load
expect 0 "$COMP" calibrate -q --travel -5:5 --grid 5 --passes 1 -o "$T/cal.comp"
run cat "$T/cal.comp"
for t in 'pitch X' 'pitch Y' 'pitch Z' 'cross Y X' 'cross X Y' 'square X Y' 'grid Z X Y'; do
	out_has "^$t"
done
expect 0 "$CTL" -d sim comp load "$T/cal.comp"
out_has 'tables: active, 8 table\(s\)'
expect 2 "$COMP" calibrate -d sim:nope -o "$T/x.comp"
finish

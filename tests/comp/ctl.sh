#!/bin/bash
# sh2000ctl comp and sh2000-comp as a user runs them, on the in-process
# card (`-d sim`, one card per sh2000ctl run, sub-commands joined with +):
# load, show, clear; refusals name FILE:LINE, exit 5 and change nothing;
# a laser CSV made into a table; a calibration whose table loads.
set -u
: "${CTL:?CTL must name sh2000ctl}" "${COMP:?COMP must name sh2000-comp}"
T=$(mktemp -d /tmp/sh2000-comptest.XXXXXX)
trap 'rm -rf "$T"' EXIT
fails=0

fail() {
	echo "FAIL: $*" >&2
	fails=$((fails + 1))
}

# run CMD...: stdout in $out, stderr in $err, exit status in $rc
run() {
	"$@" >"$T/out" 2>"$T/err"
	rc=$?
	out=$(cat "$T/out")
	err=$(cat "$T/err")
}

printf 'id 0x00c0ffee\npitch X\n-10 0\n0 0.001\n10 0.0005\n' >"$T/good.comp"
printf 'pitch X\n0 0\n1 0.001\n1 0.002\n' >"$T/order.comp"
printf 'pitch X\n0 0\n1 0.001\n1.001 0.011\n2 0.011\n' >"$T/jump.comp"

run "$CTL" -d sim comp load "$T/good.comp" + comp show "$T/good.comp"
[ "$rc" = 0 ] || fail "load good: rc $rc: $err"
grep -q 'tables: active, 1 table(s), id 0x00c0ffee' <<<"$out" || fail "show after load: $out"
grep -q 'good.comp: sum 0x[0-9a-f]*: the active tables' <<<"$out" || fail "show FILE: $out"

for bad in order:4 jump:4; do
	name=${bad%%:*} line=${bad##*:}
	run "$CTL" -d sim comp load "$T/good.comp" + comp load "$T/$name.comp"
	[ "$rc" = 5 ] || fail "$name: rc $rc, want 5"
	grep -q "$name.comp:$line: .*nothing changed on the card" <<<"$err" ||
		fail "$name: message: $err"
	# the same card after the refusal: still the good tables
	run "$CTL" -d sim comp load "$T/good.comp" + comp load "$T/$name.comp" + comp show
	grep -q 'tables: active, 1 table(s), id 0x00c0ffee' <<<"$out" ||
		fail "$name: the card changed: $out"
done

run "$CTL" -d sim comp load "$T/good.comp" + comp clear + comp show
[ "$rc" = 0 ] && grep -q 'tables: none' <<<"$out" || fail "clear: rc $rc: $out $err"
run "$CTL" -d sim comp load
[ "$rc" = 2 ] || fail "load without FILE: rc $rc"

# a laser system's export: header, nominal and measured positions
printf 'nominal,measured\n0,0\n10,10.0004\n20,20.0007\n30,30.0009\n' >"$T/laser.csv"
run "$COMP" csv x "$T/laser.csv" -o "$T/laser.comp"
[ "$rc" = 0 ] || fail "csv: rc $rc: $err"
grep -q '^pitch X' "$T/laser.comp" || fail "csv: no pitch table: $(cat "$T/laser.comp")"
grep -q '^30.0000 -0.000900000' "$T/laser.comp" || fail "csv: corrections: $(cat "$T/laser.comp")"
run "$CTL" -d sim comp load "$T/laser.comp"
[ "$rc" = 0 ] || fail "load the csv's table: rc $rc: $err"
printf '0,0\n10,x\n' >"$T/broken.csv"
run "$COMP" csv x "$T/broken.csv"
[ "$rc" = 5 ] && grep -q 'broken.csv:2:' <<<"$err" || fail "broken csv: rc $rc: $err"

# the simulated machine calibrated over a short travel: the table loads
run "$COMP" calibrate -q --travel -5:5 --grid 5 --passes 1 -o "$T/cal.comp"
[ "$rc" = 0 ] || fail "calibrate: rc $rc: $err"
for t in 'pitch X' 'pitch Y' 'pitch Z' 'cross Y X' 'cross X Y' 'square X Y' 'grid Z X Y'; do
	grep -q "^$t" "$T/cal.comp" || fail "calibrate: no '$t' table"
done
run "$CTL" -d sim comp load "$T/cal.comp"
[ "$rc" = 0 ] && grep -q 'tables: active, 8 table(s)' <<<"$out" || fail "load calibration: rc $rc: $out $err"
run "$COMP" calibrate -d sim:nope -o "$T/x.comp"
[ "$rc" = 2 ] || fail "calibrate on sim:NAME: rc $rc"

[ "$fails" = 0 ] || exit 1
echo "comp tools: all passed"

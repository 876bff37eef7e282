#!/bin/bash
# sh2000ctl params: get, set, save, load; bad values and bad files name
# FILE:LINE and set nothing (checked on a served card, which keeps its
# parameters between invocations).
. "$(dirname "$0")/testlib.sh"
S=(-d sim)

expect 0 "$CTL" "${S[@]}" params x kp vmax ferr_limit &&
	{ checks=$((checks + 1)); [ "$out" = "$(printf 'kp = 0.5\nvmax = 400\nferr_limit = 0.2')" ] ||
		fail "defaults: $out"; }
expect 0 "$CTL" "${S[@]}" params x kp=0.7 vmax=300 + params x kp vmax &&
	{ checks=$((checks + 1)); [ "$out" = "$(printf 'kp = 0.7\nvmax = 300')" ] || fail "set: $out"; }
expect 0 "$CTL" "${S[@]}" params global host_timeout_ms=250 + params global host_timeout_ms &&
	out_has "^host_timeout_ms = 250$"
expect 0 "$CTL" "${S[@]}" params y && out_has "^\[y\]$" && out_has "^kp = 0.5 +# DAC/count$" &&
	{ checks=$((checks + 1)); [ "$(printf '%s\n' "$out" | grep -c ' = ')" = 16 ] ||
		fail "params y: not 16 parameters"; }
expect 0 "$CTL" "${S[@]}" params && out_has "^\[global\]$" && out_has "^\[a\]$"
# values the card cannot take: exit 1, the device and the reason named
expect 1 "$CTL" "${S[@]}" params x kp=-1 && err_has "^sh2000ctl: sim: params: x kp: -1 DAC/count is outside 0\.\.1000"
# (a float too small for the card is refused before anything is sent)
expect 1 "$CTL" "${S[@]}" params x kaff=1e-50 && err_has "x kaff: 1e-50 .* does not fit a 32-bit float"
expect 1 "$CTL" "${S[@]}" params x soft_min=10 soft_max=5 && err_has "soft_min 10 mm must be below soft_max 5 mm"
expect 1 "$CTL" "${S[@]}" params global fine_steps=7 && err_has "servo period"
expect 2 "$CTL" "${S[@]}" params global kp=1 && err_has "kp is an axis parameter"
expect 2 "$CTL" "${S[@]}" params x kp=1 kp=2 && err_has "kp given twice"
# a new scale with a soft window that moves up past the old one: the card
# compares counts, so max goes first (min first was refused after the
# scale had been set: half applied)
expect 0 "$CTL" "${S[@]}" params x soft_min=-10 soft_max=10 + \
	params x scale=200000 soft_min=6 soft_max=20 + params x scale soft_min soft_max &&
	{ checks=$((checks + 1)); [ "$out" = "$(printf 'scale = 200000\nsoft_min = 6\nsoft_max = 20')" ] ||
		fail "scale and soft window: $out"; }

# save and load round trip, on a served card
NAME=ctlparams-$$
start_sim "$NAME" || finish
D=(-d "sim:$NAME")
expect 0 "$CTL" "${D[@]}" params x kp=0.65 soft_min=-100 soft_max=200 scale=100000 + \
	params global host_timeout_ms=300
expect 0 "$CTL" "${D[@]}" params save "$T/saved.ini"
checks=$((checks + 1))
grep -Eq '^kp = 0\.65 +# DAC/count$' "$T/saved.ini" && grep -q '^\[global\]$' "$T/saved.ini" &&
	grep -Eq '^soft_min = -100 ' "$T/saved.ini" || fail "saved file: $(cat "$T/saved.ini")"
expect 0 "$CTL" "${D[@]}" params save - && {
	checks=$((checks + 1))
	diff <(printf '%s\n' "$out") "$T/saved.ini" >/dev/null || fail "save - differs from save FILE"
}
# change things, load the file back: every value is back
expect 0 "$CTL" "${D[@]}" params x kp=0.9 soft_min=-50 + params global host_timeout_ms=100
expect 0 "$CTL" "${D[@]}" params load "$T/saved.ini"
expect 0 "$CTL" "${D[@]}" params save "$T/again.ini"
checks=$((checks + 1))
diff "$T/saved.ini" "$T/again.ini" >/dev/null || fail "load did not restore: $(diff "$T/saved.ini" "$T/again.ini")"
# a file with errors: every error as FILE:LINE, exit 1, nothing set
cat >"$T/bad.ini" <<'INI'
# a comment
[x]
kp = 0.8          ; fine on its own
kp = 0.9
foo = 1
[w]
vmax = 3
[y]
vmax = fast
vmax2
soft_min = 10
soft_max = 5
[z]
vmax = -3
[global]
kp = 1
fine_steps = 7
INI
expect 1 "$CTL" "${D[@]}" params load "$T/bad.ini" &&
	err_has "^sh2000ctl: $T/bad.ini:4: kp of \[x\] already set on line 3$" &&
	err_has "^sh2000ctl: $T/bad.ini:5: unknown parameter 'foo'$" &&
	err_has "^sh2000ctl: $T/bad.ini:6: unknown section \[w\]" &&
	err_has "^sh2000ctl: $T/bad.ini:9: vmax: 'fast' is not a number$" &&
	err_has "^sh2000ctl: $T/bad.ini:10: expected 'name = value'" &&
	err_has "^sh2000ctl: $T/bad.ini:16: kp is an axis parameter" &&
	err_has "^sh2000ctl: $T/bad.ini: nothing set$"
# the same file without its parse errors: the range and cross checks
grep -v -e '^kp = 0.9' -e foo -e '^\[w\]' -e 'vmax = 3$' -e fast -e vmax2 -e '^kp = 1' \
	"$T/bad.ini" >"$T/bad2.ini"
expect 1 "$CTL" "${D[@]}" params load "$T/bad2.ini" &&
	err_has "^sh2000ctl: $T/bad2.ini:6: y soft_min 10 mm must be below soft_max 5 mm$" &&
	err_has "^sh2000ctl: $T/bad2.ini:8: z vmax: -3 mm/s is outside" &&
	err_has "^sh2000ctl: $T/bad2.ini:10: coarse_period_us 2000 with fine_steps 7" &&
	err_has "nothing set"
printf 'kp = 1\n' >"$T/nosect.ini"
expect 1 "$CTL" "${D[@]}" params load "$T/nosect.ini" && err_has "nosect.ini:1: 'kp' before any \[section\]"
expect 1 "$CTL" "${D[@]}" params load "$T/missing.ini" && err_has "missing.ini: cannot open"
# nothing of the bad files reached the card: x kp is still 0.65
expect 0 "$CTL" "${D[@]}" params save "$T/after.ini"
checks=$((checks + 1))
diff "$T/saved.ini" "$T/after.ini" >/dev/null || fail "a bad file changed the card: $(diff "$T/saved.ini" "$T/after.ini")"
# load from stdin
printf '[x]\nkp = 0.55\n' | expect 0 "$CTL" "${D[@]}" params load -
expect 0 "$CTL" "${D[@]}" params x kp && out_has "^kp = 0.55$"
# every error of a file, the cross checks' too: a range error in the
# section does not hide the soft-limit order, nor one in [global] the timing
printf '[x]\nsoft_min = 50\nsoft_max = 10\nkp = 5000\n[global]\nfine_steps = 7\nhost_timeout_ms = -5\n' >"$T/cross.ini"
expect 1 "$CTL" "${D[@]}" params load "$T/cross.ini" &&
	err_has "^sh2000ctl: $T/cross.ini:3: x soft_min 50 mm must be below soft_max 10 mm$" &&
	err_has "^sh2000ctl: $T/cross.ini:4: x kp: 5000 DAC/count is outside" &&
	err_has "^sh2000ctl: $T/cross.ini:6: coarse_period_us 2000 with fine_steps 7" &&
	err_has "^sh2000ctl: $T/cross.ini:7: host_timeout_ms: " && err_has "nothing set$"
# a bad name or number on the command line is a usage error, with its hint
expect 2 "$CTL" "${D[@]}" params x kp=abc && err_has "kp: 'abc' is not a number" &&
	err_has "^Try 'sh2000ctl params --help'\.$"
expect 2 "$CTL" "${D[@]}" params x kpp=1 && err_has "unknown parameter 'kpp'" &&
	err_has "^Try 'sh2000ctl params --help'\.$"

# soft limits that would leave an enabled axis outside: refused, nothing
# set (the card faults every set-point outside them: the axis could not
# move back); the same from a file
expect 0 "$CTL" "${D[@]}" params x soft_min=-100 soft_max=200 + enable x + move x=10
expect 1 "$CTL" "${D[@]}" params x soft_min=50 &&
	err_has "^sh2000ctl: sim:$NAME: params: x soft limits 50\.\.200 mm would leave axis x \(enabled, at 10\.0000 mm\) outside them: .*move it inside first, or give limits around it$"
printf '[x]\nsoft_min = 50\n' >"$T/s3.params"
expect 1 "$CTL" "${D[@]}" params load "$T/s3.params" &&
	err_has "^sh2000ctl: $T/s3.params:2: x soft limits 50\.\.200 mm would leave axis x" && err_has "nothing set$"
expect 0 "$CTL" "${D[@]}" params x soft_min && out_has "^soft_min = -100$"
# limits around it are fine; the plan sends them in an order whose every
# window on the way keeps the axis inside (the library judges each set):
# narrowing around it, widening, the window moved up past it (the new min
# on the old max, the position on both) and back, a new scale with them
expect 0 "$CTL" "${D[@]}" params x soft_min=5 soft_max=15
expect 0 "$CTL" "${D[@]}" params x soft_min=9.5 soft_max=10.5 + params x soft_min=-300 soft_max=300 + \
	params x soft_min=9 soft_max=10 + params x soft_min=10 soft_max=20 + params x soft_min=0 soft_max=10 + \
	params x soft_min soft_max &&
	{ checks=$((checks + 1)); [ "$out" = "$(printf 'soft_min = 0\nsoft_max = 10')" ] || fail "moved windows: $out"; }
expect 0 "$CTL" "${D[@]}" params x scale=200000 soft_min=4 soft_max=6 + params x scale=100000 soft_min=5 soft_max=15 +\
	params x soft_min soft_max && out_has "^soft_min = 5$" && out_has "^soft_max = 15$"
# an axis above its window (enabled while not judged): a new window
# around it goes max first, as min first would leave it outside on the way
expect 0 "$CTL" "${D[@]}" params a soft_min=-200 soft_max=-50 + enable a +\
	params a soft_min=-100 soft_max=10 + params a soft_min soft_max + disable a &&
	out_has "^soft_min = -100$" && out_has "^soft_max = 10$"
# a disabled axis never homed is not judged; enabled there, it cannot
# move, and move and jog say so in the operator's terms with the way back
expect 0 "$CTL" "${D[@]}" params y soft_min=50 soft_max=200 + enable y
expect 1 "$CTL" "${D[@]}" move y=60 &&
	err_has "^sh2000ctl: sim:$NAME: axis y is at 0\.0000 mm, outside its soft limits 50\.0000\.\.200\.0000 mm, and the card refuses any set-point outside them: nothing moved\. To get back: widen them \(sh2000ctl params y soft_min=0\.0000\), move y inside, then set soft_min=50\.0000 again$"
checks=$((checks + 1))
! printf '%s\n' "$err" | grep -q "point 0\|record" || fail "move outside: runner internals: $err"
expect 1 "$CTL" "${D[@]}" jog y 1 && err_has "axis y is at 0\.0000 mm, outside its soft limits"
expect 1 "$CTL" "${D[@]}" jog y --velocity 10 --time 0.1 && err_has "axis y is at 0\.0000 mm, outside its soft limits"
# and the way back works
expect 0 "$CTL" "${D[@]}" params y soft_min=0 + move y=60 + params y soft_min=50

# a new scale: the lengths not set now read differently in mm, and a
# note lists them; lengths set with it are converted with the new scale
expect 0 "$CTL" "${D[@]}" params z scale vmax && out_has "^scale = 100000$" && out_has "^vmax = 400$"
expect 0 "$CTL" "${D[@]}" params z scale=1000 &&
	err_has "^sh2000ctl: sim:$NAME: note: z scale 1000 counts/mm \(was 100000\): the card keeps lengths in counts, so the ones not set now read .*vmax 40000 mm/s, .*position 0 mm$"
expect 0 "$CTL" "${D[@]}" params z vmax && out_has "^vmax = 40000$"
# a file with vmax before scale: the file's mm value is what the card holds
printf '[z]\nvmax = 300\nscale = 100000\n' >"$T/scale.ini"
expect 0 "$CTL" "${D[@]}" params load "$T/scale.ini" && err_has "note: z scale 100000 counts/mm \(was 1000\)"
checks=$((checks + 1))
printf '%s\n' "$err" | grep -q "vmax" && fail "note lists vmax, which the file set: $err"
expect 0 "$CTL" "${D[@]}" params z scale vmax && out_has "^scale = 100000$" && out_has "^vmax = 300$"
stop_sim
finish

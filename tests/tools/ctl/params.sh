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
stop_sim
finish

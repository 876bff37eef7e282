#!/bin/bash
# sh2000ctl gather against the in-process `sim` card: the CSV's header and
# rows, the three triggers (arming with --no-wait, then a motion or an
# emergency stop in the same chain, then --read), the values against what
# the card reports, and bad arguments (usage errors send nothing; a file
# is written only when the whole record was read).
. "$(dirname "$0")/testlib.sh"
S=(-d sim)

# column NAME FILE: the values of the column whose header is NAME
column() {
	awk -F, -v n="$1" 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == n) c = i; next }
		c { print $c }' "$2"
}

# trigger now: every sample, times from 0 one servo period apart
expect 0 "$CTL" "${S[@]}" gather --signals encoder --samples 50 &&
	out_has '^time\[s\],x\.encoder\[counts\]$'
checks=$((checks + 1))
printf '%s\n' "$out" | awk -F, 'NR > 1 { n++; if ($1 + 0 < (n - 1) * 1e-4 - 1e-9 || $1 + 0 > (n - 1) * 1e-4 + 1e-9 || $2 != 0) bad = 1 }
	END { exit bad || n != 50 }' || fail "gather now: not 50 rows 100 us apart at 0: $out"

# every signal of two axes: the header names each with its unit
expect 0 "$CTL" "${S[@]}" gather -a x,y -s all --samples 3 --period 2 &&
	out_has '^time\[s\],x\.setpoint\[counts\],x\.encoder\[counts\],x\.ferr\[counts\],x\.dac\[DAC codes\],x\.pid_p\[DAC codes\],x\.pid_i\[DAC codes\],x\.pid_d\[DAC codes\],x\.ff\[DAC codes\],x\.velocity\[counts/s\],x\.setpoint_vel\[counts/s\],y\.setpoint\[counts\],.*,y\.setpoint_vel\[counts/s\]$' &&
	out_has '^0\.0002,'

# trigger on motion with a pre-trigger: armed, the move, then the record
expect 0 "$CTL" "${S[@]}" enable x + params x ferr_limit=1 + \
	gather --no-wait --signals setpoint,encoder,ferr,dac --period 10 --samples 400 \
		--trigger motion --pretrigger 20 + \
	move x=2 + gather --read -o "$T/motion.csv"
checks=$((checks + 1))
head -n 1 "$T/motion.csv" | grep -qx 'time\[s\],x\.setpoint\[counts\],x\.encoder\[counts\],x\.ferr\[counts\],x\.dac\[DAC codes\]' ||
	fail "motion: header $(head -n 1 "$T/motion.csv")"
checks=$((checks + 1))
# rows 1 ms apart; the trigger's row at time 0 (the pre-trigger before it
# negative, as many as were taken since arming); the set-point rests at 0
# before and ends at 2 mm = 200000 counts
awk -F, 'NR == 1 { next } { n++ }
	n > 1 && ($1 - prev < 0.001 - 1e-9 || $1 - prev > 0.001 + 1e-9) { bad = "step" }
	$1 + 0 < 0 { pre++; if ($2 != 0) bad = "moved before the trigger" }
	$1 == 0 { zero++ } { prev = $1; last = $2 }
	END { if (!bad && (zero != 1 || pre > 20 || n != 380 + pre || last != 200000)) bad = "rows";
	      if (bad) { print bad, n, pre, zero, last; exit 1 } }' "$T/motion.csv" ||
	fail "motion record: $(awk -F, 'NR == 1 { next } { n++ } $1 + 0 < 0 { pre++ } END { print n, pre }' "$T/motion.csv")"
checks=$((checks + 1))
# the following error is the unrounded set-point minus the encoder
awk -F, 'NR > 1 { d = $4 - ($2 - $3); if (d < -0.5 || d > 0.5) bad = 1; if ($3 != $2) moved = 1 }
	END { exit bad || !moved }' "$T/motion.csv" ||
	fail "motion record: ferr is not set-point - encoder"
checks=$((checks + 1))
[ "$(column 'x.encoder[counts]' "$T/motion.csv" | sort -n | tail -n 1)" -gt 199000 ] ||
	fail "motion record: the encoder did not follow to 2 mm"

# trigger on a fault: the emergency stop after a jog is the record's time
# 0, the pre-trigger samples are where the jog ended (1 mm, within the
# 0.5 um the servo still lags as a landed stop ends)
expect 0 "$CTL" "${S[@]}" enable x + gather --no-wait --signals encoder --samples 30 \
	--trigger fault --pretrigger 10 + jog x 1 + estop + gather --read -o "$T/fault.csv"
checks=$((checks + 1))
[ "$(awk -F, 'NR > 1 && $1 < 0 { p++ } NR > 1 { n++; if ($2 < 99950 || $2 > 100010) far++ }
	END { print n, p, far + 0 }' "$T/fault.csv")" = "30 10 0" ] ||
	fail "fault record: $(cat "$T/fault.csv")"

# usage errors: nothing sent, exit 2
expect 2 "$CTL" "${S[@]}" gather --signals setpoint,speed && err_has "'speed' is not a signal"
expect 2 "$CTL" "${S[@]}" gather --axis q && err_has "--axis 'q': not an axis list"
expect 2 "$CTL" "${S[@]}" gather --trigger later && err_has "now, motion or fault"
expect 2 "$CTL" "${S[@]}" gather --period 0 && err_has "--period '0': a whole number 1..65535"
expect 2 "$CTL" "${S[@]}" gather --samples && err_has "needs a value"
expect 2 "$CTL" "${S[@]}" gather --read --samples 10 && err_has "only --output and --timeout"
expect 2 "$CTL" "${S[@]}" gather --no-wait -o "$T/x.csv" && err_has "writes nothing"
expect 2 "$CTL" "${S[@]}" gather extra && err_has "unexpected 'extra'"
# the card's rules, checked by the library before anything is sent: exit 1
expect 1 "$CTL" "${S[@]}" gather --pretrigger 5 && err_has "pre-trigger 5: .*0 with trigger now"
expect 1 "$CTL" "${S[@]}" gather -a all -s all --samples 1000 &&
	err_has "1000 samples of 40 values: the card holds 1\.\.32768 values"
expect 1 "$CTL" "${S[@]}" gather --read && err_has "no record on the card"
# a record that does not come: an error, and the old file stays as it was
echo keep >"$T/old.csv"
expect 1 "$CTL" "${S[@]}" gather --trigger motion --timeout 0.05 -o "$T/old.csv" &&
	err_has "not complete within 50 ms"
checks=$((checks + 1))
[ "$(cat "$T/old.csv")" = keep ] || fail "a failed gather changed the file"
expect 1 "$CTL" "${S[@]}" gather -o "$T/no/such/dir.csv" && err_has "cannot create"
checks=$((checks + 1))
[ ! -e "$T/no" ] || fail "a directory appeared"

expect 0 "$CTL" gather --help && out_has "^Usage: sh2000ctl \[-d DEVICE\] gather"
finish

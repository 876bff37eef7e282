#!/bin/bash
# sh2000-tune's step test on the in-process `sim` card: the report against
# the CSV it writes (rise, overshoot, settling computed again here), the
# picture, both directions, the DAC bound, the following-error abort with
# the axis back at its start, the velocity bound refusing before anything
# moves, usage errors, and gnuplot missing.
. "$(dirname "$0")/../ctl/testlib.sh"
. "$(dirname "$0")/tunelib.sh"

expect 0 "$TUNE" "${S[@]}" x --step 0.01 --enable --csv "$T/s.csv" --plot "$T/s.png" &&
	out_has '^axis x: step 0\.01 mm \(1000 counts\), held 0\.2 s$' &&
	out_has '^back at the start +0\.000000 mm \(position, 0 counts from where it started\)$'
rise=$(figure 'rise time (10-90 %)') over=$(figure overshoot)
settle=$(figure 'settling to 10 counts') dac=$(figure 'peak DAC')
# the same figures from the CSV: crossings of 100 and 900 counts
# interpolated, the largest excess over 1000, the sample after the last one
# more than 10 counts off (times in s, from the step)
read -r crise cover csettle cdac < <(awk -F, 'NR == 1 { next }
	{ t = $1; e = $3; d = $4 < 0 ? -$4 : $4; if (d > mdac) mdac = d }
	t >= 0 && !t10 && e >= 100 { t10 = pt < 0 || pe >= 100 ? t : pt + (100 - pe) / (e - pe) * (t - pt) }
	t >= 0 && !t90 && e >= 900 { t90 = pt < 0 || pe >= 900 ? t : pt + (900 - pe) / (e - pe) * (t - pt) }
	e - 1000 > over { over = e - 1000 }
	{ if (t >= 0 && (e - 1000 > 10 || 1000 - e > 10)) { out = 1; settle = "" } else if (out && settle == "") settle = t }
	{ pt = t; pe = e }
	END { printf "%.6f %.0f %.6f %.0f\n", (t90 - t10) * 1e3, over, settle * 1e3, mdac }' "$T/s.csv")
checks=$((checks + 1))
close "$rise" "$crise" 0.002 && close "$over" "$cover" 0 && close "$settle" "$csettle" 0.002 &&
	close "$dac" "$cdac" 0 ||
	fail "report ($rise ms, $over counts, $settle ms, $dac codes) is not the CSV's ($crise, $cover, $csettle, $cdac)"
# the model's default loop: a well-damped step of a few milliseconds
checks=$((checks + 1))
awk -v r="$rise" -v s="$settle" 'BEGIN { exit !(r > 0.5 && r < 10 && s > r && s < 50) }' ||
	fail "implausible step: rise $rise ms, settling $settle ms"
is_png "$T/s.png"

# the other way, and an SVG
expect 0 "$TUNE" "${S[@]}" x --step -0.01 --enable --plot "$T/s.svg" &&
	out_has '^axis x: step -0\.01 mm \(-1000 counts\)' && out_has '^back at the start +0\.000000 mm \(position, 0 counts from where it started\)$'
checks=$((checks + 1))
grep -q '<svg' "$T/s.svg" || fail "--plot .svg did not write an SVG"

# the DAC bound holds (the step is slower for it)
expect 0 "$TUNE" "${S[@]}" y --step 0.05 --enable --dac-max 300 --csv "$T/d.csv" &&
	out_has '^peak DAC +300 codes$'
checks=$((checks + 1))
awk -F, 'NR > 1 && ($4 > 300 || $4 < -300) { bad = 1 } END { exit bad }' "$T/d.csv" ||
	fail "the DAC went beyond --dac-max 300"

# beyond the following-error bound: aborted, back at the start, exit 8
expect 8 "$TUNE" "${S[@]}" x --step 0.5 --enable --ferr-max 0.0002 &&
	err_has 'step test aborted: axis following error limit exceeded \(limit 0\.0002 mm' &&
	out_has '^back at the start +0\.000000 mm \(position, 0 counts from where it started\)$'

# bounds that refuse before anything moves
expect 1 "$TUNE" "${S[@]}" x --step 1 --enable --vmax 100 &&
	err_has 'a step of 1 mm in one coarse period \(2 ms\) is 500\.0 mm/s: .*within 100\.0 mm/s \(at most 0\.2 mm\): nothing moved'
# the in-process card is this program's alone and starts disabled: the
# test enables the axis without --enable (on a served card it refuses:
# tool_tune_served)
expect 0 "$TUNE" "${S[@]}" x --step 0.01 && out_has '^back at the start +0\.000000 mm \(position, 0 counts from where it started\)$'

# usage errors
expect 2 "$TUNE" "${S[@]}" --step 0.01 && err_has 'which AXIS'
expect 2 "$TUNE" "${S[@]}" q --step 0.01 && err_has "'q' is not an axis"
expect 2 "$TUNE" "${S[@]}" x && err_has 'which test\? --step MM, --ramp MM/S, --chirp F0:F1 or --auto'
expect 2 "$TUNE" "${S[@]}" x --step 0 && err_has "--step: '0'"
expect 2 "$TUNE" "${S[@]}" x --step 0.01 --dac-max 0 && err_has "--dac-max: '0'"
expect 2 "$TUNE" "${S[@]}" x --step 0.01 --ferr-max -1 && err_has "--ferr-max: '-1'"
expect 2 "$TUNE" "${S[@]}" x --step && err_has 'needs a value'
expect 0 "$TUNE" --help && out_has '^Usage: sh2000-tune'

# no gnuplot: the figures are printed, exit 6
expect 6 env PATH=/nonexistent "$TUNE" "${S[@]}" x --step 0.01 --enable --plot "$T/n.png" &&
	out_has '^rise time' && err_has 'gnuplot not found on PATH'
finish

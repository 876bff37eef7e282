#!/bin/bash
# sh2000-tune's ramp and chirp tests on the in-process `sim` card: the
# reports against the CSV they write (the ramp's figures and the chirp's
# crossover computed again here), the pictures, the following-error abort
# with the axis back at its start, the DAC bound, the bounds that refuse
# before anything moves, usage errors (exit 2), and gnuplot missing.
. "$(dirname "$0")/../ctl/testlib.sh"
. "$(dirname "$0")/tunelib.sh"

# ---- ramp ----
expect 0 "$TUNE" "${S[@]}" x --ramp 100 --enable --csv "$T/r.csv" --plot "$T/r.png" &&
	out_has '^axis x: ramp 100 mm/s over 7 mm \(accelerating at 5000 mm/s\^2\)$' &&
	out_has '^back at the start +0\.000000 mm \(position, 0 counts from where it started\)$'
peak=$(figure 'constant-speed peak') rms=$(figure 'constant-speed RMS')
acc=$(figure 'accelerating peak')
# the same from the CSV: |ferr| where constant_speed is 1, and where the
# set-point moved otherwise
read -r cpeak crms cacc < <(awk -F, 'NR == 1 { next }
	{ e = $4 < 0 ? -$4 : $4 }
	$6 == 1 { n++; s += e * e; if (e > p) p = e; prev = $2; next }
	NR > 2 && $2 != prev && e > a { a = e }
	{ prev = $2 }
	END { printf "%.2f %.2f %.2f\n", p, sqrt(s / n), a }' "$T/r.csv")
checks=$((checks + 1))
close "$peak" "$cpeak" 0.005 && close "$rms" "$crms" 0.005 && close "$acc" "$cacc" 0.005 ||
	fail "ramp report ($peak, $rms, $acc counts) is not the CSV's ($cpeak, $crms, $cacc)"
is_png "$T/r.png"
# the other way, a shorter travel given
expect 0 "$TUNE" "${S[@]}" y --ramp -50 --travel 3 --enable &&
	out_has '^axis y: ramp -50 mm/s over 3 mm' && out_has '^back at the start +0\.000000 mm \(position, 0 counts from where it started\)$'
# beyond the following-error bound: aborted, back at the start, exit 8
# (with its feed-forward the loop follows this ramp within 1.2 counts,
# the counter's floor and the B-spline's jerk: a bound of one count)
expect 8 "$TUNE" "${S[@]}" x --ramp 300 --enable --ferr-max 0.00001 &&
	err_has 'ramp test aborted: axis following error limit exceeded \(limit 1e-05 mm' &&
	out_has '^back at the start +0\.000000 mm \(position, 0 counts from where it started\)$'
# bounds that refuse before anything moves
expect 1 "$TUNE" "${S[@]}" x --ramp 500 --enable &&
	err_has 'a ramp at 500 mm/s is beyond the velocity bound 400\.0 mm/s: nothing moved'
expect 1 "$TUNE" "${S[@]}" x --ramp 200 --vmax 100 --enable &&
	err_has 'beyond the velocity bound 100\.0 mm/s: nothing moved'
expect 1 "$TUNE" "${S[@]}" x --ramp 100 --travel 1 --enable &&
	err_has 'needs more than 2 mm of travel to reach its speed \(--travel 1\): nothing moved'

# ---- chirp ----
expect 0 "$TUNE" "${S[@]}" x --chirp 5:3000 --enable --csv "$T/c.csv" --plot "$T/c.png" &&
	out_has '^axis x: chirp 5-3000 Hz, amplitude 0\.002 mm \(200 counts\), 0\.8 s$' &&
	out_has '^response +48 frequencies, sampled every 0\.1 ms$' &&
	out_has '^gain margin +[0-9.]+ dB at [0-9.]+ Hz$' &&
	out_has '^back at the start +0\.000000 mm \(position, 0 counts from where it started\)$'
wc=$(figure crossover) pm=$(figure 'phase margin') gm=$(figure 'gain margin')
# the crossover again from the CSV: |L| through 1, log-interpolated
read -r cwc cpm < <(awk -F, 'NR == 1 { next }
	pl >= 1 && $4 < 1 && !done { f = log(pl) / (log(pl) - log($4));
		printf "%.2f %.1f\n", exp(log(pf) + f * (log($1) - log(pf))), 180 + pp + f * ($5 - pp); done = 1 }
	{ pf = $1; pl = $4; pp = $5 }' "$T/c.csv")
checks=$((checks + 1))
close "$wc" "$cwc" 0.02 && close "$pm" "$cpm" 0.15 ||
	fail "chirp report (crossover $wc Hz, PM $pm) is not the CSV's ($cwc, $cpm)"
# the default loop of the card model: crossover near 100 Hz, PM about
# 65 deg, GM about 30 dB (test_freqresp holds them to the analytic loop)
checks=$((checks + 1))
awk -v w="$wc" -v p="$pm" -v g="$gm" 'BEGIN { exit !(w > 90 && w < 115 && p > 60 && p < 70 && g > 28 && g < 32) }' ||
	fail "implausible loop: crossover $wc Hz, PM $pm deg, GM $gm dB"
checks=$((checks + 1))
[ "$(wc -l < "$T/c.csv")" = 49 ] || fail "--csv: $(wc -l < "$T/c.csv") lines, expected 1 + 48"
is_png "$T/c.png"
expect 0 "$TUNE" "${S[@]}" z --chirp 10:150 --enable --plot "$T/c.svg" &&
	out_has '^gain margin +none measured \(the sweep, to 150 Hz, does not reach a phase of -180 deg\)'
checks=$((checks + 1))
grep -q '<svg' "$T/c.svg" || fail "--plot .svg did not write an SVG"
# a DAC bound the sweep reaches: said, and the figures still printed
expect 0 "$TUNE" "${S[@]}" x --chirp 5:3000 --enable --dac-max 1000 --accel 20000 &&
	err_has 'the DAC reached its bound during the sweep: .*\(a smaller --amplitude or --accel\)' &&
	out_has '^crossover' && out_has '^peak DAC +1000 codes$'
# beyond the following-error bound: aborted, the card's coarse period put
# back (the runner's way back needs it), back at the start, exit 8 (the
# clipped DAC falls behind before DAC_SAT's 200 cycles at its bound)
expect 8 "$TUNE" "${S[@]}" x --chirp 5:3000 --enable --dac-max 2000 --accel 100000 &&
	err_has 'chirp test aborted: axis following error limit exceeded' &&
	out_has '^back at the start +0\.000000 mm \(position, 0 counts from where it started\)$'
# bounds that refuse before anything moves
expect 1 "$TUNE" "${S[@]}" x --chirp 5:4000 --enable &&
	err_has "the card's servo period \(0\.1 ms\) carries a sweep up to 3563 Hz: nothing moved"
expect 1 "$TUNE" "${S[@]}" x --chirp 5:100 --amplitude 0.5 --vmax 100 --accel 1000000 --enable &&
	err_has '--amplitude 0\.5 mm at 112\.2 Hz is 352\.6 mm/s: it must be within 100\.0 mm/s .*nothing moved'
# without --enable on the in-process card (this program's alone)
expect 0 "$TUNE" "${S[@]}" x --chirp 5:100 && out_has '^back at the start +0\.000000 mm \(position, 0 counts from where it started\)$'

# ---- usage errors: exit 2, before the card is opened ----
expect 2 "$TUNE" "${S[@]}" x --chirp 200:5 && err_has '--chirp 200:5: F0 \(200 Hz\) must be below F1 \(5 Hz\)'
expect 2 "$TUNE" "${S[@]}" x --chirp 100:100 && err_has 'F0 \(100 Hz\) must be below F1'
expect 2 "$TUNE" "${S[@]}" x --chirp 100 && err_has "--chirp: '100' is not F0:F1"
expect 2 "$TUNE" "${S[@]}" x --chirp 0:100 && err_has 'two frequencies above 0 Hz'
expect 2 "$TUNE" "${S[@]}" x --chirp 5:x && err_has 'two frequencies above 0 Hz'
expect 2 "$TUNE" "${S[@]}" x --chirp 5:100 --amplitude 2 &&
	err_has '--amplitude 2 mm: beyond the travel window of 1 mm from the start \(--travel\)'
expect 2 "$TUNE" "${S[@]}" x --chirp 5:100 --amplitude 0.5 --travel 0.2 &&
	err_has 'beyond the travel window of 0\.2 mm'
expect 2 "$TUNE" "${S[@]}" x --chirp 5:100 --duration 0.1 &&
	err_has '--duration 0\.1 s: a sweep from 5 Hz needs at least 0\.6 s'
expect 2 "$TUNE" "${S[@]}" x --chirp 5:100 --duration 11 && err_has '--duration: at most 10 s'
expect 2 "$TUNE" "${S[@]}" x --chirp 5:100 --amplitude 0 && err_has "--amplitude: '0' is not a number above 0"
expect 2 "$TUNE" "${S[@]}" x --chirp 5:100 --accel -5 && err_has "--accel: '-5'"
expect 2 "$TUNE" "${S[@]}" x --ramp 0 && err_has "--ramp: '0' is not a speed other than 0"
expect 2 "$TUNE" "${S[@]}" x --ramp fast && err_has "--ramp: 'fast'"
expect 2 "$TUNE" "${S[@]}" x --ramp 100 --travel -1 && err_has "--travel: '-1'"
expect 2 "$TUNE" "${S[@]}" x --ramp 100 --chirp 5:100 && err_has 'one test at a time'
expect 2 "$TUNE" "${S[@]}" x --step 0.01 --ramp 100 && err_has 'one test at a time'

# no gnuplot: the figures are printed, exit 6
expect 6 env PATH=/nonexistent "$TUNE" "${S[@]}" x --chirp 5:200 --enable --plot "$T/n.png" &&
	out_has '^crossover' && err_has 'gnuplot not found on PATH'
finish

#!/bin/bash
# sh2000-tune --auto. On a card served by sh2000-sim (its plant 10x the
# default mass, --mass 20), read by sh2000ctl (a second program):
# --dry-run writes nothing (the gains are as before), --apply writes the
# five gains it printed and runs its step check, --save writes a file that
# `sh2000ctl params load` loads back onto the card; a design the plant
# cannot meet is refused with nothing written. Then on the in-process
# `sim`: the plant printed is the model's default, --plot's chirp measures
# the margins the design predicted, and bad inputs are usage errors
# (exit 2).
. "$(dirname "$0")/../ctl/testlib.sh"
: "${TUNE:?TUNE must name sh2000-tune}"
# sh2000-tune streams to a served card: at the hosts' priority (realtime.sh)
TUNE_RT=("${RT_HOST[@]}" "$TUNE")
name=tuneauto$$
S=(-d "sim:$name")
start_sim "$name" --mass 20 || finish

gains() {
	"${CTL_RT[@]}" "${S[@]}" params x kp ti td kvff kaff
}
# printed NAME: the new value of gain NAME in the last stdout
printed() {
	printf '%s\n' "$out" | awk -v n="$1" '$1 == n { print $3 }'
}

expect 0 "${CTL_RT[@]}" "${S[@]}" enable x
before=$(gains)
expect 0 "${TUNE_RT[@]}" "${S[@]}" x --auto --dry-run &&
	out_has '^plant gain g +3051[0-9.]* counts/s\^2 per DAC code$' &&
	out_has '^friction pole b/m +1 1/s$' &&
	out_has '^dead time +0 servo cycles' &&
	out_has '^design .* phase margin 45\.5 deg, gain margin 8 dB asked$' &&
	out_has '^predicted, new gains +phase 45\.5 deg' &&
	out_has '^dry run: nothing written'
checks=$((checks + 1))
[ "$(gains)" = "$before" ] || fail "--dry-run changed the gains: $(gains), before: $before"

expect 0 "${TUNE_RT[@]}" "${S[@]}" x --auto --apply --save "$T/g.par" &&
	out_has '^the new gains are on the card$' &&
	out_has '^step test with the new gains:$' &&
	out_has '^back at the start +0\.000000 mm \(position, 0 counts from where it started\)$'
after=$(gains)
for g in kp ti td kvff kaff; do
	checks=$((checks + 1))
	want=$(printed "$g")
	have=$(printf '%s\n' "$after" | awk -v n="$g" '$1 == n { print $3 }')
	awk -v a="$want" -v b="$have" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(a > 0 && d <= 1e-6 * a) }' ||
		fail "$g on the card is $have, --auto printed $want"
done
checks=$((checks + 1))
[ "$after" != "$before" ] || fail "--apply left the gains as they were"
# the saved file puts the tuned gains back after they were changed
expect 0 "${CTL_RT[@]}" "${S[@]}" params x kp=1 ti=0 td=0 kvff=0 kaff=0
expect 0 "${CTL_RT[@]}" "${S[@]}" params load "$T/g.par"
checks=$((checks + 1))
[ "$(gains)" = "$after" ] || fail "params load of --save: $(gains), tuned: $after"
checks=$((checks + 1))
grep -q '^\[x\]$' "$T/g.par" || fail "--save: no [x] section"
# a chirp from 5 Hz with the tuned gains (feed-forward, a high integral
# gain): below some 30 Hz the DAC the set-point drives is less than the
# PID's answer to the encoder's quantisation, and those frequencies are
# left out (said), not drawn as a plant
expect 0 "${TUNE_RT[@]}" "${S[@]}" x --chirp 5:150 --csv "$T/weak.csv" &&
	err_has 'frequencies \(5-[0-9.]* Hz\) left out: .*quantisation drowns the plant'
low=$(awk -F, 'NR == 2 { print $1 }' "$T/weak.csv")
checks=$((checks + 1))
awk -v f="$low" 'BEGIN { exit !(f > 15 && f < 60) }' ||
	fail "the chirp's lowest frequency kept is $low Hz"

# a phase margin the delay does not leave at that bandwidth: refused
before=$(gains)
expect 1 "${TUNE_RT[@]}" "${S[@]}" x --auto --apply --bandwidth 1500 --margin 60 &&
	err_has 'no PID reaches a phase margin of 60 deg at 1500 Hz.*nothing written'
checks=$((checks + 1))
[ "$(gains)" = "$before" ] || fail "a refused design changed the gains"
# a gain margin floor the default crossover's phase margin does not
# leave at that bandwidth: refused the same way
expect 1 "${TUNE_RT[@]}" "${S[@]}" x --auto --apply --bandwidth 1000 --gain-margin 12 &&
	err_has 'gain margin of [0-9.]* dB, below 12 dB.*nothing written'
checks=$((checks + 1))
[ "$(gains)" = "$before" ] || fail "a refused design changed the gains"
# the same floor with the crossover left to the design: a lower one
expect 0 "${TUNE_RT[@]}" "${S[@]}" x --auto --dry-run --gain-margin 12 &&
	out_has '^predicted, new gains +phase 45\.5 deg at [0-9.]* Hz, gain 1[2-9]\.[0-9] dB'
stop_sim

# the in-process card: the documented default plant
expect 0 "$TUNE" -d sim x --auto --enable --dry-run &&
	out_has '^plant gain g +30517[0-9.]* counts/s\^2 per DAC code$' &&
	out_has '^friction pole b/m +10 1/s$'
# the command as the docs give it: no --enable on the in-process card
expect 0 "$TUNE" -d sim x --auto --plot "$T/issue.png" &&
	out_has '^chirp with the new gains:$' && out_has '^the old gains are back on the card$'

# --plot: the step with the new gains, then a chirp with them, its Bode
# plot beside the step's picture and its measured margins beside the
# design's predicted ones (the card model's loop: they agree)
expect 0 "$TUNE" -d sim x --auto --enable --plot "$T/a.png" &&
	out_has '^step test with the new gains:$' &&
	out_has '^chirp with the new gains:$' &&
	out_has '^margins, new gains +predicted +measured \(chirp\)$' &&
	out_has '^the old gains are back on the card$'
# row NAME: "predicted measured" of that row of the table
row() {
	printf '%s\n' "$out" | sed -n "/^margins, new gains/,\$ s/^$1  *\([-0-9.]*\)  *\([-0-9.]*\).*/\1 \2/p"
}
for c in "crossover 10" "phase margin 1" "gain margin 0.5"; do
	set -- $c
	tol=${!#}
	name=${c% *}
	read -r pred meas <<<"$(row "$name")"
	checks=$((checks + 1))
	awk -v a="$pred" -v b="$meas" -v e="$tol" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(a != "" && b != "" && d <= e) }' ||
		fail "$name: predicted '$pred', measured '$meas' (tolerance $tol)"
done
for f in a.png a-bode.png; do
	checks=$((checks + 1))
	[ "$(head -c 8 "$T/$f" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] ||
		fail "--auto --plot did not write the PNG $f"
done

# usage errors
expect 2 "$TUNE" -d sim x --apply && err_has '--apply needs --auto'
expect 2 "$TUNE" -d sim x --step 0.01 --save f && err_has '--save needs --auto'
expect 2 "$TUNE" -d sim x --margin 50 --step 0.01 && err_has '--bandwidth, --margin or --gain-margin needs --auto'
expect 2 "$TUNE" -d sim x --gain-margin 6 --step 0.01 && err_has '--gain-margin needs --auto'
expect 2 "$TUNE" -d sim x --auto --gain-margin 40 && err_has '--gain-margin: 40 is not a gain margin 3\.\.30 dB'
expect 2 "$TUNE" -d sim x --auto --dry-run --apply && err_has '--dry-run writes nothing: not with --apply'
expect 2 "$TUNE" -d sim x --auto --dry-run --save f && err_has 'not with --save'
expect 2 "$TUNE" -d sim x --auto --margin 95 && err_has '--margin: 95 is not a phase margin 20\.\.89'
expect 2 "$TUNE" -d sim x --auto --bandwidth -5 && err_has "--bandwidth: '-5' is not a number above 0"
expect 2 "$TUNE" -d sim x --auto --travel 0 && err_has "--travel: '0'"
expect 2 "$TUNE" -d sim --auto && err_has 'which AXIS'
# found before anything moves: an output folder that cannot be written,
# a bandwidth beyond a quarter of the servo rate
expect 2 "$TUNE" -d sim x --auto --apply --save /nonexistent/x.par &&
	err_has 'save /nonexistent/x\.par: cannot write in /nonexistent: .*nothing moved'
expect 2 "$TUNE" -d sim x --auto --plot /nonexistent/t.png && err_has 'cannot write in /nonexistent'
expect 1 "$TUNE" -d sim x --auto --bandwidth 5000 &&
	err_has 'a bandwidth of 5000 Hz is beyond a quarter of the servo rate \(2500 Hz\): nothing moved'
checks=$((checks + 1))
[ -z "$out" ] || fail "--bandwidth 5000 identified before refusing: $out"
finish

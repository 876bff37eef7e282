#!/bin/bash
# sh2000-sim --clock-ppm: the serving line says the clock's error; a card
# at +100000 ppm (a period of 110 us) never runs more cycles in 4 s than
# its oscillator allows, which at the nominal 100 us it would exceed by
# 10 %; one at -50000 ppm runs more than the slow one.
# Cycles are read from the shared memory's cycle word. The cards run at
# SCHED_FIFO when permitted (../realtime.sh), so a busy machine does not
# hold one off the CPU more than the other; without it a loaded machine
# may still cost a served card cycles, never add any (cardmodel_clock
# measures the rates themselves, in-process).
. "$(dirname "$0")/../ctl/testlib.sh"
A=simclk-a-$$
B=simclk-b-$$

# servo cycles run so far: struct sh2000_shm's `cycles`, bytes 24..31
cycles() {
	od -An -t u8 -j 24 -N 8 "/dev/shm/sh2000-$1" | tr -d ' '
}

"${RT_CARD[@]}" "$SIM" -c 250 "$A" >"$T/out" 2>"$T/err" &
P=$!
SIM_PIDS="$SIM_PIDS $P"
wait_for "the ready line of sh2000-sim -c 250" file_has '^ready$' "$T/out"
checks=$((checks + 1))
grep -q "^sh2000-sim: serving sim:$A at /sh2000-$A (pid $P, real time, clock +250 ppm)$" "$T/out" ||
	fail "stdout: $(cat "$T/out") $(cat "$T/err")"
kill -TERM $P
wait $P
SIM_PIDS=""

start_sim "$A" --clock-ppm 100000 || finish
start_sim "$B" --clock-ppm -50000 || finish
# sample: the time before, both counts, the time after, read by one
# process at the hosts' priority so that the two cards are read together
sample() {
	"${RT_HOST[@]}" bash -c "date +%s%N; $(declare -f cycles); cycles $A; cycles $B; date +%s%N" |
		tr '\n' ' '
}
read -r t0 a0 b0 _ <<<"$(sample)"	# t0 before the first counts are read
sleep 4
read -r _ a1 b1 t1 <<<"$(sample)"	# t1 after the last
a=$((a1 - a0))
b=$((b1 - b0))
# between the two readings a server runs at most one cycle per period,
# plus the 50 ms it may have owed when the first was read
awk -v a="$a" -v b="$b" -v t="$((t1 - t0))" 'BEGIN {
	printf "# in %.3f s: %d cycles at +100000 ppm (at most %d), %d at -50000 ppm (at most %d)\n",
		t / 1e9, a, 1 + (t + 5e7) / 110000, b, 1 + (t + 5e7) / 95000 }'
checks=$((checks + 1))
awk -v a="$a" -v t="$((t1 - t0))" 'BEGIN { exit !(a <= 1 + (t + 5e7) / 110000 && a > 0) }' ||
	fail "+100000 ppm: $a cycles in $((t1 - t0)) ns, more than one per 110 us"
checks=$((checks + 1))
awk -v b="$b" -v t="$((t1 - t0))" 'BEGIN { exit !(b <= 1 + (t + 5e7) / 95000) }' ||
	fail "-50000 ppm: $b cycles in $((t1 - t0)) ns, more than one per 95 us"
checks=$((checks + 1))
[ "$b" -gt "$a" ] || fail "the fast card ran $b cycles, the slow one $a"
kill -TERM $SIM_PIDS
wait
SIM_PIDS=""
finish

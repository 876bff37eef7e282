#!/bin/bash
# sh2000-sim --clock-ppm: two served cards at +20000 and -20000 ppm run
# 1/1.02 and 1/0.98 of the nominal 10000 servo cycles per second of real
# time (counted in the shared memory's cycle word); the serving line says
# the clock's error.
. "$(dirname "$0")/../ctl/testlib.sh"
A=simclk-a-$$
B=simclk-b-$$

# servo cycles run so far: struct sh2000_shm's `cycles`, bytes 24..31
cycles() {
	od -An -t u8 -j 24 -N 8 "/dev/shm/sh2000-$1" | tr -d ' '
}

"$SIM" -c 250 "$A" >"$T/out" 2>"$T/err" &
P=$!
SIM_PIDS="$SIM_PIDS $P"
for _ in $(seq 100); do grep -q '^ready$' "$T/out" && break; sleep 0.05; done
checks=$((checks + 1))
grep -q "^sh2000-sim: serving sim:$A at /sh2000-$A (pid $P, real time, clock +250 ppm)$" "$T/out" ||
	fail "stdout: $(cat "$T/out") $(cat "$T/err")"
kill -TERM $P
wait $P
SIM_PIDS=""

start_sim "$A" --clock-ppm 20000 || finish
start_sim "$B" --clock-ppm -20000 || finish
sleep 0.2
# each count with the time half-way through reading it: on a loaded
# machine starting od takes a while
stamp() {
	local t0 c t1
	t0=$(date +%s%N)
	c=$(cycles "$1")
	t1=$(date +%s%N)
	echo "$c $(((t0 + t1) / 2))"
}
a0=$(stamp "$A")
b0=$(stamp "$B")
sleep 3
a1=$(stamp "$A")
b1=$(stamp "$B")
rate() {
	awk -v x="$1 $2" 'BEGIN { split(x, v, " ");
		printf "%.1f", (v[3] - v[1]) * 1e9 / (v[4] - v[2]) }'
}
ra=$(rate "$a0" "$a1")
rb=$(rate "$b0" "$b1")
echo "# card at +20000 ppm: $ra servo cycles per second (expected 9803.9)"
echo "# card at -20000 ppm: $rb servo cycles per second (expected 10204.1)"
# a loaded machine may deschedule a server past its catch-up window and
# cost both cycles; the slow card must still be clearly the slower, by
# 0.98 / 1.02 = 0.961 (test_clock measures each rate exactly)
checks=$((checks + 1))
awk -v a="$ra" -v b="$rb" 'BEGIN { r = a / b; printf "# ratio %.4f (expected 0.9608)\n", r;
	exit !(r > 0.94 && r < 0.985) }' ||
	fail "ratio of the two cards' rates: $ra / $rb, expected 0.98 / 1.02"
kill -TERM $SIM_PIDS
wait
SIM_PIDS=""
finish

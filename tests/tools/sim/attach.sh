#!/bin/bash
# sh2000-sim --attach PATH on a plain 2048-byte file standing in for the
# kernel card's /dev/sh2000-dsp-N page: the firmware boots into it (magic,
# version), its heartbeat advances in real time, an emergency stop written
# by a "host" into the file is acknowledged, and a stop clears the magic.
. "$(dirname "$0")/../ctl/testlib.sh"
RAM=$T/ram
head -c 2048 /dev/zero >"$RAM"

# word W of the RAM file (little-endian, as the driver's pread)
word() {
	od -An -tu2 --endian=little -j $((2 * $1)) -N 2 "$RAM" | tr -d ' '
}
setword() {
	printf "$(printf '\\%03o\\%03o' $(($2 & 255)) $(($2 >> 8)))" |
		dd of="$RAM" bs=2 count=1 seek="$1" conv=notrunc status=none
}

rm -f "$T/ready"
mkfifo "$T/ready"
"${RT_CARD[@]}" "$SIM" --attach "$RAM" --ready-fd 3 3>"$T/ready" >"$T/out" 2>"$T/err" &
SIM_PID=$!
SIM_PIDS="$SIM_PIDS $SIM_PID"
read -r -t "$WAIT_BOUND" line <"$T/ready"
checks=$((checks + 1))
[ "${line:-}" = ready ] || fail "not ready: $(cat "$T/err")"
checks=$((checks + 1))
grep -q "^sh2000-sim: card model attached to $RAM (pid $SIM_PID, real time)$" "$T/out" ||
	fail "stdout: $(cat "$T/out")"
checks=$((checks + 1))
CARD_H="$(dirname "$0")/../../../libsh2000/protocol/include/sh2000/card.h"
pmaj=$(sed -n 's/^#define[ \t]*SH2000_PROTO_MAJOR[ \t]*\([0-9]*\)u*.*/\1/p' "$CARD_H")
pmin=$(sed -n 's/^#define[ \t]*SH2000_PROTO_MINOR[ \t]*\([0-9]*\)u*.*/\1/p' "$CARD_H")
[ "$(word 1)" = $((0x5348)) ] && [ "$(word 2)" = $((pmaj * 256 + pmin)) ] ||
	fail "magic/version: $(word 1) $(word 2)"
checks=$((checks + 1))
[ "$(word 5)" = 1 ] || fail "state $(word 5), expected 1 (idle)"
# the heartbeat over at least 0.2 s: one count per 100 us servo cycle. The
# card runs at SCHED_FIFO (realtime.sh), so it keeps its rate (it catches
# up a stall of up to 50 ms); the 16-bit word wraps after 6.5 s
t0=$(date +%s%N)
h1=$(word 3)
sleep 0.2
h2=$(word 3)
t1=$(date +%s%N)
checks=$((checks + 1))
n=$(((h2 - h1 + 65536) % 65536))
if [ ${#RT_CARD[@]} = 0 ]; then
	[ "$n" -gt 0 ] || fail "heartbeat $h1 -> $h2 in $((t1 - t0)) ns (not at SCHED_FIFO: rate not judged)"
elif [ $((t1 - t0)) -lt 6000000000 ]; then
	awk -v n="$n" -v t="$((t1 - t0))" 'BEGIN { exit !(n >= 1800 && n <= t / 100000 + 501) }' ||
		fail "heartbeat $h1 -> $h2 ($n cycles) in $((t1 - t0)) ns, expected one per 100 us"
fi
# the host's emergency stop: ESTOP_REQ (word 0) +1 -> ESTOP_ACK (4), ESTOP (6)
setword 0 1
# one servo cycle once the server runs
checks=$((checks + 1))
ack_is_1() { [ "$(word 4)" = 1 ]; }
wait_for "ESTOP_ACK (word 4) to become 1" ack_is_1
[ "$(word 4)" = 1 ] && [ "$(word 5)" = 6 ] && [ $(($(word 6) & 4)) = 4 ] ||
	fail "estop not acted on: ack $(word 4) state $(word 5) faults $(word 6)"
stop_sim TERM
checks=$((checks + 1))
[ "$sim_rc" = 0 ] || fail "exit $sim_rc after SIGTERM"
checks=$((checks + 1))
[ "$(word 1)" = 0 ] || fail "magic $(word 1) left after stop (hosts would see a stalled card)"
checks=$((checks + 1))
grep -Eq "^sh2000-sim: stopped after [0-9]+ servo cycles, $RAM detached$" "$T/out" ||
	fail "stdout: $(cat "$T/out")"

# what cannot be attached: exit 3 and the reason
head -c 100 /dev/zero >"$T/small"
expect 3 "$SIM" --attach "$T/small" && err_has "^sh2000-sim: $T/small: 100 bytes, the RAM needs 2048$"
expect 3 "$SIM" --attach "$T/none" && err_has "^sh2000-sim: $T/none: cannot open: No such file"
expect 3 "$SIM" --attach "$T" && err_has "^sh2000-sim: $T: cannot open"
expect 2 "$SIM" --attach "$RAM" extra && err_has "takes no NAME"
finish

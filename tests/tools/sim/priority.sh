#!/bin/bash
# sh2000-sim's real-time priority: the servo loop takes SCHED_FIFO (60, or
# --priority N) when the system permits it, keeps ordinary scheduling with
# --priority=0 and when free-running, and when it is not permitted says so
# on stderr and serves all the same.
. "$(dirname "$0")/../ctl/testlib.sh"
NAME=simprio-$$
# the server's own choice is what is checked: start it at ordinary
# priority, not under testlib's chrt for served cards
RT_CARD=()

# policy PID: "SCHED_FIFO 60", "SCHED_OTHER 0"
policy() {
	chrt -p "$1" | awk -F': ' '/policy/ { split($2, p, "|"); pol = p[1] }
		/priority/ { pri = $2 } END { print pol, pri }'
}
# serving NAME WANT OPTIONS...: the server's policy is WANT
serving() {
	local name=$1 want=$2 got
	shift 2
	start_sim "$name" "$@" || return
	got=$(policy "$SIM_PID")
	checks=$((checks + 1))
	[ "$got" = "$want" ] || fail "sh2000-sim $*: $got, expected $want"
	expect 0 "$CTL" -d "sim:$name" status
	stop_sim
}

if chrt -f 1 true 2>/dev/null; then
	serving "$NAME" "SCHED_FIFO 60"
	checks=$((checks + 1))
	[ ! -s "$T/sim.err" ] || fail "stderr when permitted: $(cat "$T/sim.err")"
	serving "$NAME" "SCHED_FIFO 10" --priority 10
	serving "$NAME" "SCHED_OTHER 0" --priority=0
	serving "$NAME" "SCHED_OTHER 0" --free-run
	checks=$((checks + 1))
	[ ! -s "$T/sim.err" ] || fail "stderr when free-running: $(cat "$T/sim.err")"
else
	echo "# not permitted to take SCHED_FIFO here: only the refusal is checked"
fi

# refused: neither CAP_SYS_NICE (dropped from the bounding set, so not even
# root keeps it across exec) nor an RLIMIT_RTPRIO that allows it
if [ "$(id -u)" -eq 0 ]; then
	cat >"$T/unprivileged" <<SH
#!/bin/sh
exec prlimit --rtprio=0:0 setpriv --bounding-set=-sys_nice --inh-caps=-sys_nice "$SIM" "\$@"
SH
	chmod +x "$T/unprivileged"
	SIM=$T/unprivileged
fi
serving "$NAME" "SCHED_OTHER 0"
err=$(cat "$T/sim.err")
err_has "^sh2000-sim: no real-time priority \(SCHED_FIFO 60: Operation not permitted\): on a busy machine the card's servo cycles come late; allow it \(sh2000-sim\(1\), PRIORITY\) or use --priority=0$"
serving "$NAME" "SCHED_OTHER 0" --priority=0
checks=$((checks + 1))
[ ! -s "$T/sim.err" ] || fail "stderr with --priority=0: $(cat "$T/sim.err")"
finish

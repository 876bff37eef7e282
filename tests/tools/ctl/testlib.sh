# Helpers of the tools' black-box tests (sourced by tests/tools/ctl/*.sh and
# tests/tools/sim/*.sh). ctest passes the binaries as $CTL and $SIM.
set -u
: "${CTL:?CTL must name sh2000ctl}" "${SIM:?SIM must name sh2000-sim}"
: "${JSONQ:?JSONQ must name the tests JSON reader jsonq}"
unset SH2000_DEVICE
. "$(dirname "${BASH_SOURCE[0]}")/../realtime.sh"
# sh2000ctl as a host of a served card runs it (realtime.sh)
CTL_RT=("${RT_HOST[@]}" "$CTL")
# sh2000ctl as an operator's second terminal while another program is the
# host (streams, homes): below that host, which a starting sh2000ctl (a
# tenth of a second of CPU under the sanitizers) must never hold back
CTL_OP=("${RT_OPERATOR[@]}" "$CTL")
T=$(mktemp -d /tmp/sh2000-tooltest.XXXXXX)
fails=0
checks=0
SIM_PIDS=""

cleanup() {
	for p in $SIM_PIDS; do
		kill -TERM "$p" 2>/dev/null && wait "$p" 2>/dev/null
	done
	rm -rf "$T"
}
trap cleanup EXIT

fail() {
	echo "FAIL: $*" >&2
	fails=$((fails + 1))
}

# run CMD...: stdout in $out, stderr in $err, exit status in $rc
run() {
	"$@" >"$T/out" 2>"$T/err"
	rc=$?
	out=$(cat "$T/out")
	err=$(cat "$T/err")
}

# expect RC CMD...: run it and check the exit status
expect() {
	local want=$1
	shift
	checks=$((checks + 1))
	run "$@"
	if [ "$rc" != "$want" ]; then
		fail "'$*': exit $rc, expected $want; stdout: $out; stderr: $err"
		return 1
	fi
	return 0
}

# err_has REGEX / out_has REGEX: about the last run
err_has() {
	checks=$((checks + 1))
	printf '%s\n' "$err" | grep -Eq -- "$1" ||
		{ fail "stderr does not match /$1/: $err"; return 1; }
}
out_has() {
	checks=$((checks + 1))
	printf '%s\n' "$out" | grep -Eq -- "$1" ||
		{ fail "stdout does not match /$1/: $out"; return 1; }
}
err_lacks() {
	checks=$((checks + 1))
	if printf '%s\n' "$err" | grep -Eq -- "$1"; then
		fail "stderr matches /$1/ and should not: $err"
		return 1
	fi
}
out_lacks() {
	checks=$((checks + 1))
	if printf '%s\n' "$out" | grep -Eq -- "$1"; then
		fail "stdout matches /$1/ and should not: $out"
		return 1
	fi
}

# json_check POINTER OP VALUE...: about the last line of the last stdout,
# read as strict JSON by jsonq (json-c). OP: = and != (text), ~ T,TOL
# (|x - T| <= TOL), in LO,HI (LO < x < HI), has WORD (an array holds it).
json_check() {
	local line v p op want t e
	checks=$((checks + 1))
	line=$(printf '%s\n' "$out" | tail -n 1)
	while [ $# -ge 3 ]; do
		p=$1 op=$2 want=$3
		shift 3
		if ! v=$(printf '%s\n' "$line" | "$JSONQ" "$p" 2>&1); then
			fail "JSON: $v"
			return 1
		fi
		case $op in
		=) [ "$v" = "$want" ] ;;
		!=) [ "$v" != "$want" ] ;;
		'~') t=${want%,*} e=${want#*,}
		   awk -v v="$v" -v t="$t" -v e="$e" 'BEGIN { d = v - t; if (d < 0) d = -d; exit !(d <= e) }' ;;
		in) t=${want%,*} e=${want#*,}
		   awk -v v="$v" -v lo="$t" -v hi="$e" 'BEGIN { exit !(v > lo && v < hi) }' ;;
		has) printf '%s' "$v" | grep -Fq "\"$want\"" ;;
		*) false ;;
		esac || { fail "JSON $p is '$v', expected $op $want; line: $line"; return 1; }
	done
}

# json_column POINTER: that value of every stdout line, one per line
# (fails the test if a line is not strict JSON)
json_column() {
	printf '%s\n' "$out" | "$JSONQ" "$1" || fail "stdout lines not JSON: $out"
}

# start_sim NAME [OPTIONS...]: start sh2000-sim at the card's priority
# (realtime.sh; not with --free-run, which never sleeps), wait for its ready
# line on --ready-fd; sets $SIM_PID
start_sim() {
	local name=$1 line="" rt=("${RT_CARD[@]}")
	shift
	case " $* " in *" --free-run "* | *" -F "*) rt=() ;; esac
	rm -f "$T/ready"
	mkfifo "$T/ready"
	"${rt[@]}" "$SIM" -q --ready-fd 3 "$@" "$name" 3>"$T/ready" >"$T/sim.out" 2>"$T/sim.err" &
	SIM_PID=$!
	SIM_PIDS="$SIM_PIDS $SIM_PID"
	read -r -t "$WAIT_BOUND" line <"$T/ready"
	if [ "$line" != "ready" ]; then
		fail "sh2000-sim $name did not get ready within $WAIT_BOUND s: $(cat "$T/sim.err")"
		return 1
	fi
}

# stop_sim [SIGNAL]: stop the last server, wait for it; sets $sim_rc
stop_sim() {
	kill -"${1:-TERM}" "$SIM_PID"
	wait "$SIM_PID"
	sim_rc=$?
	SIM_PIDS=$(echo "$SIM_PIDS" | sed "s/ $SIM_PID\b//")
}

finish() {
	if [ "$fails" -ne 0 ]; then
		echo "$fails of $checks checks failed" >&2
		exit 1
	fi
	echo "all $checks checks passed"
	exit 0
}

# The protocol version this tree speaks, from its header (PMAJ.PMIN, and
# PROTO_VERSION as the card's VERSION word).
CARD_H="$(dirname "${BASH_SOURCE[0]}")/../../../libsh2000/protocol/include/sh2000/card.h"
PMAJ=$(sed -n 's/^#define[ \t]*SH2000_PROTO_MAJOR[ \t]*\([0-9]*\)u*.*/\1/p' "$CARD_H")
PMIN=$(sed -n 's/^#define[ \t]*SH2000_PROTO_MINOR[ \t]*\([0-9]*\)u*.*/\1/p' "$CARD_H")
PROTO_VERSION=$((PMAJ * 256 + PMIN))

# Helpers of the tools' black-box tests (sourced by tests/tools/ctl/*.sh and
# tests/tools/sim/*.sh). ctest passes the binaries as $CTL and $SIM.
set -u
: "${CTL:?CTL must name sh2000ctl}" "${SIM:?SIM must name sh2000-sim}"
unset SH2000_DEVICE
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
out_lacks() {
	checks=$((checks + 1))
	if printf '%s\n' "$out" | grep -Eq -- "$1"; then
		fail "stdout matches /$1/ and should not: $out"
		return 1
	fi
}

# json_check PROGRAM: python3 with the last line of the last stdout parsed
# as JSON in `d`; the program must exit 0 (use assert)
json_check() {
	checks=$((checks + 1))
	printf '%s\n' "$out" | tail -n 1 | python3 -c "import json,sys
d = json.loads(sys.stdin.read())
$1" 2>"$T/pyerr" || { fail "JSON check failed: $1: $(cat "$T/pyerr"); stdout: $out"; return 1; }
}

# start_sim NAME [OPTIONS...]: start sh2000-sim, wait for its ready line on
# --ready-fd; sets $SIM_PID
start_sim() {
	local name=$1 line=""
	shift
	rm -f "$T/ready"
	mkfifo "$T/ready"
	"$SIM" -q --ready-fd 3 "$@" "$name" 3>"$T/ready" >"$T/sim.out" 2>"$T/sim.err" &
	SIM_PID=$!
	SIM_PIDS="$SIM_PIDS $SIM_PID"
	read -r -t 10 line <"$T/ready"
	if [ "$line" != "ready" ]; then
		fail "sh2000-sim $name did not get ready: $(cat "$T/sim.err")"
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

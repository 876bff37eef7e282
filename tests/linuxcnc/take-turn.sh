# SPDX-License-Identifier: GPL-2.0-or-later
# shellcheck shell=bash disable=SC2034  # sets variables for the sourcing script
# Sourced by the scripts that start LinuxCNC or HAL (tests/linuxcnc/run,
# bench/lcnc-compare/run). There is one LinuxCNC per machine: its launcher
# ends any other instance, and HAL's shared memory and the installed
# hal_sh2000.so are the machine's. Runs from several trees, or a benchmark
# beside the suite, take turns on a lock instead of breaking each other.

# The user the runs start LinuxCNC as when run as root (stage.sh,
# bench/lcnc-compare/run): nothing else runs as it.
turn_user=sh2000-test

# turn_close_lock: a command prefix that runs the command without the
# turn's lock descriptor (9): LinuxCNC's daemons (linuxcncsvr, rtapi_app)
# would hold the lock after a run killed mid-way, and every later run
# would wait on them.
turn_close_lock=(sh -c 'exec "$@" 9>&-' sh)

# end_orphans: with the turn held, no run owns a LinuxCNC of the test
# user: what is left is a killed run's (a timeout's SIGKILL skips its
# clean-up, and LinuxCNC's daemons outlive it). End it as LinuxCNC's own
# launcher would: its processes, its lock file, HAL's shared memory.
end_orphans() {
	local uid p i
	local -a pids

	[ "$(id -u)" -eq 0 ] || return 0
	uid=$(id -u "$turn_user" 2>/dev/null) || return 0
	mapfile -t pids < <(pgrep -u "$uid")
	for p in $(pgrep -x rtapi_app); do
		[ "$(awk '/^Uid:/ { print $5 }' /proc/"$p"/status 2>/dev/null)" = "$uid" ] &&
			pids+=("$p")
	done
	# zombies are gone already (their parent, init here, may never reap
	# them): nothing to end, and kill -0 would wait on them
	for i in "${!pids[@]}"; do
		[ "$(awk '/^State:/ { print $2 }' /proc/"${pids[$i]}"/status 2>/dev/null)" = Z ] &&
			unset 'pids[i]'
	done
	pids=("${pids[@]}")
	if [ ${#pids[@]} -gt 0 ]; then
		echo "-- ending what a killed run left running as $turn_user (pids ${pids[*]})"
		kill -TERM "${pids[@]}" 2>/dev/null
		for i in $(seq 50); do	# 5 s to end, then killed
			for p in "${pids[@]}"; do
				kill -0 "$p" 2>/dev/null && break
			done || break
			sleep 0.1
		done
		kill -KILL "${pids[@]}" 2>/dev/null
	fi
	[ -e /tmp/linuxcnc.lock ] && [ "$(stat -c %u /tmp/linuxcnc.lock)" = "$uid" ] &&
		rm -f /tmp/linuxcnc.lock
	for p in $(ipcs -m | awk -v u="$turn_user" '$3 == u && $6 == 0 { print $2 }'); do
		ipcrm -m "$p" 2>/dev/null
	done
	return 0
}

# take_turn: wait (at most 20 minutes) until no other run holds the lock,
# end what a killed run left (end_orphans), then wait until no other
# LinuxCNC or HAL session runs (one started by hand, or by a tree that
# does not take turns); the lock is held until the calling script exits.
take_turn() {
	local lock=/tmp/sh2000-linuxcnc.lock waited=0

	exec 9>>"$lock" || return 1
	[ -O "$lock" ] && chmod 0666 "$lock" 2>/dev/null
	if ! flock -n 9; then
		echo "-- waiting for another LinuxCNC run on this machine ($lock)"
		flock -w 1200 9 || {
			echo "FAIL another LinuxCNC run held $lock for 20 minutes"
			return 1
		}
	fi
	end_orphans
	while [ -e /tmp/linuxcnc.lock ] || pgrep -x rtapi_app >/dev/null; do
		if [ "$waited" -ge 1200 ]; then
			echo "FAIL another LinuxCNC or HAL session ran for 20 minutes"
			return 1
		fi
		[ "$waited" -eq 0 ] &&
			echo "-- waiting for another LinuxCNC or HAL session to end"
		sleep 1
		waited=$((waited + 1))
	done
}

# SPDX-License-Identifier: GPL-2.0-or-later
# Sourced by the scripts that start LinuxCNC or HAL (tests/linuxcnc/run,
# bench/lcnc-compare/run). There is one LinuxCNC per machine: its launcher
# ends any other instance, and HAL's shared memory and the installed
# hal_sh2000.so are the machine's. Runs from several trees, or a benchmark
# beside the suite, take turns on a lock instead of breaking each other.

# take_turn: wait (at most 20 minutes) until no other run holds the lock,
# then until no other LinuxCNC or HAL session runs (one started by hand,
# or by a tree that does not take turns); the lock is held until the
# calling script exits.
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

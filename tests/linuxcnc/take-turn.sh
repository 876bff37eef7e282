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
# launcher would: its processes and its lock file (end_stale_segments,
# once no session runs, its shared memory). A lock file of a user no
# longer on the machine is a killed run's too: the test user is created
# anew on a machine whose /etc was reset but not its /tmp.
end_orphans() {
	local uid p i
	local -a pids

	[ "$(id -u)" -eq 0 ] || return 0
	[ -e /tmp/linuxcnc.lock ] &&
		! getent passwd "$(stat -c %u /tmp/linuxcnc.lock)" >/dev/null &&
		rm -f /tmp/linuxcnc.lock
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
	return 0
}

# end_stale_segments: with the turn held and no LinuxCNC or HAL session
# running, LinuxCNC's System V shared memory that no process is attached
# to is a killed session's, whoever owned it. It must go: LinuxCNC attaches
# to a segment it finds instead of making a new one, and the io controller
# then reads the killed session's last tool command, echoes its serial
# number, and task waits on every I/O command for good (the machine never
# comes on). Such segments outlive the processes, the test user (the
# owner may be a uid no user has) and a reset /tmp. The keys: the NML
# buffers' (linuxcnc.nml, the ones LinuxCNC's own launcher removes at
# exit), motion's (EMCMOT SHMEM_KEY, 100 by default), HAL's (HAL_KEY),
# the uspace RTAPI's (UUID_KEY) and halsampler's first channel
# (SAMPLER_SHMEM_KEY).
lcnc_nml=/usr/share/linuxcnc/linuxcnc.nml
end_stale_segments() {
	local -a keys
	local id

	[ "$(id -u)" -eq 0 ] || return 0
	mapfile -t keys < <(awk '$1 == "B" && $3 == "SHMEM" { printf "0x%08x\n", $10 }' \
		"$lcnc_nml" 2>/dev/null)
	keys+=(0x00000064 0x48414c32 0x48484c34 0x48534130)
	for id in $(ipcs -m | awk -v keys="${keys[*]}" '
		BEGIN { n = split(keys, k, " "); for (i = 1; i <= n; i++) stale[k[i]] = 1 }
		tolower($1) in stale && $6 == 0 { print $2 }'); do
		echo "-- removing a killed LinuxCNC session's shared memory (shmid $id)"
		ipcrm -m "$id" 2>/dev/null
	done
	return 0
}

# take_turn: wait (at most 20 minutes) until no other run holds the lock,
# end what a killed run left (end_orphans), then wait until no other
# LinuxCNC or HAL session runs (one started by hand, or by a tree that
# does not take turns) and remove what shared memory a killed session
# left (end_stale_segments); the lock is held until the calling script
# exits.
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
	end_stale_segments
}

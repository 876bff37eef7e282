# SPDX-License-Identifier: GPL-2.0-or-later
# shellcheck shell=bash disable=SC2034  # sets variables for the sourcing script
# What a LinuxCNC test script needs before it runs LinuxCNC (sourced by
# tests/linuxcnc/run and tests/linuxcnc/gantry): its turn on the machine
# (take-turn.sh: one LinuxCNC per machine), LinuxCNC installed (else exit
# 77, skipped), the built hal_sh2000.so where rtapi_app loads modules
# from, and as root the test user sh2000-test that runs LinuxCNC
# (rtapi_app refuses root), allowed real-time priority, with rtapi_app's
# threads and the user's card servers boosted to SCHED_FIFO as they appear
# (this kernel is not PREEMPT_RT: a busy machine would starve the 1 ms
# servo thread), and the card servers kept on the servo thread's CPU
# (stage_boost says why). tests/linuxcnc/run's header says why each step.
#
#   . stage.sh; stage_setup BUILD_DIR [SERVER...]
#       sets here, repo, build, work, as_user (a command prefix), user;
#       SERVER: the command names (as pgrep -x sees them) of the card
#       servers the script starts as the user, boosted beside rtapi_app
# Cleans up on exit: the module found before put back, the boost stopped,
# $work removed (copied first to $SH2000_KEEP_LOGS when that names a
# directory that does not exist yet: a failing run's logs and samples
# kept), and every pid in $stage_pids killed.

# shellcheck source=tests/linuxcnc/take-turn.sh
. "$(dirname "${BASH_SOURCE[0]}")/take-turn.sh"

stage_skip() { echo "SKIP: $*"; exit 77; }
stage_fail() { echo "FAIL $*"; echo "0 passed, 1 failed"; exit 1; }

stage_cleanup() {
	if [ -n "${stage_backup:-}" ]; then
		if [ "$stage_backup" = none ]; then rm -f "$stage_modules/hal_sh2000.so"
		else mv -f "$stage_backup" "$stage_modules/hal_sh2000.so"; fi
	fi
	for p in ${stage_pids:-}; do kill "$p" 2>/dev/null; done
	[ -n "${SH2000_KEEP_LOGS:-}" ] && [ -n "${work:-}" ] &&
		[ ! -e "$SH2000_KEEP_LOGS" ] && cp -a "$work" "$SH2000_KEEP_LOGS"
	[ -n "${work:-}" ] && rm -rf "$work"
}

# stage_boost UID [SERVER...]: SCHED_FIFO 70 for rtapi_app's threads
# (LinuxCNC's own take the top priorities on PREEMPT_RT), 60 for the
# user's card servers named SERVER (sh2000-sim's own priority), as they
# appear; all sleep most of the time. rtapi_app is setuid root and keeps
# the user only as its file-system uid. Every card server of the user
# (SERVER, sh2000-sim, sh2000_test_cardserver) is also kept on the CPUs of
# rtapi_app's servo thread (stage_pin).
stage_boost() {
	local uid=$1 p t prio name servers
	shift
	while :; do
		servers=
		for name in "$@"; do
			servers="$servers $(pgrep -u "$uid" -x "$name")"
		done
		for p in $(pgrep -x rtapi_app) $servers; do
			[ "$(awk '/^Uid:/ { print $5 }' /proc/"$p"/status 2>/dev/null)" = "$uid" ] ||
				continue
			prio=60
			[ "$(cat /proc/"$p"/comm 2>/dev/null)" = rtapi_app ] && prio=70
			for t in /proc/"$p"/task/*; do
				t=${t##*/}
				chrt -p "$t" 2>/dev/null | grep -q SCHED_FIFO ||
					chrt -f -p "$prio" "$t" 2>/dev/null
			done
		done
		stage_pin "$uid" "$@" sh2000-sim sh2000_test_car
		sleep 0.2
	done
}

# stage_pin UID SERVER...: the user's card servers (command names SERVER)
# on the CPUs rtapi_app runs its servo thread on (uspace pins its
# real-time threads, "rtapi_app:T#N", to one CPU). A stall of that CPU
# alone (the hypervisor descheduling the virtual CPU, a kernel section
# that does not yield) stops the servo thread but not a card served from
# the other CPU: with its ring some 30 periods deep, a stall of 30 ms ran
# the card dry in the middle of a homing ("segment queue ran dry
# mid-motion", LinuxCNC: "joint 0 following error"). A real card does not
# share the PC's stalls, but neither does a real installation run on a
# CPU that stops for 30 ms; on one CPU the card and the thread stop
# together, and a stall of both is caught up by the served card (it
# replays the cycles it missed) and by the thread (it runs its missed
# periods), as on a machine stalled whole.
stage_pin() {
	local uid=$1 p t cpus='' name
	shift
	for p in $(pgrep -x rtapi_app); do
		[ "$(awk '/^Uid:/ { print $5 }' /proc/"$p"/status 2>/dev/null)" = "$uid" ] ||
			continue
		for t in /proc/"$p"/task/*; do
			case $(cat "$t/comm" 2>/dev/null) in
			rtapi_app:T#*)
				cpus=$(awk '/^Cpus_allowed_list:/ { print $2 }' "$t/status" 2>/dev/null)
				break ;;
			esac
		done
	done
	[ -n "$cpus" ] || return 0
	for name in "$@"; do
		for p in $(pgrep -u "$uid" -x "$name"); do
			[ "$(awk '/^Cpus_allowed_list:/ { print $2 }' /proc/"$p"/status 2>/dev/null)" = "$cpus" ] ||
				taskset -a -p -c "$cpus" "$p" >/dev/null 2>&1
		done
	done
}

stage_setup() {
	here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
	repo=$(cd "$here/../.." && pwd)
	build=$(cd "$1" && pwd)
	user=$turn_user
	stage_modules=/usr/lib/linuxcnc/modules
	local module=$build/hal/hal_sh2000.so
	shift
	take_turn || { echo "0 passed, 1 failed"; exit 1; }
	"$here/install-deps" ||
		stage_skip "linuxcnc-uspace and linuxcnc-uspace-dev cannot be installed (apt-get failed): no LinuxCNC to test hal_sh2000 with"
	[ -f "$module" ] ||
		stage_fail "$module was not built: linuxcnc-uspace-dev was missing when $build was configured; configure it again (cmake -S $repo -B $build)"
	work=$(mktemp -d /tmp/sh2000-linuxcnc.XXXXXX)
	trap stage_cleanup EXIT
	as_user=()
	if [ "$(id -u)" -ne 0 ]; then
		cmp -s "$module" "$stage_modules/hal_sh2000.so" ||
			stage_skip "not root: cannot put $module into $stage_modules (rtapi_app loads modules only from there); run as root or install it there"
		return 0
	fi
	id "$user" >/dev/null 2>&1 ||
		useradd --system --create-home --home-dir "/var/lib/$user" \
			--shell /bin/bash "$user" ||
		stage_fail "cannot create the test user $user"
	stage_backup=none
	if [ -e "$stage_modules/hal_sh2000.so" ]; then
		stage_backup=$work/hal_sh2000.so.before
		cp -a "$stage_modules/hal_sh2000.so" "$stage_backup"
	fi
	install -m 0644 "$module" "$stage_modules/hal_sh2000.so"
	chown "$user" "$work"
	as_user=(setpriv --reuid="$user" --regid="$user" --init-groups
		--inh-caps=+sys_nice --ambient-caps=+sys_nice --
		env HOME="/var/lib/$user" USER="$user" LOGNAME="$user"
		"${turn_close_lock[@]}")
	stage_boost "$(id -u "$user")" "$@" &
	stage_pids="${stage_pids:-} $!"
}

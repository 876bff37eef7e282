# Helpers of the tools' black-box tests on served cards (sourced by
# ctl/testlib.sh and upload/upload_tests.sh): the priorities a real
# installation gives the processes, and bounded waits for a state.
#
# A served card (sh2000-sim) runs in real time, and so does every program
# that streams to it: the card's ring lasts about 100 ms of records, its
# host timeout is 100 ms, and a client judges a heartbeat stuck after
# 100 ms. On a machine with a busy process per core an ordinary process can
# be held off the CPU for longer than that, which a real card never is. So
# the tests run, when SCHED_FIFO is permitted (the suite runs as root):
#   RT_CARD      the served card, above everything else here (as the card's
#                own DSP is never descheduled),
#   RT_HOST      the programs that command or stream to it (sh2000ctl,
#                sh2000-upload, sh2000-tune): below the card,
#   RT_OPERATOR  a test's own step that must act while a motion is under
#                way (a second signal during a stop; sh2000ctl's status
#                polls, STOP or live parameters beside the host): below
#                the host, which it must never hold off a core (at equal
#                SCHED_FIFO priority, a starting sanitized sh2000ctl did
#                for a tenth of a second when the test had one core).
# All of them sleep between their polls, so none takes a core for itself.
# Without the permission they run as they are and the tests say so once.
RT_CARD=()
RT_HOST=()
RT_OPERATOR=()
if chrt -f 60 true 2>/dev/null; then
	RT_CARD=(chrt -f 60)
	RT_HOST=(chrt -f 50)
	RT_OPERATOR=(chrt -f 40)
else
	echo "# SCHED_FIFO not permitted: the served cards and their hosts run" \
		"at ordinary priority (a loaded machine may starve them)" >&2
fi

# How long a wait for a state may take before the test fails: generous,
# since only a broken tool never reaches the state.
WAIT_BOUND=${WAIT_BOUND:-60}

# wait_for WHAT CMD...: run CMD until it succeeds, every 20 ms, for at most
# WAIT_BOUND seconds; on timeout fail (the caller's fail) naming WHAT.
wait_for() {
	local what=$1 end=$((SECONDS + WAIT_BOUND))
	shift
	until "$@"; do
		if [ "$SECONDS" -ge "$end" ]; then
			fail "waited $WAIT_BOUND s for $what"
			return 1
		fi
		sleep 0.02
	done
}

# file_has REGEX FILE: FILE exists and a line matches (for wait_for)
file_has() {
	grep -Eq -- "$1" "$2" 2>/dev/null
}

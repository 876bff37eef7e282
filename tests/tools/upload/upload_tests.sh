#!/usr/bin/env bash
# Black-box tests of sh2000-upload: upload_tests.sh NAME runs one (ctest
# tool_upload_NAME). Environment from CMake: UPLOAD, CHECK (trace_check),
# PROBE, SIM (sh2000-sim or empty), DATA, EXAMPLES, WORK (scratch dir).
# Exit 0 pass, 1 fail, 77 skipped.
set -uo pipefail

rm -rf "$WORK" && mkdir -p "$WORK" && cd "$WORK" || exit 1
failures=0

fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
ok() { echo "ok: $*"; }
# expect CODE DESCRIPTION -- command...: runs it, stdout/stderr to out/err
expect() {
	local want=$1 what=$2 got
	shift 3
	"$@" >out 2>err
	got=$?
	if [ "$got" -ne "$want" ]; then
		fail "$what: exit $got, expected $want"
		sed 's/^/  stderr: /' err | head -n 20
		return 1
	fi
	ok "$what: exit $got"
}
# value KEY FILE: the KEY=value line of trace_check's output
value() { sed -n "s/^$1=//p" "$2" | head -n 1; }
# cmp_le A B (floats)
le() { awk -v a="$1" -v b="$2" 'BEGIN { exit !(a <= b) }'; }
ge() { awk -v a="$1" -v b="$2" 'BEGIN { exit !(a >= b) }'; }
has() { grep -qE -- "$1" "$2" || { fail "'$1' not in $2:"; sed 's/^/  /' "$2" | head -n 20; }; }
# an end point within tol mm of x,y,z,a
near() {
	awk -v got="$1" -v want="$2" -v tol="$3" 'BEGIN {
		n = split(got, g, ","); split(want, w, ",");
		for (i = 1; i <= 4; i++) { d = g[i] - w[i]; if (d < 0) d = -d; if (d > tol) exit 1 }
		exit (n != 4) }'
}
no_motion() { # the trace file must not exist: nothing was streamed
	[ ! -e "$1" ] || fail "$1 exists: the run started"
}
# the served cards' tests: priorities and bounded waits
. "$(dirname "$0")/../realtime.sh"
# sh2000-upload streams to a served card at the hosts' priority
UPLOAD_RT=("${RT_HOST[@]}" "$UPLOAD")

t_geometry() {
	expect 0 "square + circle on sim" -- "$UPLOAD" -q -d sim --trace tr.csv "$DATA/square_circle.ngc" || return
	"$CHECK" tr.csv header >h && [ "$(value header_ok h)" = 1 ] || fail "trace header"
	ge "$(value rows h)" 100000 || fail "$(value rows h) rows: expected one per servo cycle (> 100000)"
	"$CHECK" tr.csv segments >s
	[ "$(value segments s)" = 5 ] || { fail "5 motions expected"; cat s; return; }
	# the square at F1200: corners may be rounded by the corner tolerance
	# (10 um); the lines themselves are exact
	"$CHECK" tr.csv poly 2 10,10 60,10 60,60 10,60 10,10 >sq
	le "$(value cmd_dev_um sq)" 10 || fail "square: set-point $(value cmd_dev_um sq) um off the square"
	le "$(value act_dev_um sq)" 12 || fail "square: encoder $(value act_dev_um sq) um off the square"
	# the circle R20 at F9000 (150 mm/s): compensated, the card's
	# B-spline runs on the circle
	"$CHECK" tr.csv circle 4 100 35 20 >c
	le "$(value cmd_dev_um c)" 0.5 || fail "circle: set-point radius off by $(value cmd_dev_um c) um"
	le "$(value act_dev_um c)" 2 || fail "circle: encoder radius off by $(value act_dev_um c) um"
	ok "square $(value cmd_dev_um sq) um, circle $(value cmd_dev_um c) um (set-point)"
	"$CHECK" tr.csv end >e
	[ "$(value cmd e)" = "70.000000,35.000000,0.000000,0.000000" ] || fail "end set-point $(value cmd e), expected exactly 70,35,0,0"
	near "$(value act e)" 70,35,0,0 0.001 || fail "end encoder $(value act e)"
	has "max following error" out
}

t_raw() {
	expect 0 "compensated" -- "$UPLOAD" -q -d sim --trace c.csv "$DATA/square_circle.ngc" || return
	expect 0 "--raw" -- "$UPLOAD" -q -d sim --raw --trace r.csv "$DATA/square_circle.ngc" || return
	has "compensation off" out
	"$CHECK" c.csv circle 4 100 35 20 >cc
	"$CHECK" r.csv circle 4 100 35 20 >rc
	local c r
	c=$(value cmd_dev_um cc)
	r=$(value cmd_dev_um rc)
	echo "circle set-point radius error: compensated $c um, raw $r um"
	ge "$r" 0.3 || fail "--raw: the card's B-spline should cut the circle (>= 0.3 um), got $r um"
	ge "$r" "$(awk -v c="$c" 'BEGIN { print 10 * c }')" || fail "--raw ($r um) not 10 x worse than compensated ($c um)"
	"$CHECK" r.csv end >e
	[ "$(value cmd e)" = "70.000000,35.000000,0.000000,0.000000" ] || fail "--raw end $(value cmd e)"
}

# bad FILE LINE:COL PATTERN: exit 5, the position on stderr, nothing moved
bad() {
	expect 5 "$1" -- "$UPLOAD" -q -d sim --trace tr.csv "$DATA/$1" || return
	has "^$DATA/$1:$2: error: $3" err
	has "nothing moved" err
	no_motion tr.csv
}
t_bad_unknown() { bad bad_unknown.ngc 4:1 "unknown G code G12"; }
t_bad_arc() { bad bad_arc.ngc 3:1 "radius to end of arc differs"; }
t_bad_nan() { bad bad_nan.csv 4:5 "y: 'nan' is not a number"; }
t_bad_feed() { bad bad_feed.ngc 3:1 "G1 move with zero feed rate"; }
# found by the planning pass, not by the reader
t_bad_plan() { bad bad_plan.ngc 3:1 "line: end X 30000.000 mm is beyond"; }

t_warnings() {
	expect 0 "spindle, coolant and tool words" -- "$UPLOAD" -q -d sim "$DATA/warnings.ngc" || return
	local k n
	for k in "S1000 \(spindle speed\)" "M3 \(spindle" "M8 \(coolant" "T2 \(tool select\)" "M6 \(tool change\)"; do
		n=$(grep -cE "warning: $k" err)
		[ "$n" = 1 ] || fail "warning '$k' printed $n times, expected once"
	done
	n=$(grep -c "warning:" err)
	[ "$n" = 5 ] || fail "$n warnings, expected 5 (one per kind):"
	grep -qE "warning: (S2000|S3000|M4|M5|M9) " err && fail "a later word of a warned kind was reported again"
	has "done" out
}

t_csv() {
	expect 0 "CSV" -- "$UPLOAD" -q -d sim --trace tr.csv "$EXAMPLES/pocket.csv" || return
	"$CHECK" tr.csv end >e
	[ "$(value cmd e)" = "0.000000,0.000000,5.000000,0.000000" ] || fail "CSV end $(value cmd e), expected 0,0,5,0"
	"$CHECK" tr.csv header >h
	[ "$(value header_ok h)" = 1 ] || fail "header"
	# a CSV without feeds needs --feed
	printf 'x,y\n0,0\n5,0\n5,5\n' >nofeed.csv
	expect 5 "CSV without feed" -- "$UPLOAD" -q -d sim nofeed.csv
	expect 0 "CSV with --feed" -- "$UPLOAD" -q -d sim --feed 600 --trace f.csv nofeed.csv
	"$CHECK" f.csv end >e
	[ "$(value cmd e)" = "5.000000,5.000000,0.000000,0.000000" ] || fail "--feed CSV end $(value cmd e)"
}

t_json() {
	expect 0 "JSON NURBS" -- "$UPLOAD" -q -d sim --trace tr.csv "$EXAMPLES/wave.json" || return
	"$CHECK" tr.csv end >e
	[ "$(value cmd e)" = "50.000000,0.000000,0.000000,0.000000" ] || fail "JSON end $(value cmd e), expected 50,0,0,0"
	# --trace-every 10 keeps every tenth row
	expect 0 "--trace-every 10" -- "$UPLOAD" -q -d sim --trace-every 10 --trace t10.csv "$EXAMPLES/wave.json" || return
	local n1 n10
	n1=$(($(wc -l <tr.csv) - 1))
	n10=$(($(wc -l <t10.csv) - 1))
	[ "$n10" -eq $(((n1 + 9) / 10)) ] || fail "--trace-every 10: $n10 rows of $n1"
	[ "$(sed -n 3p t10.csv | cut -d, -f1)" = "$(sed -n 12p tr.csv | cut -d, -f1)" ] || fail "--trace-every 10: row 2 is not sample 11"
	# --format beats the name
	cp "$EXAMPLES/wave.json" curve.txt
	expect 0 "--format json" -- "$UPLOAD" -q -d sim -f json curve.txt
	expect 2 "no format from the name" -- "$UPLOAD" -q -d sim curve.txt
	has "use --format" err
}

t_override() {
	expect 0 "100 %" -- "$UPLOAD" -q -d sim "$DATA/arc.ngc" || return
	local t1 t2
	t1=$(sed -n 's/^  time  *\([0-9.]*\) s.*/\1/p' out)
	expect 0 "--feed-override 50" -- "$UPLOAD" -q -d sim -o 50 --trace tr.csv "$DATA/arc.ngc" || return
	t2=$(sed -n 's/^  time  *\([0-9.]*\) s.*/\1/p' out)
	echo "card time: $t1 s at 100 %, $t2 s at 50 %"
	# feed moves take twice as long; the short rapids hardly change
	awk -v a="$t1" -v b="$t2" 'BEGIN { r = b / a; exit !(r > 1.8 && r < 2.05) }' ||
		fail "50 % override: $t2 s against $t1 s"
	"$CHECK" tr.csv end >e
	[ "$(value cmd e)" = "20.000000,10.000000,0.000000,0.000000" ] || fail "end $(value cmd e)"
}

t_dry_run() {
	expect 0 "--dry-run" -- "$UPLOAD" -d sim --dry-run --trace tr.csv --plot p.png "$EXAMPLES/part.ngc" || return
	has "nothing moved \(--dry-run\)" out
	has "planned time +[0-9.]+ s" out
	has "axes moved +x y z" out
	has "peak acceleration +[0-9.]+ % of amax \([xyza]\)$" out
	has "planner margin +0\.950$" out
	no_motion tr.csv
	no_motion p.png
	expect 5 "--dry-run finds the planner's errors" -- "$UPLOAD" -d sim --dry-run "$DATA/bad_plan.ngc"
}

t_usage() {
	expect 2 "no file" -- "$UPLOAD" -d sim
	expect 2 "unknown option" -- "$UPLOAD" --frobnicate -d sim x.ngc
	has "Try 'sh2000-upload --help'" err
	expect 2 "two files" -- "$UPLOAD" -d sim a.ngc b.ngc
	expect 2 "--plot x.jpg" -- "$UPLOAD" -d sim --plot x.jpg "$EXAMPLES/part.ngc"
	expect 2 "--feed-override 300" -- "$UPLOAD" -d sim -o 300 "$EXAMPLES/part.ngc"
	expect 2 "--trace-every 0" -- "$UPLOAD" -d sim --trace-every 0 "$EXAMPLES/part.ngc"
	expect 2 "--format xml" -- "$UPLOAD" -d sim --format xml "$EXAMPLES/part.ngc"
	expect 0 "--help" -- "$UPLOAD" --help
	has "Exit codes" out
	expect 0 "--version" -- "$UPLOAD" --version
	has "^sh2000-upload [0-9]" out
	has "^libsh2000 [0-9.]+ \(libsh2000\.so\.[0-9]+\)$" out
	has "^protocol 1\.[0-9]+$" out
	has "^driver ABI [0-9]+$" out
	expect 1 "unreadable file" -- "$UPLOAD" -d sim nonexistent.ngc
	has "nonexistent.ngc" err
}

t_device() {
	expect 3 "no such served card" -- "$UPLOAD" -d sim:upload-test-none "$EXAMPLES/part.ngc"
	has "sim:upload-test-none" err
	expect 3 "bad device string" -- "$UPLOAD" -d io:0x301 "$EXAMPLES/part.ngc"
}

t_rs274_missing() {
	mkdir -p bin
	ln -sf "$(command -v true)" bin/true
	expect 6 "--rs274 without rs274" -- env PATH="$WORK/bin" "$UPLOAD" -d sim --rs274 "$DATA/arc.ngc" || return
	has "linuxcnc-uspace" err
	expect 2 "--rs274 with CSV" -- "$UPLOAD" -d sim --rs274 -f csv "$DATA/arc.ngc"
}

t_rs274() {
	# a stand-in for LinuxCNC's rs274: checks its arguments, and that its
	# HOME is its own directory (rs274 keeps \$HOME/.tool.mmap, which two
	# at once share and die of), prints the canonical commands rs274
	# gives for arc.ngc
	mkdir -p bin
	cat >bin/rs274 <<EOS
#!/bin/sh
[ "\$1" = -g ] && [ "\$2" = -t ] && [ -f "\$3" ] && [ "\$4" = -v ] && [ -f "\$5" ] && [ -f "\$6" ] || { echo "fake rs274: bad arguments: \$*" >&2; exit 1; }
[ "\$HOME" = "\$(dirname "\$3")" ] || { echo "fake rs274: HOME \$HOME is not its own" >&2; exit 1; }
touch "\$HOME/.tool.mmap"
cat "$DATA/arc.canon"
EOS
	chmod +x bin/rs274
	expect 0 "--rs274 (stand-in)" -- env PATH="$WORK/bin:$PATH" "$UPLOAD" -q -d sim --rs274 --trace c.csv "$DATA/arc.ngc" || return
	expect 0 "built-in parser" -- "$UPLOAD" -q -d sim --trace g.csv "$DATA/arc.ngc" || return
	"$CHECK" c.csv end >ec
	"$CHECK" g.csv end >eg
	[ "$(value cmd ec)" = "20.000000,10.000000,0.000000,0.000000" ] || fail "rs274 end $(value cmd ec)"
	[ "$(value cmd ec)" = "$(value cmd eg)" ] || fail "rs274 and built-in ends differ"
	"$CHECK" c.csv segments >s
	[ "$(value segments s)" -ge 1 ] || fail "no motion through rs274"
	# rs274 stops printing at an error in the G-code: nothing moves, and
	# its output is kept for the positions in the messages
	cat >bin/rs274 <<EOS
#!/bin/sh
head -n 8 "$DATA/arc.canon"
echo "fake rs274: Near line 5 of \$6: some error" >&2
exit 1
EOS
	expect 5 "--rs274, rs274 fails" -- env PATH="$WORK/bin:$PATH" "$UPLOAD" -q -d sim --rs274 --trace e.csv "$DATA/arc.ngc" || return
	has "fake rs274: Near line 5" err
	has "rs274.canon:8:1: error: no PROGRAM_END" err
	has "rs274's output is kept in /.*/rs274.canon" err
	no_motion e.csv
	rm -rf "$(sed -n "s/.*kept in \(.*\)\/rs274.canon/\1/p" err)"
}

t_plot() {
	expect 0 "--plot PNG" -- "$UPLOAD" -q -d sim --plot p.png "$DATA/arc.ngc" || return
	has "plot +p.png" out
	[ "$(head -c 8 p.png | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] || fail "p.png is not a PNG"
	expect 0 "--plot SVG" -- "$UPLOAD" -q -d sim --plot p.svg "$DATA/arc.ngc" || return
	grep -q "<svg" p.svg || fail "p.svg is not SVG"
}

t_plot_missing() {
	mkdir -p bin
	expect 6 "--plot without gnuplot" -- env PATH="$WORK/bin" "$UPLOAD" -d sim --trace tr.csv --plot p.png "$DATA/arc.ngc" || return
	has "gnuplot-nox" err
	no_motion tr.csv
}

t_pause() {
	# no terminal: a line on stdin resumes; M1 is skipped by default
	echo | "$UPLOAD" -d sim --trace tr.csv "$DATA/pause.ngc" >out 2>err
	local rc=$?
	[ "$rc" = 0 ] || { fail "M0 with a line on stdin: exit $rc"; cat err; return; }
	has "pause.ngc:3:1: M0: paused" err
	has "resuming" err
	has "M1 optional stops are skipped" err
	has "progress 100% \\([0-9.]+ s, line 6\\)" err
	"$CHECK" tr.csv end >e
	[ "$(value cmd e)" = "0.000000,5.000000,0.000000,0.000000" ] || fail "end $(value cmd e)"
	# --optional-stop: M1 pauses too; two lines resume twice
	printf '\n\n' | "$UPLOAD" -d sim --optional-stop "$DATA/pause.ngc" >out 2>err
	[ $? = 0 ] || fail "--optional-stop: exit $?"
	[ "$(grep -c ': paused' err)" = 2 ] || fail "--optional-stop: expected 2 pauses"
	# SIGUSR1 resumes when stdin has nothing to say
	rm -f usr1.err
	"$UPLOAD" -d sim "$DATA/pause.ngc" >out 2>usr1.err </dev/null &
	local pid=$! i
	wait_for "the pause at M0" file_has "paused" usr1.err
	kill -USR1 $pid
	wait $pid
	rc=$?
	[ "$rc" = 0 ] || fail "M0 resumed by SIGUSR1: exit $rc"
	has "SIGUSR1" usr1.err
	has "resuming" usr1.err
}

t_fault() {
	expect 4 "a run into the limit switch" -- "$UPLOAD" -q -d sim "$DATA/limit.ngc"
	has "sim: axis x: limit switch" err
	has "limit.ngc:3: the card was running this block" err
	# a program path longer than the message buffer: the location is cut
	# short, the buffer is not overrun (ASan saw a stack overflow here)
	local long
	long=$WORK/$(printf 'd%.0s' $(seq 150))/$(printf 'e%.0s' $(seq 150))
	mkdir -p "$long" && cp "$DATA/limit.ngc" "$long/" || fail "mkdir $long"
	expect 4 "a run into the limit switch, long path" -- "$UPLOAD" -q -d sim "$long/limit.ngc"
	has "sim: axis x: limit switch" err
	has "the card was running this block" err
}

start_sim() { # start_sim NAME: sh2000-sim in the background, ready
	[ -n "$SIM" ] && [ -x "$SIM" ] || { echo "sh2000-sim not built: skipped"; exit 77; }
	"${RT_CARD[@]}" "$SIM" --quiet --ready-fd 3 "$1" 3>ready 2>sim.err &
	simpid=$!
	wait_for "sh2000-sim $1 to get ready" file_has ready ready && return 0
	cat sim.err
	kill $simpid
	exit 1
}
stop_sim() {
	kill -TERM $simpid
	wait $simpid || fail "sh2000-sim exit $?"
}

t_shm() {
	local name=upload-test-$$
	start_sim $name
	"$PROBE" sim:$name >p0 || fail "probe"
	expect 0 "run on sim:$name" -- "${UPLOAD_RT[@]}" -q -d sim:$name --trace tr.csv "$DATA/arc.ngc"
	"$CHECK" tr.csv end >e
	near "$(value cmd e)" 20,10,0,0 0.0001 || fail "end $(value cmd e)"
	ge "$(value rows e)" 50 || fail "only $(value rows e) rows (one per status poll)"
	"$PROBE" sim:$name >p1
	has "state=1 fill=0 enabled=7 cmd=20.0000,10.0000,0.0000,0.0000" p1
	# a bad program leaves the served card as it was
	expect 5 "bad program on sim:$name" -- "${UPLOAD_RT[@]}" -q -d sim:$name "$DATA/bad_unknown.ngc"
	"$PROBE" sim:$name >p2
	cmp -s p1 p2 || { fail "the card changed after a bad program"; cat p1 p2; }
	expect 5 "plan error on sim:$name" -- "${UPLOAD_RT[@]}" -q -d sim:$name "$DATA/bad_plan.ngc"
	"$PROBE" sim:$name >p3
	cmp -s p1 p3 || { fail "the card changed after a plan error"; cat p1 p3; }
	# the planning pass holds the program to the card's soft limits: the
	# arc of arc.ngc's line 5 runs from X10 to X0, refused when added
	"$PROBE" sim:$name 0 soft_min 5 >/dev/null || fail "setting soft_min"
	expect 5 "beyond a soft limit on sim:$name" -- "${UPLOAD_RT[@]}" -q -d sim:$name "$DATA/arc.ngc"
	has "arc.ngc:5:1: error: arc: end X 0\.000000 mm is beyond the soft limit: the bound is 4\.998000 mm" err
	"$PROBE" sim:$name >p4
	cmp -s p1 p4 || { fail "the card changed after a soft-limit error"; cat p1 p4; }
	stop_sim
}

enabled_shown() { # enabled_shown NAME MASK: sim:NAME shows MASK enabled
	"$PROBE" sim:$1 | grep -q "enabled=$2 "
}
enabled_is() { # enabled_is NAME MASK: wait until sim:NAME shows MASK enabled
	wait_for "sim:$1 to show the axes $2 enabled" enabled_shown "$1" "$2"
}
running_with_records() { # the served card NAME runs with records queued
	"$PROBE" sim:$1 | grep -Eq "^state=2 fill=[1-9]"
}
card_cycle_past() { # card_cycle_past NAME CYCLE: sim:NAME has run past CYCLE
	local c
	c=$("$PROBE" sim:$1 cycle) && [ "$c" -gt "$2" ]
}
card_time_passes() { # card_time_passes NAME CYCLES: wait for the card's own time
	local c0
	c0=$("$PROBE" sim:$1 cycle) || { fail "probe sim:$1 cycle"; return 1; }
	wait_for "$2 servo cycles of sim:$1" card_cycle_past "$1" $((c0 + $2))
}

# A program that moves Y alone, with X disabled at rest off the binary
# fractions (123.4568 mm): X is not "moved" (the planner leaves a held axis
# an ulp or so off such a start), so it is not enabled and stays as it is.
t_moved_axes() {
	[ -n "${CTL:-}" ] && [ -x "$CTL" ] || { echo "sh2000ctl not built: skipped"; exit 77; }
	local name=upload-moved-$$
	start_sim $name
	# each step once the card shows the last (a served card acknowledges a
	# command a moment before its state word shows it)
	# (the servo settles on the end point before X is disabled: a
	# disabled axis coasts on whatever speed its loop still has)
	"${RT_HOST[@]}" "$CTL" -d sim:$name enable x >ctl.out 2>&1 && enabled_is $name 1 &&
		"${RT_HOST[@]}" "$CTL" -d sim:$name move x=123.4568 --feed 100 >>ctl.out 2>&1 &&
		card_time_passes $name 2000 &&
		"${RT_HOST[@]}" "$CTL" -d sim:$name disable x >>ctl.out 2>&1 && enabled_is $name 0 ||
		{ fail "sh2000ctl: X to 123.4568 mm, disabled"; cat ctl.out; }
	printf 'G21 G90 G17 F3000\nG1 Y5\nM2\n' >y.ngc
	expect 0 "--dry-run of a move on Y" -- "${UPLOAD_RT[@]}" -d sim:$name --dry-run y.ngc &&
		has "axes moved +y$" out
	expect 0 "a move on Y" -- "${UPLOAD_RT[@]}" -d sim:$name y.ngc
	grep -q "enabling axes y$" err || { fail "enabled more than y:"; cat err; }
	"$PROBE" sim:$name >p
	has "state=1 fill=0 enabled=2 cmd=123\.45[67][0-9],5\.0000,0\.0000,0\.0000" p
	stop_sim
}

# The first pass judges the acceleration of the set-points on the card's
# own limits (the rule itself: tests/lib/test_limits.c test_accel_guard).
# This program, two nearly straight moves, once took Z to 2.5 times amax
# at amax 20000 and was refused; it now plans within amax there and runs
# to its end point, as it does at the card model's 5000.
t_accel_guard() {
	[ -n "${CTL:-}" ] && [ -x "$CTL" ] || { echo "sh2000ctl not built: skipped"; exit 77; }
	local name=upload-accel-$$ f=$DATA/accel_guard.ngc a
	start_sim $name
	for a in 20000 5000; do
		"${RT_HOST[@]}" "$CTL" -d sim:$name params x amax=$a + params y amax=$a + params z amax=$a >ctl.out 2>&1 ||
			{ fail "sh2000ctl: amax $a"; cat ctl.out; }
		expect 0 "amax $a: runs" -- "${UPLOAD_RT[@]}" -q -d sim:$name "$f"
		"$PROBE" sim:$name >p
		has "cmd=0\.0566,-0\.0497,-1\.6596" p
		"${RT_HOST[@]}" "$CTL" -d sim:$name move x=0 y=0 z=0 --feed 100 >ctl.out 2>&1 ||
			{ fail "sh2000ctl: back to 0"; cat ctl.out; }
	done
	stop_sim
}

# Where the planner alone would take an axis past its amax, the first pass
# plans the program again with a smaller margin and says so (not under
# -q); the plan it runs keeps amax and ends where the program does (the
# fine set-points measured: tests/planner/test_safe.c test_accel_fit).
t_accel_fit() {
	local f=$DATA/accel_fit.ngc peak
	expect 0 "--dry-run" -- "$UPLOAD" -d sim --dry-run "$f" || return
	has "planner margin +0\.9[0-4][0-9] \(planned [0-9]+ times: with a larger one the set-points passed an axis' amax\)$" out
	has "accel_fit.ngc: planned with the margin 0\.9[0-4][0-9], not 0\.950" err
	peak=$(sed -n 's/^  peak acceleration *\([0-9.]*\) % .*/\1/p' out)
	echo "peak acceleration ${peak} % of amax"
	[ -n "$peak" ] && le "$peak" 100 || fail "peak acceleration '$peak' % of amax"
	expect 0 "runs" -- "$UPLOAD" -q -d sim --trace tr.csv "$f" || return
	grep -q "planned with the margin" err && fail "-q: the margin message given"
	"$CHECK" tr.csv end >e
	[ "$(value cmd e)" = "13.500000,7.500000,0.000000,0.000000" ] || fail "end set-point $(value cmd e), expected exactly 13.5,7.5,0,0"
}

# An axis the program never moves is held still: its limits do not bound
# the plan. With X, Y and Z at 20000 mm/s^2, the plan with a slow A (5000)
# takes the time of the plan with a fast one (0.558 s; the least amax of
# all four axes made it 0.618 s); it runs to its end, and A is not
# enabled.
t_still_axes() {
	[ -n "${CTL:-}" ] && [ -x "$CTL" ] || { echo "sh2000ctl not built: skipped"; exit 77; }
	local name=upload-still-$$ f=$DATA/still_axes.ngc fast slow
	start_sim $name
	"${RT_HOST[@]}" "$CTL" -d sim:$name params x amax=20000 + params y amax=20000 + params z amax=20000 + params a amax=20000 >ctl.out 2>&1 ||
		{ fail "sh2000ctl: amax 20000"; cat ctl.out; }
	expect 0 "A at 20000: planned" -- "${UPLOAD_RT[@]}" -d sim:$name --dry-run "$f"
	has "axes held still +a$" out
	fast=$(sed -n 's/^  planned time *\([0-9.]*\) s.*/\1/p' out)
	"${RT_HOST[@]}" "$CTL" -d sim:$name params a amax=5000 >ctl.out 2>&1 ||
		{ fail "sh2000ctl: A amax 5000"; cat ctl.out; }
	expect 0 "A at 5000: planned" -- "${UPLOAD_RT[@]}" -d sim:$name --dry-run "$f"
	slow=$(sed -n 's/^  planned time *\([0-9.]*\) s.*/\1/p' out)
	echo "planned: A at 20000 ${fast} s, A at 5000 ${slow} s"
	[ -n "$fast" ] && [ "$slow" = "$fast" ] ||
		fail "A at 5000 planned ${slow} s, at 20000 ${fast} s"
	expect 0 "A at 5000: runs" -- "${UPLOAD_RT[@]}" -d sim:$name "$f"
	has "enabling axes x y z$" err
	"$PROBE" sim:$name >p
	has "cmd=0\.0000,41\.5290,42\.8625,0\.0000" p
	stop_sim
}

# The guard between the two passes: the card moves after sh2000-upload
# read where it stands and before the run (here rs274's stand-in jogs Y
# on the served card while sh2000-upload waits for its output): the run is
# refused, naming the axis and how far, and nothing moves. The trace is
# not half-made: a file the run would have created is not there, and a
# user's file of that name is left as it was.
t_moved_since_check() {
	[ -n "${CTL:-}" ] && [ -x "$CTL" ] || { echo "sh2000ctl not built: skipped"; exit 77; }
	local name=upload-guard-$$
	start_sim $name
	"${RT_HOST[@]}" "$CTL" -d sim:$name enable y >ctl.out 2>&1 && enabled_is $name 2 ||
		{ fail "sh2000ctl: Y enabled"; cat ctl.out; }
	mkdir -p bin
	cat >bin/rs274 <<EOS
#!/bin/sh
"$CTL" -d sim:$name move y=\${JOG:-0.5} --feed 100 >/dev/null 2>&1 || { echo "stand-in: jog refused" >&2; exit 1; }
cat "$DATA/arc.canon"
EOS
	chmod +x bin/rs274
	expect 1 "a card moved between the check and the run" -- env PATH="$WORK/bin:$PATH" "${UPLOAD_RT[@]}" -d sim:$name --rs274 --trace m.csv "$DATA/arc.ngc"
	has "sim:$name: axis y moved by 0\.5000 mm since the program was checked; nothing moved" err
	# the trace's path was checked before the guard, the file removed
	no_motion m.csv
	"$PROBE" sim:$name >p
	has "state=1 fill=0 .*cmd=0\.0000,0\.5000,0\.0000,0\.0000" p
	# again, onto a file of the user's: refused, the file untouched
	printf 'the user'"'"'s notes\n' >notes.csv
	cp notes.csv notes.orig
	expect 1 "moved again, --trace onto an existing file" -- env JOG=1.0 PATH="$WORK/bin:$PATH" "${UPLOAD_RT[@]}" -d sim:$name --rs274 --trace notes.csv "$DATA/arc.ngc"
	has "axis y moved by 0\.5000 mm since the program was checked; nothing moved" err
	cmp -s notes.csv notes.orig || fail "a refused run changed the user's notes.csv"
	stop_sim
}

# The refusals after the trace file was opened, on the in-process card:
# axes to enable with --no-enable. No trace is left, a user's file of that
# name keeps its contents, and a run that starts writes it anew.
t_refused_trace() {
	expect 1 "--no-enable with the axes disabled" -- "$UPLOAD" -q -d sim --no-enable --trace new.csv "$DATA/arc.ngc"
	has "not enabled \(--no-enable; enable them with sh2000ctl enable\); nothing moved" err
	no_motion new.csv
	printf 'kept\n' >old.csv
	expect 1 "--no-enable onto an existing file" -- "$UPLOAD" -q -d sim --no-enable --trace old.csv "$DATA/arc.ngc"
	[ "$(cat old.csv)" = kept ] || fail "a refused run changed old.csv: $(head -c 200 old.csv)"
	# an output's folder that cannot be written: a usage error before the
	# card is touched, for the trace and the plot alike
	expect 2 "a trace that cannot be written" -- "$UPLOAD" -q -d sim --trace nodir/t.csv "$DATA/arc.ngc"
	has "^sh2000-upload: --trace nodir/t.csv: cannot write in nodir: No such file or directory \(nothing moved\)" err
	no_motion nodir/t.csv
	if command -v gnuplot >/dev/null; then
		expect 2 "a plot that cannot be written" -- "$UPLOAD" -q -d sim --plot nodir/t.png "$DATA/arc.ngc"
		has "^sh2000-upload: --plot nodir/t.png: cannot write in nodir: No such file or directory \(nothing moved\)" err
	fi
	# a trace path that is a folder: refused once opened, still before any move
	expect 1 "a trace that is a folder" -- "$UPLOAD" -q -d sim --trace . "$DATA/arc.ngc"
	has "^sh2000-upload: --trace \.: .*; nothing moved" err
	# the run starts: the old contents go, the header is the first line
	expect 0 "a run onto an existing file" -- "$UPLOAD" -q -d sim --trace old.csv "$DATA/arc.ngc" || return
	"$CHECK" old.csv header >h && [ "$(value header_ok h)" = 1 ] || fail "old.csv: header"
	grep -q '^kept$' old.csv && fail "old.csv still has its old contents"
}

# Starts sh2000-upload on long.ngc on sim:NAME in the background with its
# stderr in FILE; UPLOAD_PID is its pid. Returns once the first progress
# line is there (the signal handlers are in by then) and the card runs the
# program with records queued.
start_long_upload() {
	rm -f "$2"
	"${UPLOAD_RT[@]}" -d sim:$1 "$DATA/long.ngc" >out 2>"$2" &
	UPLOAD_PID=$!
	wait_for "the first progress line of the upload" file_has "progress" "$2" &&
		wait_for "sim:$1 to run long.ngc with records queued" running_with_records "$1"
}

t_shm_stop() {
	local name=upload-stop-$$
	start_sim $name
	start_long_upload $name stop.err
	local pid=$UPLOAD_PID
	kill -INT $pid
	wait $pid
	local rc=$?
	[ "$rc" = 7 ] || { fail "SIGINT: exit $rc, expected 7"; cat stop.err; }
	has "long.ngc:[0-9]+: stopped by the operator" stop.err
	"$PROBE" sim:$name >p
	has "state=1 fill=0" p
	# a second signal is an emergency stop: sent once the upload has taken
	# the first (its line is there), while the stop plays out the records
	# already queued (about 100 ms of the card's time), by a step at the
	# operator's priority so that a busy machine does not hold it back
	# until the stop is over (two signals sent at once would be one)
	start_long_upload $name stop2.err
	pid=$UPLOAD_PID
	"${RT_OPERATOR[@]}" bash -c '
		kill -INT "$1"
		for _ in $(seq 20000); do
			grep -q "stopping on the path" "$2" && exec kill -INT "$1"
			sleep 0.002
		done
		echo "FAIL: the upload did not take the first SIGINT" >&2' _ "$pid" stop2.err
	wait $pid
	rc=$?
	[ "$rc" = 4 ] || { fail "two SIGINTs: exit $rc, expected 4"; cat stop2.err; }
	has "emergency stop \(second signal\)" stop2.err
	"$PROBE" sim:$name >p
	has "state=6 " p
	stop_sim
}

# A feed hold (SIGUSR2) on a served card: the card comes to rest on the
# path with the motion still queued and stays there, SIGUSR1 resumes, the
# program ends where it should. Measured in the card's time: 0.5 s to come
# to rest from 10 mm/s, then 0.3 s in which it must not move.
t_shm_hold() {
	local name=upload-hold-$$ a b
	start_sim $name
	start_long_upload $name hold.err
	local pid=$UPLOAD_PID
	kill -USR2 $pid
	wait_for "the upload to take the feed hold" file_has "feed hold \(SIGUSR2\)" hold.err
	card_time_passes $name 5000
	"$PROBE" sim:$name >p1
	card_time_passes $name 3000
	"$PROBE" sim:$name >p2
	has "state=2 " p1
	grep -q "fill=0 " p1 && fail "held with nothing queued: $(cat p1)"
	a=$(sed 's/.*cmd=\([^ ]*\).*/\1/' p1)
	b=$(sed 's/.*cmd=\([^ ]*\).*/\1/' p2)
	[ "$a" = "$b" ] || fail "moved while held: $a -> $b"
	kill -USR1 $pid
	wait $pid
	local rc=$?
	[ "$rc" = 0 ] || { fail "resumed run: exit $rc"; cat hold.err; }
	has "resuming from the feed hold" hold.err
	"$PROBE" sim:$name >p
	has "state=1 fill=0" p
	stop_sim
}

# An operator's STOP from another program (sh2000ctl in a second terminal):
# the upload says so and exits 7, and the card is left idle with nothing
# latched (pushing on would have had the next record rejected).
t_shm_other_stop() {
	[ -n "${CTL:-}" ] && [ -x "$CTL" ] || { echo "sh2000ctl not built: skipped"; exit 77; }
	local name=upload-ostop-$$
	start_sim $name
	start_long_upload $name ostop.err
	local pid=$UPLOAD_PID
	# the operator's STOP: below the streaming upload (realtime.sh)
	"${RT_OPERATOR[@]}" "$CTL" -d sim:$name stop >ctl.out 2>ctl.err ||
		{ fail "sh2000ctl stop: exit $?"; cat ctl.err; }
	wait $pid
	local rc=$?
	[ "$rc" = 7 ] || { fail "STOP from sh2000ctl: exit $rc, expected 7"; cat ostop.err; }
	has "the card stopped the motion" ostop.err
	"$PROBE" sim:$name >p
	has "state=1 fill=0" p
	stop_sim
}

# a program as CAM output starts it: T1 M6 G43 H1. T1's Z+10 mm puts the
# machine 10 mm above the tip's path: G1 X20 Y10 Z-1 ends at Z 9
t_tool_table() {
	expect 0 "T1 M6 G43 H1 with --tool-table" -- "$UPLOAD" -q -d sim --tool-table "$DATA/tools.tbl" --trace tr.csv "$DATA/tool_start.ngc" || return
	"$CHECK" tr.csv end >e
	[ "$(value cmd e)" = "20.000000,10.000000,9.000000,0.000000" ] || fail "end $(value cmd e), expected 20,10,9,0 (Z-1 + T1's 10 mm)"
	local n
	n=$(grep -c "warning: M6 (tool change) not paused at" err)
	[ "$n" = 1 ] || fail "the tool change reported $n times, expected once"
	# without the table G43 H1 is refused, at its H word
	expect 5 "G43 H1 without --tool-table" -- "$UPLOAD" -q -d sim --trace no.csv "$DATA/tool_start.ngc"
	has "tool_start.ngc:3:11: error: G43 H1: tool 1 is not in the tool table: no tool table was given" err
	no_motion no.csv
	# a table with a bad line: its FILE:LINE:COLUMN, nothing moved
	printf 'T1 P1 Z10 ;ok\nT2 P2 Zx\nT3 Z1\n' >bad.tbl
	expect 5 "a bad tool table" -- "$UPLOAD" -q -d sim --tool-table bad.tbl --trace b.csv "$DATA/tool_start.ngc"
	has "^bad.tbl:2:7: error: Z: 'x' is not a finite number" err
	has "^bad.tbl:3:1: error: T3 has no P word" err
	has "tool-table bad.tbl: 2 errors; nothing moved" err
	no_motion b.csv
	expect 1 "an unreadable tool table" -- "$UPLOAD" -q -d sim --tool-table nosuch.tbl "$DATA/tool_start.ngc"
	has "nosuch.tbl: error: cannot read the tool table" err
	expect 2 "--parameter-file without --rs274" -- "$UPLOAD" -q -d sim --parameter-file x.var "$DATA/tool_start.ngc"
}

# the same table through LinuxCNC's own rs274 (real, not a stand-in)
t_tool_rs274() {
	command -v rs274 >/dev/null || { echo "SKIP: LinuxCNC's rs274 is not installed (Debian package linuxcnc-uspace)"; exit 77; }
	expect 0 "--rs274 --tool-table" -- "$UPLOAD" -q -d sim --rs274 --tool-table "$DATA/tools.tbl" --trace r.csv "$DATA/tool_start.ngc" || return
	"$CHECK" r.csv end >e
	# rs274 reads a table in its own inches: given in mm, it is converted
	[ "$(value cmd e)" = "20.000000,10.000000,9.000000,0.000000" ] || fail "rs274 end $(value cmd e), expected 20,10,9,0 as the built-in parser"
	# without a table rs274 stops at T1, as a user's program with T1 did
	expect 5 "--rs274 without a table" -- "$UPLOAD" -q -d sim --rs274 --trace n.csv "$DATA/tool_start.ngc"
	has "Requested tool 1 not found in the tool table" err
	no_motion n.csv
	rm -rf "$(sed -n "s/.*kept in \(.*\)\/rs274.canon/\1/p" err)"
	# the parameter file (mm, as a LinuxCNC machine in mm keeps it): its
	# G54 X offset of 10 mm moves everything 10 mm; the file stays as it was
	printf '5220\t1.000000\n5221\t10.000000\n' >p.var
	cp p.var p.orig
	expect 0 "--parameter-file" -- "$UPLOAD" -q -d sim --rs274 --tool-table "$DATA/tools.tbl" --parameter-file p.var --trace p.csv "$DATA/tool_start.ngc" || return
	"$CHECK" p.csv end >e
	[ "$(value cmd e)" = "30.000000,10.000000,9.000000,0.000000" ] || fail "--parameter-file end $(value cmd e), expected 30,10,9,0"
	cmp -s p.var p.orig || fail "rs274 changed the user's parameter file"
	local cds=/usr/share/linuxcnc/ncfiles/cds.ngc
	if [ -f "$cds" ]; then
		expect 0 "LinuxCNC's cds.ngc (G43 H1 in inches)" -- "$UPLOAD" -q -d sim -n --rs274 --tool-table "$DATA/tools.tbl" "$cds"
		has "blocks checked and planned" out
	fi
}

t_tool_pause() {
	expect 2 "--pause-on-tool-change without a terminal" -- "$UPLOAD" -d sim --pause-on-tool-change --tool-table "$DATA/tools.tbl" "$DATA/tool_start.ngc" </dev/null
	has "standard input is not a terminal" err
	expect 0 "--pause-on-tool-change --dry-run needs none" -- "$UPLOAD" -q -d sim -n --pause-on-tool-change --tool-table "$DATA/tools.tbl" "$DATA/tool_start.ngc" </dev/null
	command -v script >/dev/null || { echo "SKIP: script(1) (util-linux) gives the terminal"; exit 77; }
	# on a terminal: the run stops at M6, names the tool, Enter resumes
	printf '\n' | script -qec "'$UPLOAD' -d sim --pause-on-tool-change --tool-table '$DATA/tools.tbl' --trace tr.csv '$DATA/tool_start.ngc'" /dev/null >tty.out 2>&1
	local rc=$?
	tr -d '\r' <tty.out >tty.txt
	[ "$rc" = 0 ] || { fail "paused run: exit $rc"; tail -n 5 tty.txt; return; }
	has "tool_start.ngc:3:4: tool change: put tool 1 in the spindle \(pocket 1, Z offset 10.0000 mm, diameter 6.0000 mm: 6 mm end mill\); press Enter" tty.txt
	has "resuming" tty.txt
	has ": done" tty.txt
	grep -q "not paused at" tty.txt && fail "a paused tool change was also reported as not paused"
	"$CHECK" tr.csv end >e
	[ "$(value cmd e)" = "20.000000,10.000000,9.000000,0.000000" ] || fail "end $(value cmd e)"
}

case ${1:-} in
geometry|raw|override|bad_unknown|bad_arc|bad_nan|bad_feed|bad_plan|warnings|csv|json|dry_run|usage|device|rs274_missing|rs274|plot|plot_missing|pause|fault|shm|shm_stop|shm_hold|shm_other_stop|moved_axes|tool_table|tool_rs274|tool_pause|moved_since_check|refused_trace|accel_guard|accel_fit|still_axes)
	"t_$1" ;;
*) echo "usage: upload_tests.sh TEST"; exit 2 ;;
esac
[ "$failures" = 0 ] || { echo "$failures failure(s)"; exit 1; }
echo "passed"

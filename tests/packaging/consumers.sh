# shellcheck shell=bash disable=SC2154,SC2034  # the caller sets the variables named below
# Consumers of the installed libraries (sourced after lib.sh), shared by
# deb_install (packages unpacked into a root) and inroot (packages installed
# in /usr). Each -dev package has a pkg-config name, a CMake component
# (none for libsh2000-dev) and a consumer program in consumer/:
#   consumer  libsh2000 alone: opens `sim` without linking libsh2000-sim
#   runpart   libsh2000-motion: runs examples/part.ngc on `sim`
#   simcard   libsh2000-sim: an in-process card with its own configuration
# The caller sets cons (the consumer/ folder), part (part.ngc), ver, and
# defines pc (pkg-config as it should be called) and runenv (a command
# prefix that lets a program find the libraries, or nothing).
devs=(libsh2000-dev libsh2000-motion-dev libsh2000-sim-dev)
declare -A dev_pc=([libsh2000-dev]=sh2000 [libsh2000-motion-dev]=sh2000-motion
	[libsh2000-sim-dev]=sh2000-sim)
declare -A dev_comp=([libsh2000-dev]="" [libsh2000-motion-dev]=motion
	[libsh2000-sim-dev]=sim)
declare -A dev_prog=([libsh2000-dev]=consumer [libsh2000-motion-dev]=runpart
	[libsh2000-sim-dev]=simcard)
# Our libraries each consumer loads (NEEDED): no more than it calls.
declare -A prog_libs=([consumer]=libsh2000 [runpart]="libsh2000 libsh2000-motion"
	[simcard]="libsh2000 libsh2000-sim")

prog_args() { # prog_args PROG: its command line
	case $1 in
	consumer) echo sim ;;
	runpart) echo sim "$part" ;;
	esac
}
prog_wants() { # prog_wants PROG: a regex its output must match
	case $1 in
	consumer) echo "libsh2000 $ver " ;;
	runpart) echo "runpart: ok: .* on sim with libsh2000 $ver: at the end point" ;;
	simcard) echo "simcard: ok: libsh2000-sim $ver, libsh2000 $ver on sim" ;;
	esac
}

# build_pc PROG PCNAME OUT [--static LIBDIR]: cc with the pkg-config flags;
# --static links our archives from LIBDIR in place of -lsh2000*, with
# everything `pkg-config --static` says they need (Libs.private,
# Requires.private).
build_pc() {
	local prog=$1 name=$2 out=$3 libs
	if [ "${4:-}" = --static ]; then
		libs=$(pc --static --libs "$name" | sed -E "s#-l(sh2000(-[a-z]+)?)\\b#$5/lib\\1.a#g")
	else
		libs=$(pc --libs "$name")
	fi
	# shellcheck disable=SC2046
	cc -std=c11 -Wall -Wextra -Werror -pedantic $(pc --cflags "$name") \
		"$cons/$prog.c" -o "$out" $libs -lm
}

# run_prog LABEL BINARY PROG: runs it on `sim`, checks what it printed.
run_prog() {
	local out rc
	# shellcheck disable=SC2046
	out=$($runenv "$2" $(prog_args "$3") 2>&1)
	rc=$?
	if [ $rc -eq 0 ] && [[ $out =~ $(prog_wants "$3") ]]; then
		ok "$1: $(tail -n 1 <<<"$out")"
	else
		fail "$1 (exit $rc):"
		sed 's/^/     /' <<<"$out" | tail -n 12
	fi
}

# needs_only BINARY "LIB...": of our libraries the binary loads exactly
# these ("" for none: a static build).
needs_only() {
	local got want l
	got=$(objdump -p "$1" | awk '/NEEDED/ && $2 ~ /^libsh2000/ {print $2}' | sort | tr '\n' ' ')
	want=$(for l in $2; do echo "$l.so.0"; done | sort | tr '\n' ' ')
	[ "$got" = "$want" ]
}

# pc_consumers DIR: every consumer built with pkg-config (shared, and
# static from LIBDIR when given) into DIR, then run.
pc_consumers() {
	local dir=$1 libdir=${2:-} dev prog name
	for dev in "${devs[@]}"; do
		prog=${dev_prog[$dev]} name=${dev_pc[$dev]}
		if build_pc "$prog" "$name" "$dir/${prog}_pc" 2>"$dir/$prog.log"; then
			ok "$prog built with pkg-config $name: $(pc --libs "$name")"
			check "${prog}_pc loads ${prog_libs[$prog]} and no other of ours" \
				needs_only "$dir/${prog}_pc" "${prog_libs[$prog]}"
			run_prog "${prog}_pc" "$dir/${prog}_pc" "$prog"
		else
			fail "$prog built with pkg-config $name"; cat "$dir/$prog.log"
		fi
		[ -n "$libdir" ] || continue
		if build_pc "$prog" "$name" "$dir/${prog}_pc_static" --static "$libdir" 2>"$dir/$prog.log"; then
			ok "$prog built with pkg-config --static $name (archives)"
			check "${prog}_pc_static loads none of our libraries" needs_only "$dir/${prog}_pc_static" ""
			run_prog "${prog}_pc_static" "$dir/${prog}_pc_static" "$prog"
		else
			fail "$prog built with pkg-config --static $name"; cat "$dir/$prog.log"
		fi
	done
}

# cmake_consumers DIR [CMAKE ARGS...]: consumer/ with find_package(sh2000
# $ver REQUIRED COMPONENTS motion sim): each program shared and static.
cmake_consumers() {
	local dir=$1 prog
	shift
	if cmake -S "$cons" -B "$dir" -DSH2000_WANT="$ver" \
		-DCMAKE_C_FLAGS="-Wall -Wextra -Werror" "$@" >"$dir.log" 2>&1 &&
	   cmake --build "$dir" -j2 >>"$dir.log" 2>&1; then
		ok "consumers built with find_package(sh2000 $ver REQUIRED COMPONENTS motion sim)"
	else
		tail -n 30 "$dir.log"; fail "consumers built with find_package(sh2000 $ver COMPONENTS motion sim)"
		return
	fi
	for prog in consumer runpart simcard; do
		check "${prog}_cmake loads ${prog_libs[$prog]} and no other of ours" \
			needs_only "$dir/${prog}_cmake" "${prog_libs[$prog]}"
		check "${prog}_cmake_static loads none of our libraries" \
			needs_only "$dir/${prog}_cmake_static" ""
		run_prog "${prog}_cmake" "$dir/${prog}_cmake" "$prog"
		run_prog "${prog}_cmake_static" "$dir/${prog}_cmake_static" "$prog"
	done
}

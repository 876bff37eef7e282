# shellcheck shell=bash disable=SC2034  # ABI_LIBS is for the scripts that source this
# What the ABI check and its baseline share: the three libraries, the
# public headers each one's ABI is made of, and how abidw writes a baseline.
# Sourced by tests/abi/abi_check and scripts/abi-baseline.

# The libraries, in the order they are checked.
ABI_LIBS=(libsh2000 libsh2000-motion libsh2000-sim)

# abi_headers SRC LIB: the header folders whose types are LIB's ABI: its
# own public headers and those of the layers below it that its functions
# show (a struct sh2000_status reached from libsh2000-motion is part of
# libsh2000-motion's ABI too). Types from anywhere else (the libraries'
# private headers, libc) are not.
abi_headers() {
	local l=$1/libsh2000
	case $2 in
	libsh2000) echo "$l/protocol/include $l/device/include" ;;
	libsh2000-motion) echo "$l/protocol/include $l/device/include $l/motion/include" ;;
	libsh2000-sim) echo "$l/protocol/include $l/device/include $l/sim/include" ;;
	*) return 1 ;;
	esac
}

# abi_hd_args OPTION SRC LIB: OPTION DIR for each of LIB's header folders.
abi_hd_args() {
	local d
	for d in $(abi_headers "$2" "$3"); do
		printf '%s\n%s\n' "$1" "$d"
	done
}

# abi_promise LIB: "stable" when programs may build on LIB's ABI (the
# SONAME changes with any break), "none" for libsh2000-sim: its packages'
# shlibs say "=", so no program runs against another version of it than
# the one it was built with, and it changes with the card model.
abi_promise() {
	case $1 in
	libsh2000-sim) echo none ;;
	*) echo stable ;;
	esac
}

# abi_soname FILE: the SONAME of a shared library, or of a baseline.
abi_soname() {
	case $1 in
	*.xml) sed -n "s/.*<abi-corpus [^>]*soname='\([^']*\)'.*/\1/p" "$1" | head -n 1 ;;
	*) LC_ALL=C readelf -d "$1" | sed -n 's/.*(SONAME).*\[\(.*\)\]/\1/p' ;;
	esac
}

# abi_debuginfo FILE: true when FILE has DWARF, which abidw reads the
# types from (a RelWithDebInfo or Debug tree; a Release one has none).
abi_debuginfo() {
	# (no grep -q in a pipe: under pipefail its early exit fails readelf)
	[[ $(LC_ALL=C readelf -S "$1" 2>/dev/null) == *.debug_info* ]]
}

# abi_dump SRC LIB FILE OUT: LIB's ABI from FILE into OUT: the exported
# functions and the public types they reach, with no path of this machine
# in it (file names only, no build or source folder) and type ids made
# from the types themselves, so that a change to one type changes few
# lines. The locations stay: abidiff tells public types from private ones
# by them (without, every type would count as private and nothing fail).
abi_dump() {
	local hd
	mapfile -t hd < <(abi_hd_args --headers-dir "$1" "$2")
	abidw "${hd[@]}" --drop-private-types --exported-interfaces-only \
		--no-corpus-path --no-comp-dir-path --short-locs \
		--type-id-style hash --out-file "$4" "$3"
}

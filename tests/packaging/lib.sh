# Shared by the packaging tests (sourced). Lines "ok ..."/"FAIL ..." per
# check; finish() exits 1 if any failed.
set -uo pipefail

failures=0
ok() { echo "ok   $*"; }
fail() { echo "FAIL $*"; failures=$((failures + 1)); }
note() { echo "--   $*"; }
check() { # check "what" command...
	local what=$1; shift
	if "$@"; then ok "$what"; else fail "$what"; fi
}
finish() {
	if [ "$failures" -eq 0 ]; then
		echo "packaging: all checks passed"
		exit 0
	fi
	echo "packaging: $failures check(s) failed"
	exit 1
}
need_root() {
	if [ "$(id -u)" -ne 0 ]; then
		echo "SKIP: needs root (installs Debian packages, runs dkms)"
		exit 77
	fi
}

# need PKG...: apt-get install what is missing; apt-get update only when
# the install fails without it (a fresh image has no lists).
installed() {
	[ "$(dpkg-query -W -f='${db:Status-Status}' "$1" 2>/dev/null)" = installed ]
}
need() {
	local missing=() p
	for p in "$@"; do
		installed "$p" || missing+=("$p")
	done
	[ ${#missing[@]} -eq 0 ] && return 0
	note "apt-get install ${missing[*]}"
	export DEBIAN_FRONTEND=noninteractive
	apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null 2>&1 && return 0
	apt-get update -qq >/dev/null 2>&1
	apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}

# The kernel a headers metapackage points to: linux-headers-amd64 ->
# 6.1.0-56-amd64 (from the installed package's Depends, no network).
headers_kernel() {
	dpkg-query -W -f='${Depends}' "$1" 2>/dev/null |
		tr ',' '\n' | sed -n 's/^ *linux-headers-\([^ ]*\).*/\1/p' | head -n 1
}

# The driver's DKMS tree as the sh2000-dkms package ships it: dkms.conf,
# the root Kbuild and driver/ sources (never what a Kbuild run left).
driver_files() { # driver_files SRC: relative paths, sorted
	(cd "$1" && { echo dkms.conf; echo Kbuild
		find driver -type f \( -name '*.c' -o -name '*.h' -o -name Kbuild \) \
			! -name '*.mod.c' ! -name '.*'; } | LC_ALL=C sort)
}
matches() { [[ $1 =~ $2 ]]; }
no() { ! "$@"; }
q() { "$@" >/dev/null 2>&1; }

# What each library must never export: libsh2000's ABI never shows the
# card model or the shared-memory server (libsh2000-sim) nor the motion
# layer above it; the layers beside each other share nothing. And the data
# symbols a library exports besides its functions.
card_model_re='^sh2000_(fw|cardsim|sim|interp|pid|plant)_'
motion_re='^sh2000_(path|run|prog|program|limits|bscomp)_'
abi_rules() { # abi_rules LIBNAME: sets ABI_FORBID and ABI_EXTRA
	case $1 in
	libsh2000) ABI_FORBID="$card_model_re|$motion_re" ABI_EXTRA='' ;;
	libsh2000-motion) ABI_FORBID=$card_model_re ABI_EXTRA='' ;;
	# the `sim` provider libsh2000 looks up (sh2000_simprovider.h)
	libsh2000-sim) ABI_FORBID=$motion_re ABI_EXTRA=sh2000_sim_provider_v1 ;;
	*) ABI_FORBID='' ABI_EXTRA='' ;;
	esac
}

# abi_check NAME LIBRARY HEADER...: the shared library exports exactly the
# sh2000_*() functions its public headers declare (comments stripped, so a
# name mentioned in prose does not count; static inline ones are not
# exported), plus the data symbols in $ABI_EXTRA, and none whose name
# matches $ABI_FORBID (an extended regex). Leaves the sorted exported names
# in $ABI_OUT (a file) and prints their count.
abi_check() {
	local name=$1 lib=$2 decl inline extra missing forbidden n
	shift 2
	decl=$(mktemp) inline=$(mktemp)
	for h in "$@"; do cc -fpreprocessed -dD -E -P -x c "$h"; done >"$inline.txt"
	{ grep -oE '\bsh2000_[A-Za-z0-9_]+[[:space:]]*\(' "$inline.txt" | sed 's/[[:space:](]//g'
	  for s in ${ABI_EXTRA:-}; do echo "$s"; done; } | sort -u >"$decl"
	grep -oE 'static inline [^(]*\bsh2000_[A-Za-z0-9_]+\(' "$inline.txt" |
		grep -oE 'sh2000_[A-Za-z0-9_]+' | sort -u >"$inline"
	nm -D --defined-only "$lib" | awk '{print $3}' | sort -u >"$ABI_OUT"
	extra=$(comm -13 "$decl" "$ABI_OUT" | head -n 8 | tr '\n' ' ')
	missing=$(comm -23 "$decl" "$ABI_OUT" | comm -23 - "$inline" | head -n 8 | tr '\n' ' ')
	forbidden=$(grep -E "${ABI_FORBID:-^$}" "$ABI_OUT" | head -n 8 | tr '\n' ' ')
	n=$(wc -l <"$ABI_OUT" | tr -d ' ')
	check "$name exports no function its headers do not declare${extra:+: $extra}" [ -z "$extra" ]
	check "$name defines every function its headers declare${missing:+: missing $missing}" [ -z "$missing" ]
	if [ -n "${ABI_FORBID:-}" ]; then
		check "$name exports nothing of another layer${forbidden:+: $forbidden}" [ -z "$forbidden" ]
	fi
	note "$name exports $n symbols (nm -D --defined-only)"
	rm -f "$decl" "$inline" "$inline.txt"
}

# The protocol version the protocol headers define ("1.0") and the
# driver's ioctl ABI version, from the source tree SRC.
proto_version() {
	local h=("$1"/libsh2000/protocol/include/sh2000/*.h) maj min
	maj=$(sed -n 's/^#define[ \t]*SH2000_PROTO_MAJOR[ \t]*\([0-9]*\)u*.*/\1/p' "${h[@]}")
	min=$(sed -n 's/^#define[ \t]*SH2000_PROTO_MINOR[ \t]*\([0-9]*\)u*.*/\1/p' "${h[@]}")
	echo "$maj.$min"
}
driver_abi() {
	sed -n 's/^#define[ \t]*SH2000_ABI_VERSION[ \t]*\([0-9]*\).*/\1/p' "$1/driver/uapi/sh2000.h"
}

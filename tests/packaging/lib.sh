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
q() { "$@" >/dev/null 2>&1; }

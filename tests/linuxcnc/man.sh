#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-or-later
# hal_sh2000(9) renders without a groff warning and names every pin,
# parameter and function the module exports (the names in hal_sh2000.c).
#   man.sh PAGE SOURCE
set -u
page=$1
src=$2
if ! command -v groff >/dev/null; then
	echo "groff not installed (apt-get install groff-base): skipped"
	exit 77
fi
fail=0
warn=$(LC_ALL=C.UTF-8 groff -ww -man -Tutf8 -z "$page" 2>&1)
if [ -n "$warn" ]; then
	echo "FAIL: groff warnings for $page:" >&2
	echo "$warn" >&2
	fail=1
fi
text=$(LC_ALL=C.UTF-8 MANWIDTH=200 groff -man -Tutf8 "$page" 2>/dev/null | sed 's/.\x08//g')
# "sh2000.%d." name and "sh2000.%d.%c." name in the source (pins, and the
# axis parameters of AXIS_PARAM)
names=$(grep -oE '((AXIS|CARD)_PIN\([a-z0-9]+, HAL_[A-Z]+|AXIS_PARAM\([a-z0-9]+), [a-z_]+, "[a-z-]+"\)' "$src" |
	sed -E 's/.*"([a-z-]+)"\)/\1/')
names="$names position-scale queue-target comp-id comp-sum comp-tables read write"
for n in $names; do
	if ! printf '%s\n' "$text" | grep -qE "sh2000\.N\.(A\.)?$n( |$)"; then
		echo "FAIL: $page does not describe sh2000.N[.A].$n" >&2
		fail=1
	fi
done
[ $fail = 0 ] && echo "$page: clean, every name described ($(echo $names | wc -w))"
exit $fail

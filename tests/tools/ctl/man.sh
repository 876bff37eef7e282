#!/bin/bash
# A man page renders without a groff warning (groff -ww, as
# `man --warnings` runs it) and has the sections a tool's page needs.
set -u
page=$1
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
text=$(LC_ALL=C.UTF-8 MANWIDTH=80 groff -man -Tutf8 "$page" 2>/dev/null | sed 's/.\x08//g')
for s in NAME SYNOPSIS DESCRIPTION OPTIONS "EXIT STATUS" EXAMPLES "SEE ALSO"; do
	if ! printf '%s\n' "$text" | grep -q "^$s\$"; then
		echo "FAIL: $page has no $s section" >&2
		fail=1
	fi
done
if command -v man >/dev/null; then
	mw=$(MANWIDTH=80 man --warnings -l "$page" 2>&1 >/dev/null)
	if [ -n "$mw" ]; then
		echo "FAIL: man --warnings -l $page:" >&2
		echo "$mw" >&2
		fail=1
	fi
fi
[ $fail = 0 ] && echo "$page: clean"
exit $fail

#!/usr/bin/env bash
# The README's first command, as a new user runs it: clone the repository's
# HEAD into a temporary folder and run the demo command exactly as the
# README's first code block writes it. Checks its exit status, the summary
# it prints, and that the picture is a PNG of the size the README states.
#
#   clean_clone.sh SOURCE_DIR
set -uo pipefail

src=$1
fail() { echo "FAIL: $*"; exit 1; }

readme=$src/README.md
# The first command of the README: the first line of its first indented
# code block (the README opens with the two commands).
cmd=$(awk '/^    \.\// { sub(/^    /, ""); sub(/[ \t]+#.*/, ""); print; exit }' "$readme")
[ "$cmd" = "./scripts/demo" ] || fail "README's first command is '$cmd', expected ./scripts/demo"
# The size of the picture as the README states it: "W × H pixels".
size=$(grep -oE '[0-9]+ × [0-9]+ pixels' "$readme" | head -n 1)
[ -n "$size" ] || fail "README states no picture size (W × H pixels)"
want_w=${size%% ×*}
want_h=${size#* × }
want_h=${want_h%% *}

tmp=$(mktemp -d /tmp/sh2000-clean-clone.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
git clone -q "$src" "$tmp/clone" || fail "git clone of $src"
cd "$tmp/clone" || fail "cd into the clone"
echo "clean clone of $(git rev-parse --short HEAD) in $tmp/clone; running: $cmd"

out=$tmp/demo.out
# shellcheck disable=SC2086
$cmd >"$out" 2>&1
rc=$?
cat "$out"
[ "$rc" -eq 0 ] || fail "'$cmd' exited $rc on a clean clone"

expect() {
	grep -qE "$1" "$out" || fail "the demo's output has no line matching /$1/"
}
expect '^sh2000-upload: examples/part\.ngc on sim: done$'
expect '^  time +[0-9.]+ s of card time \(planned [0-9.]+ s\)$'
expect '^  underruns +0 '
expect '^  plot +build/demo/part\.png$'
expect '^demo: the picture .*: build/demo/part\.png$'
expect '^demo: the trace, .*: build/demo/part\.csv$'

png=build/demo/part.png
[ -s "$png" ] || fail "$png missing or empty"
# PNG signature, then the IHDR chunk: width and height, big-endian.
sig=$(head -c 8 "$png" | od -An -tx1 | tr -d ' \n')
[ "$sig" = "89504e470d0a1a0a" ] || fail "$png is not a PNG (signature $sig)"
w=$((16#$(od -An -tx1 -j16 -N4 "$png" | tr -d ' \n')))
h=$((16#$(od -An -tx1 -j20 -N4 "$png" | tr -d ' \n')))
[ "$w" -eq "$want_w" ] && [ "$h" -eq "$want_h" ] ||
	fail "$png is ${w}x$h, the README says $want_w × $want_h"
rows=$(($(wc -l <build/demo/part.csv) - 1))
[ "$rows" -gt 1000 ] || fail "the trace has $rows rows"
echo "PASS: the demo ran on a clean clone: a ${w}x$h PNG, $rows trace rows"

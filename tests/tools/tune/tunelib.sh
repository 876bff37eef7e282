# Helpers of sh2000-tune's black-box tests (sourced by step.sh and
# sweep.sh after ../ctl/testlib.sh): the tool on the in-process card, and
# reading its figures back.
: "${TUNE:?TUNE must name sh2000-tune}"
S=(-d sim)

# figure NAME: the number after NAME in the last stdout
figure() {
	printf '%s\n' "$out" | sed -n "s/^$1 *\([-0-9.]*\).*/\1/p"
}

# close A B TOL: |A - B| <= TOL (both given)
close() {
	awk -v a="$1" -v b="$2" -v e="$3" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(a != "" && b != "" && d <= e) }'
}

# is_png FILE: the PNG signature
is_png() {
	checks=$((checks + 1))
	[ "$(head -c 8 "$1" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] ||
		fail "--plot did not write a PNG ($1)"
}

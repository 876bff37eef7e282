#!/bin/bash
# The firmware sees the card only through board.h: no firmware translation
# unit reaches the plant, the board's simulation side or the card's
# internals, directly or through another header (the compiler's own list
# of what each one includes), and none names the plant.
#   layers.sh CC SRCDIR -I... [-I...]
set -u
cc=$1 src=$2
shift 2
firmware="firmware.c gather.c homing.c params.c pid.c observer.c interp.c timebase.c"
forbidden='plant\.h|board_sim\.h|card_internal\.h|sh2000_cardsim\.h'
fail=0
for f in $firmware; do
	deps=$("$cc" -MM "$@" "$src/$f" 2>&1) || {
		echo "FAIL $f: the compiler cannot list its headers: $deps"
		fail=1
		continue
	}
	bad=$(tr ' \\' '\n\n' <<<"$deps" | grep -E "/($forbidden)$")
	if [ -n "$bad" ]; then
		echo "FAIL $f includes $(echo $bad)"
		fail=1
	else
		echo "ok   $f: $(tr ' \\' '\n\n' <<<"$deps" | grep -c '\.h$') headers, none of the machine's"
	fi
	if grep -n -i 'plant' "$src/$f"; then
		echo "FAIL $f names the plant (above)"
		fail=1
	fi
done
# the headers the firmware does include say nothing of it either
for h in cardmodel.h board.h; do
	if grep -n -E "#include \"($forbidden)\"|struct sh2000_plant" "$src/$h"; then
		echo "FAIL $h reaches the plant (above)"
		fail=1
	fi
done
exit $fail

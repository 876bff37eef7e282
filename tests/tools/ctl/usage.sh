#!/bin/bash
# sh2000ctl: command-line errors exit 2 with a message, help and version
# exit 0; nothing here needs a card.
. "$(dirname "$0")/testlib.sh"

expect 2 "$CTL" && err_has "missing COMMAND" && err_has "Try 'sh2000ctl --help'"
expect 2 "$CTL" bogus && err_has "unknown command 'bogus'"
expect 2 "$CTL" --bogus status && err_has "unknown option '--bogus'"
expect 2 "$CTL" -d && err_has "needs a DEVICE"
expect 2 "$CTL" -d sim status + && err_has "'\+' at the end"
expect 0 "$CTL" --help && out_has "^Usage: sh2000ctl" && out_has "Exit status"
expect 0 "$CTL" -V && out_has "^sh2000ctl [0-9]" && out_has "^libsh2000 [0-9]" &&
	out_has "^protocol 1\.[0-9]+$" && out_has "^driver ABI [0-9]+$"
for sub in info status params enable disable jog move home stop estop reset dump; do
	expect 0 "$CTL" "$sub" --help && out_has "^Usage: sh2000ctl \[-d DEVICE\] $sub"
	expect 0 "$CTL" help "$sub" && out_has "^Usage: sh2000ctl \[-d DEVICE\] $sub"
done
# bad arguments of each subcommand: usage errors, before the device is
# opened (the device does not exist, so exit 3 would mean it was tried)
D=(-d /nonexistent/sh2000-9)
expect 2 "$CTL" "${D[@]}" info extra && err_has "info: unexpected 'extra'"
expect 2 "$CTL" "${D[@]}" status --bogus && err_has "unexpected '--bogus'"
expect 2 "$CTL" "${D[@]}" status --watch 0 && err_has "--watch"
expect 2 "$CTL" "${D[@]}" status --count 3 && err_has "--count needs --watch"
expect 2 "$CTL" "${D[@]}" params q && err_has "'q' is not an axis"
expect 2 "$CTL" "${D[@]}" params x bogus && err_has "unknown parameter 'bogus'"
expect 2 "$CTL" "${D[@]}" params x kp=abc && err_has "kp: 'abc' is not a number"
expect 2 "$CTL" "${D[@]}" params x kp=1 ti && err_has "not both"
expect 2 "$CTL" "${D[@]}" params load && err_has "needs one FILE"
expect 2 "$CTL" "${D[@]}" enable && err_has "which axes"
expect 2 "$CTL" "${D[@]}" enable q && err_has "'q' is not an axis list"
expect 2 "$CTL" "${D[@]}" disable x,w && err_has "'x,w' is not an axis list"
expect 2 "$CTL" "${D[@]}" jog && err_has "which axis"
expect 2 "$CTL" "${D[@]}" jog w 1 && err_has "'w' is not an axis"
expect 2 "$CTL" "${D[@]}" jog x && err_has "needs a DISTANCE"
expect 2 "$CTL" "${D[@]}" jog x 0 && err_has "not a non-zero distance"
expect 2 "$CTL" "${D[@]}" jog x 1 --velocity 3 --time 1 && err_has "not both"
expect 2 "$CTL" "${D[@]}" jog x --velocity 3 && err_has "needs a DISTANCE"
expect 2 "$CTL" "${D[@]}" jog x --velocity 3 --time -1 && err_has "--time"
expect 2 "$CTL" "${D[@]}" jog x 1 --speed && err_has "needs a value"
expect 2 "$CTL" "${D[@]}" move && err_has "no target"
expect 2 "$CTL" "${D[@]}" move x=abc && err_has "expected AXIS=POS"
expect 2 "$CTL" "${D[@]}" move x=1 x=2 && err_has "axis x given twice"
expect 2 "$CTL" "${D[@]}" move x=1 --feed -3 && err_has "--feed"
expect 2 "$CTL" "${D[@]}" home && err_has "which axis"
expect 2 "$CTL" "${D[@]}" home x y && err_has "unexpected 'y'"
expect 2 "$CTL" "${D[@]}" home x --timeout no && err_has "--timeout"
expect 2 "$CTL" "${D[@]}" stop now && err_has "unexpected 'now'"
expect 2 "$CTL" "${D[@]}" estop x && err_has "unexpected 'x'"
expect 2 "$CTL" "${D[@]}" reset x && err_has "unexpected 'x'"
expect 2 "$CTL" "${D[@]}" dump 5-3 && err_has "bad range '5-3'"
expect 2 "$CTL" "${D[@]}" dump 1024 && err_has "bad range '1024'"
expect 2 "$CTL" "${D[@]}" dump 1020+10 && err_has "bad range '1020\+10'"
expect 2 "$CTL" "${D[@]}" dump x && err_has "bad range 'x'"
finish

#!/bin/bash
# sh2000-sim: usage errors exit 2 with a message; help and version exit 0.
. "$(dirname "$0")/../ctl/testlib.sh"
expect 2 "$SIM" && err_has "^sh2000-sim: missing NAME" && err_has "Try 'sh2000-sim --help'"
expect 2 "$SIM" --bogus x && err_has "unknown option '--bogus'"
expect 2 "$SIM" a b && err_has "one NAME only"
expect 2 "$SIM" a/b && err_has "bad NAME 'a/b'"
expect 2 "$SIM" "$(printf 'n%.0s' $(seq 65))" && err_has "bad NAME"
expect 2 "$SIM" --ready-fd x n && err_has "--ready-fd: 'x' is not a file descriptor"
expect 2 "$SIM" --ready-fd 77 n && err_has "--ready-fd: 77 is not open"
expect 2 "$SIM" --attach && err_has "option -a"
expect 2 "$SIM" --clock-ppm fast n && err_has "--clock-ppm: 'fast' is not a number in -100000..100000"
expect 2 "$SIM" -c 100001 n && err_has "--clock-ppm: '100001' is not a number"
expect 2 "$SIM" -c && err_has "option -c"
expect 2 "$SIM" --mass 0 n && err_has "--mass: '0' is not a number above 0 and at most 10000"
expect 2 "$SIM" --mass heavy n && err_has "--mass: 'heavy' is not a number"
expect 2 "$SIM" --friction -1 n && err_has "--friction: '-1' is not a number in 0\.\.1e\+06"
expect 2 "$SIM" --friction && err_has "unknown option|missing"
expect 2 "$SIM" --priority 100 n && err_has "--priority: '100' is not a number in 0\.\.99"
expect 2 "$SIM" -p high n && err_has "--priority: 'high' is not a number"
expect 0 "$SIM" --help && out_has "^Usage: sh2000-sim" && out_has "--attach PATH" &&
	out_has "--clock-ppm N" && out_has "--mass KG" && out_has "--friction NS_PER_M" &&
	out_has "--priority N"
expect 0 "$SIM" -V && out_has "^sh2000-sim [0-9.]+$" &&
	out_has "^libsh2000 [0-9.]+ \(libsh2000\.so\.[0-9]+\)$" &&
	out_has "^protocol 1\.[0-9]+$" && out_has "^driver ABI [0-9]+$"
finish

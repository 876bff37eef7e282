#!/bin/bash
# sh2000ctl: devices that cannot be opened exit 3 with a message naming the
# device and the reason; $SH2000_DEVICE is the default.
. "$(dirname "$0")/testlib.sh"

expect 3 "$CTL" -d sim:nosuch-$$ status &&
	err_has "^sh2000ctl: sim:nosuch-$$: .*start sh2000-sim"
expect 3 "$CTL" -d /nonexistent/sh2000-9 status &&
	err_has "^sh2000ctl: /nonexistent/sh2000-9: cannot open"
expect 3 "$CTL" -d io:0x301 info && err_has "^sh2000ctl: io:0x301: .*4-aligned"
# the base is hexadecimal with 0x: io:300 (decimal 0x12c, a valid base
# of another board) is refused, not opened; the device named once
for d in io:300 io:0300 io:0x io:0x0x300; do
	expect 3 "$CTL" -d $d status &&
		err_has "^sh2000ctl: $d: not a port base: write it in hexadecimal with 0x"
done
expect 3 "$CTL" -d io:0x300 status && err_has "^sh2000ctl: io:0x300: [^:]*[a-z ]" &&
	err_lacks 'io:0x300: io:'
expect 3 "$CTL" -d bogus status && err_has "^sh2000ctl: bogus: "
# a regular file is no card (no driver behind it)
head -c 2048 /dev/zero >"$T/ram"
expect 3 "$CTL" -d "$T/ram" status && err_has "^sh2000ctl: $T/ram: "
# the environment variable, and -d over it
SH2000_DEVICE=sim:envcard-$$ expect 3 "$CTL" status && err_has "sim:envcard-$$"
# an empty -d is the library's empty string: $SH2000_DEVICE (docs/library.md)
SH2000_DEVICE=sim:envcard-$$ expect 3 "$CTL" -d "" status && err_has "sim:envcard-$$"
SH2000_DEVICE=sim expect 0 "$CTL" --device= status
SH2000_DEVICE=sim:envcard-$$ expect 0 "$CTL" -d sim status && out_has "^device  sim$"
SH2000_DEVICE=sim expect 0 "$CTL" status && out_has "^device  sim$"
# no -d, no variable: /dev/sh2000-0 (absent on the build host, unless a
# kernel card is loaded: then it must open)
if [ ! -e /dev/sh2000-0 ]; then
	expect 3 "$CTL" status && err_has "^sh2000ctl: /dev/sh2000-0: "
fi
finish

#!/bin/sh
# rtapi-exports.sh OUT OBJECT...
# The linker version script of a HAL module, as LinuxCNC's Makefile.modinc
# makes it: the names the objects list in their .rtapi_export section
# (EXPORT_SYMBOL, module parameters, rtapi_app_main/exit) are global,
# everything else, the statically linked libsh2000 included, is local.
set -e
out=$1
shift
tmp=$out.sym
: >"$tmp"
for o in "$@"; do
	objcopy -j .rtapi_export -O binary "$o" "$tmp.1"
	cat "$tmp.1" >>"$tmp"
done
{
	echo '{ global :'
	tr -s '\0' '\n' <"$tmp" | grep . | sed 's/$/;/'
	echo 'local : * ; };'
} >"$out"
rm -f "$tmp" "$tmp.1"

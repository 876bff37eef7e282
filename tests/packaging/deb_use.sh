# shellcheck shell=bash disable=SC2154  # the caller sets the variables named below
# Sourced by deb_install: the packages unpacked (dpkg -x) into throw-away
# roots and used from there.
#  - all of them in $root: the exported symbols of each library against
#    its -dev package's headers, the tools, and every consumer built with
#    pkg-config and with find_package (shared and static) and run on `sim`;
#  - each -dev package with only what it depends on of ours in a root of
#    its own: its headers compile alone, its consumer builds with its
#    pkg-config file and with its find_package component; and with
#    libsh2000-dev alone, a missing component is reported and `sim` says
#    which package it needs.
# Uses debs, ver, src, here, t, root, L, tools, field (deb_control.sh).
. "$here/consumers.sh"
cons=$here/consumer part=$src/examples/part.ngc
sys_pc=$(pkg-config --variable pc_path pkg-config)
# pkg-config of the root $proot: its .pc files first, then the system's
# (json-c); the root's prefix in place of /usr (json-c.pc's paths are
# literal). PKG_CONFIG_SYSROOT_DIR would move json-c into the root too.
pc() {
	PKG_CONFIG_PATH='' PKG_CONFIG_LIBDIR=$proot$L/pkgconfig:$sys_pc \
		pkg-config --define-variable=prefix="$proot/usr" "$@"
}
unpack() { # unpack ROOT PKG...
	local r=$1 p
	shift
	mkdir -p "$r"
	for p in "$@"; do dpkg -x "${debs[$p]}" "$r"; done
}
closure() { # closure PKG...: these and every package of ours they depend on
	local todo=("$@") seen=" " p d
	while [ ${#todo[@]} -gt 0 ]; do
		p=${todo[0]} todo=("${todo[@]:1}")
		[[ $seen == *" $p "* ]] && continue
		seen+="$p "
		for d in $(deps "$p" Depends | sed 's/[ |].*//'); do
			[ -n "${debs[$d]:-}" ] && todo+=("$d")
		done
	done
	echo $seen
}
# headers_alone DEV: each header of the package compiles on its own (C and
# C++) with its pkg-config file's flags.
headers_alone() {
	local h rel flags
	flags=$(pc --cflags "${dev_pc[$1]}")
	for h in $(headers_of "$1"); do
		rel=${h#/usr/include/}
		check "#include <$rel> alone (C)" q sh -c "printf '#include <%s>\nint main(void) { return 0; }\n' '$rel' |
			cc -std=c11 -Wall -Wextra -Werror -pedantic -fsyntax-only $flags -x c -"
		command -v c++ >/dev/null || continue
		check "#include <$rel> alone (C++)" q sh -c "printf '#include <%s>\nint main() { return 0; }\n' '$rel' |
			c++ -std=c++17 -Wall -Wextra -Werror -pedantic -fsyntax-only $flags -x c++ -"
	done
}
# findcomp NAME "ARG;ARG...": configure findcomp/ against $proot; the log
# is $t/fc-NAME.log, the status cmake's.
findcomp() {
	cmake -S "$here/findcomp" -B "$t/fc-$1" -DCMAKE_PREFIX_PATH="$proot/usr" \
		"-DARGS=$2" >"$t/fc-$1.log" 2>&1
}
logs() { # logs NAME ERE...: the log of findcomp NAME matches each
	local n=$1 e
	shift
	for e in "$@"; do grep -Eq "$e" "$t/fc-$n.log" || return 1; done
}
fails_saying() { # fails_saying NAME "ARGS" ERE: findcomp fails, saying so
	! findcomp "$1" "$2" && logs "$1" "$3"
}

# --- everything in one root ----------------------------------------------------------
unpack "$root" "${!debs[@]}"
ok "unpacked into $root"
lib=$root$L proot=$root
for l in libsh2000 libsh2000-motion libsh2000-sim; do
	check "$l.so.$ver has SONAME $l.so.0" \
		q sh -c "objdump -p '$lib/$l.so.$ver' | grep -Eq 'SONAME +$l\\.so\\.0\$'"
	abi_rules "$l"
	mapfile -t hdrs < <(headers_of "$l-dev" | sed "s|^|$root|")
	ABI_OUT=$t/$l.exported abi_check "$l.so" "$lib/$l.so.$ver" "${hdrs[@]}"
done
dup=$(cat "$t"/*.exported | sort | uniq -d | head -n 8 | tr '\n' ' ')
check "no symbol exported by two libraries${dup:+: $dup}" [ -z "$dup" ]
check "packaged dkms.conf: PACKAGE_VERSION=\"$ver\"" \
	grep -qx "PACKAGE_VERSION=\"$ver\"" "$root/usr/src/sh2000-$ver/dkms.conf"
same=1
while read -r f; do
	[ "$f" = dkms.conf ] && continue
	cmp -s "$src/$f" "$root/usr/src/sh2000-$ver/$f" || { same=0; note "differs: $f"; }
done < <(driver_files "$src")
check "packaged driver sources are the tree's" [ $same -eq 1 ]
bad=$(grep -rl "$b\|$src" "$root/usr/lib" "$root/usr/include" 2>/dev/null | head -n 3)
check "no build or source path in the installed files${bad:+: $bad}" [ -z "$bad" ]

abi=$(driver_abi "$src") proto=$(proto_version "$src")
for tool in "${tools[@]}"; do
	x=$root/usr/bin/$tool
	[ -x "$x" ] || continue
	if LD_LIBRARY_PATH=$lib "$x" --version >"$t/$tool.version" 2>&1; then
		ok "$tool --version: $(tr '\n' ' ' <"$t/$tool.version")"
		# Every --version names the library, protocol and driver ABI versions.
		lacking=
		grep -q "libsh2000 $ver" "$t/$tool.version" || lacking+=" libsh2000 $ver;"
		grep -q "protocol $proto" "$t/$tool.version" || lacking+=" protocol $proto;"
		grep -qi "ABI $abi" "$t/$tool.version" || lacking+=" driver ABI $abi;"
		check "$tool --version names library, protocol and driver ABI versions${lacking:+: lacks$lacking}" \
			[ -z "$lacking" ]
	else
		fail "$tool --version: $(tr '\n' ' ' <"$t/$tool.version")"
	fi
done
if [ -x "$root/usr/bin/sh2000ctl" ]; then
	if LD_LIBRARY_PATH=$lib "$root/usr/bin/sh2000ctl" -d sim status >"$t/status" 2>&1; then
		ok "sh2000ctl -d sim status"
	else
		fail "sh2000ctl -d sim status"
	fi
	sed 's/^/     /' "$t/status" | head -n 20
fi

if [ -n "${debs[python3-sh2000]:-}" ]; then
	check "python3-sh2000: import sh2000 from the root, open sim, check and run part.ngc" \
		env PYTHONPATH="$root/usr/lib/python3/dist-packages" LD_LIBRARY_PATH="$lib" \
		/usr/bin/python3 -c "import sh2000, sys
c = sh2000.open('sim')
p = c.program(sys.argv[1]); c.enable(p.check().moved)
assert sh2000.__file__.startswith('$root') and p.run().points > 0" "$part"
fi

for name in sh2000 sh2000-motion sh2000-sim; do
	check "pkg-config --modversion $name = $ver" [ "$(pc --modversion "$name")" = "$ver" ]
done
check "pkg-config --static --libs sh2000-motion has json-c (Requires.private)" \
	q sh -c "PKG_CONFIG_LIBDIR='$lib/pkgconfig:$sys_pc' pkg-config --static --libs sh2000-motion | grep -q -- -ljson-c"
check "pkg-config --libs sh2000-motion has no json-c (a private dependency)" \
	q sh -c "! PKG_CONFIG_LIBDIR='$lib/pkgconfig:$sys_pc' pkg-config --libs sh2000-motion | grep -q -- -ljson-c"
runenv="env LD_LIBRARY_PATH=$lib"
mkdir -p "$t/pc"
pc_consumers "$t/pc" "$lib"
cmake_consumers "$t/cm" -DCMAKE_PREFIX_PATH="$root/usr"
check "find_package found the root's package" \
	grep -q "sh2000_DIR:PATH=$lib/cmake/sh2000" "$t/cm/CMakeCache.txt"
# The version rule: 0.x minors are incompatible, a newer request fails.
IFS=. read -r ma mi _ <<<"$ver"
check "find_package(sh2000 $ma.$((mi + 1))) is refused" \
	q sh -c "! cmake -S '$cons' -B '$t/cm2' -DCMAKE_PREFIX_PATH='$root/usr' -DSH2000_WANT=$ma.$((mi + 1))"
findcomp all "REQUIRED;COMPONENTS;motion;sim"
check "find_package(sh2000 REQUIRED COMPONENTS motion sim): both found" \
	logs all 'sh2000_motion_FOUND=(1|TRUE)' 'sh2000_sim_FOUND=(1|TRUE)'

# --- each -dev package with what it depends on --------------------------------------
for dev in "${devs[@]}"; do
	pkgs=$(closure "$dev")
	proot=$t/only-$dev
	# shellcheck disable=SC2086
	unpack "$proot" $pkgs
	note "$dev alone: $pkgs"
	headers_alone "$dev"
	prog=${dev_prog[$dev]} comp=${dev_comp[$dev]}
	check "$dev alone: $prog builds with pkg-config ${dev_pc[$dev]}" \
		build_pc "$prog" "${dev_pc[$dev]}" "$proot/$prog"
	findcomp "$dev" "REQUIRED${comp:+;COMPONENTS;$comp}"
	check "$dev alone: find_package(sh2000 REQUIRED${comp:+ COMPONENTS $comp})" \
		logs "$dev" "sh2000_${comp:-}${comp:+_}FOUND=(1|TRUE)"
	for other in "${devs[@]}"; do
		[[ " $pkgs " == *" $other "* ]] && continue
		check "$dev alone: no ${dev_pc[$other]}.pc" no pc --exists "${dev_pc[$other]}"
	done
done

# libsh2000-dev alone: the components are missing, and say so.
proot=$t/only-libsh2000-dev
findcomp opt "OPTIONAL_COMPONENTS;motion;sim"
check "libsh2000-dev alone: OPTIONAL_COMPONENTS motion sim: sh2000 found, neither component" \
	logs opt 'sh2000_FOUND=(1|TRUE)' 'sh2000_motion_FOUND=(0|FALSE)$' 'sh2000_sim_FOUND=(0|FALSE)$'
findcomp comp "COMPONENTS;motion"
check "libsh2000-dev alone: COMPONENTS motion: sh2000 not found, install libsh2000-motion-dev" \
	logs comp 'sh2000_FOUND=(0|FALSE)$' 'install libsh2000-motion-dev'
check "libsh2000-dev alone: REQUIRED COMPONENTS sim fails: install libsh2000-sim-dev" \
	fails_saying req "REQUIRED;COMPONENTS;sim" 'install libsh2000-sim-dev'
check "libsh2000-dev alone: REQUIRED COMPONENTS bogus fails: no such component" \
	fails_saying bogus "REQUIRED;COMPONENTS;bogus" 'component bogus: no such component'
# `sim` with no libsh2000-sim anywhere: the error names the package.
if ldconfig -p | grep -q 'libsh2000-sim\.so\.0 '; then
	note "this machine has libsh2000-sim.so.0 installed: \`sim\` without it is left out"
elif out=$(LD_LIBRARY_PATH=$proot$L "$proot/consumer" sim 2>&1); then
	fail "libsh2000 without libsh2000-sim: \`sim\` opened: $out"
else
	check "libsh2000 without libsh2000-sim: \`sim\` fails naming the package: $out" \
		matches "$out" 'install libsh2000-sim'
fi

# shellcheck shell=bash disable=SC2154  # the caller sets the variables named below
# Sourced by deb_install: the packages' control fields and maintainer
# scripts. Uses debs, debver, ver, t, src.
field() { dpkg-deb -f "${debs[$1]}" "$2"; }
deps() { # deps PKG FIELD: one relation a line ("name (op ver)")
	field "$1" "$2" | tr ',' '\n' | sed 's/^ *//; s/ *$//'
}
has_dep() { deps "$1" "$2" | grep -Fqx "$3"; }
dep_matches() { deps "$1" "$2" | grep -Eq "$3"; }	# dep_matches PKG FIELD ERE
ctl() { dpkg-deb --ctrl-tarfile "${debs[$1]}" | tar -xO "./$2" 2>/dev/null; }

for p in "${!debs[@]}"; do
	check "$p: Package $p, Version $debver" \
		[ "$(field "$p" Package) $(field "$p" Version)" = "$p $debver" ]
	note "$p Depends: $(field "$p" Depends)"
done

# --- the libraries: shlibs, ldconfig, Depends --------------------------------
# What a program built against each library depends on: ">=" for libsh2000
# and libsh2000-motion (additions keep the SONAME), "=" for libsh2000-sim
# (no ABI promise to applications).
declare -A shlibs_op=([libsh2000]='>=' [libsh2000-motion]='>=' [libsh2000-sim]='=')
declare -A soname_pkg=()
for l in "${!shlibs_op[@]}"; do
	want="$l 0 $l (${shlibs_op[$l]} $debver)"
	check "$l: shlibs '$want'" [ "$(ctl "$l" shlibs)" = "$want" ]
	check "$l: ldconfig trigger" [ "$(ctl "$l" triggers)" = "activate-noawait ldconfig" ]
	soname_pkg[$l.so.0]=$l
done
# Symbols files: shipped as committed, checked by dpkg-gensymbols -c4 while
# cpack built the packages, and that check does fail on a symbol the file
# lists but the library lacks, and on one the library has but the file
# does not list (the shipped file with a line added, with one removed).
for l in libsh2000 libsh2000-motion; do
	check "$l: DEBIAN/symbols is cmake/debian/$l.symbols" \
		[ "$(ctl "$l" symbols)" = "$(cat "$src/cmake/debian/$l.symbols")" ]
	check "$l: cpack ran dpkg-gensymbols -c4 and it passed" \
		grep -Fq "dpkg-gensymbols -c4: $l matches its symbols file" "$t/cpack.log"
	mkdir -p "$t/sym/$l"
	dpkg-deb -x "${debs[$l]}" "$t/sym/$l"
	ctl "$l" symbols >"$t/sym/$l.ok"
	{ cat "$t/sym/$l.ok"; echo " sh2000_no_such_symbol@Base $ver"; } >"$t/sym/$l.gone"
	grep -v '^ sh2000_' "$t/sym/$l.ok" >"$t/sym/$l.new"
	grep '^ sh2000_' "$t/sym/$l.ok" | tail -n +2 >>"$t/sym/$l.new"
	for k in ok gone new; do
		(cd "$t/sym/$l" && dpkg-gensymbols -c4 -p"$l" -v"$debver" -P. \
			-I"$t/sym/$l.$k" -O"$t/sym/$l.$k.out") >/dev/null 2>&1
		echo $? >"$t/sym/$l.$k.rc"
	done
	check "$l: dpkg-gensymbols -c4 passes the packaged library with its file" \
		[ "$(cat "$t/sym/$l.ok.rc")" = 0 ]
	check "$l: and fails with a symbol removed from the library" \
		[ "$(cat "$t/sym/$l.gone.rc")" != 0 ]
	check "$l: and with a symbol the file does not list" \
		[ "$(cat "$t/sym/$l.new.rc")" != 0 ]
done
check "libsh2000-sim: no symbols file (no ABI promise; shlibs pins =)" \
	no q ctl libsh2000-sim symbols
check "libsh2000: Depends on libc6" dep_matches libsh2000 Depends '^libc6\b'
check "libsh2000: Recommends libsh2000-sim (loaded for \`sim\`)" \
	dep_matches libsh2000 Recommends '^libsh2000-sim( |$)'
check "libsh2000: no Depends on libsh2000-sim (real cards need no card model)" \
	no dep_matches libsh2000 Depends '^libsh2000-sim\b'
check "libsh2000-motion: Depends libsh2000 (>= $debver)" has_dep libsh2000-motion Depends "libsh2000 (>= $debver)"
check "libsh2000-motion: Depends on libjson-c5" dep_matches libsh2000-motion Depends '^libjson-c5\b'
check "libsh2000-sim: Depends libsh2000 (= $debver) (the private \`sim\` provider contract)" \
	has_dep libsh2000-sim Depends "libsh2000 (= $debver)"
check "libsh2000-sim: no Depends on libsh2000-motion" no dep_matches libsh2000-sim Depends motion

# Every binary of every package: each of our libraries it loads is in the
# package's Depends, as that library's shlibs says (or pinned to =).
mkdir -p "$t/x"
for p in "${!debs[@]}"; do
	dpkg -x "${debs[$p]}" "$t/x/$p"
	while read -r f; do
		readelf -h "$f" >/dev/null 2>&1 || continue
		for so in $(objdump -p "$f" | awk '/NEEDED/ && $2 ~ /^libsh2000/ {print $2}'); do
			l=${soname_pkg[$so]:-}
			if [ -z "$l" ]; then
				fail "$p: ${f#"$t/x/$p"} loads $so, which no package of ours ships"
				continue
			fi
			check "$p: ${f#"$t/x/$p"} loads $so: Depends $l (${shlibs_op[$l]} $debver)" \
				dep_matches "$p" Depends "^$l \\((${shlibs_op[$l]}|=) $debver\\)\$"
		done
	done < <(find "$t/x/$p" -type f)
done

# --- development packages -----------------------------------------------------
for dev in libsh2000-dev libsh2000-motion-dev libsh2000-sim-dev; do
	l=${dev%-dev}
	check "$dev: Depends $l (= $debver)" has_dep "$dev" Depends "$l (= $debver)"
	[ "$dev" = libsh2000-dev ] && continue
	check "$dev: Depends libsh2000-dev (= $debver)" has_dep "$dev" Depends "libsh2000-dev (= $debver)"
done
check "libsh2000-motion-dev: Depends libjson-c-dev (its static library links json-c)" \
	has_dep libsh2000-motion-dev Depends libjson-c-dev

# --- tools and driver -----------------------------------------------------------
if [ -n "${debs[sh2000-tools]:-}" ]; then
	check "sh2000-tools: Depends on libc6" dep_matches sh2000-tools Depends '^libc6\b'
	check "sh2000-tools: Depends libsh2000-sim (= $debver) (sh2000-sim, and -d sim)" \
		has_dep sh2000-tools Depends "libsh2000-sim (= $debver)"
fi
if [ -n "${debs[python3-sh2000]:-}" ]; then
	# the extension is built for Debian's python3 of this machine, one minor
	pyv=$(/usr/bin/python3 -c 'import sys; print("%d.%d" % sys.version_info[:2])')
	check "python3-sh2000: Depends python3 (>= $pyv~)" has_dep python3-sh2000 Depends "python3 (>= $pyv~)"
	check "python3-sh2000: Depends python3 (<< ${pyv%.*}.$((${pyv#*.} + 1)))" \
		has_dep python3-sh2000 Depends "python3 (<< ${pyv%.*}.$((${pyv#*.} + 1)))"
	check "python3-sh2000: Recommends libsh2000-sim (for \`sim\`)" \
		dep_matches python3-sh2000 Recommends '^libsh2000-sim( |$)'
	check "python3-sh2000: numpy recommended (the gather calls)" \
		dep_matches python3-sh2000 Recommends '(^|, )python3-numpy$'
	check "python3-sh2000: no Depends on python3-numpy" no dep_matches python3-sh2000 Depends numpy
	# the extension loads both libraries (the loop below checks the shlibs form)
	for l in libsh2000 libsh2000-motion; do
		check "python3-sh2000: Depends $l (>= $debver)" has_dep python3-sh2000 Depends "$l (>= $debver)"
	done
	check "python3-sh2000: postinst byte-compiles (py3compile -p python3-sh2000)" \
		grep -q '^[[:space:]]*py3compile -p python3-sh2000$' <(ctl python3-sh2000 postinst)
	check "python3-sh2000: prerm removes the byte-code (py3clean -p python3-sh2000)" \
		grep -q '^[[:space:]]*py3clean -p python3-sh2000$' <(ctl python3-sh2000 prerm)
fi
check "sh2000-dkms: Depends on dkms" dep_matches sh2000-dkms Depends '^dkms\b'
check "sh2000-dkms: Architecture all" [ "$(field sh2000-dkms Architecture)" = all ]
ctl sh2000-dkms postinst >"$t/postinst"
ctl sh2000-dkms prerm >"$t/prerm"
check "sh2000-dkms: postinst adds the sh2000 group" grep -q 'groupadd --system sh2000' "$t/postinst"
check "sh2000-dkms: postinst runs DKMS (common.postinst sh2000 $ver)" \
	grep -q "^VERSION=$ver\$" "$t/postinst"
check "sh2000-dkms: postinst calls common.postinst" grep -q '/usr/lib/dkms/common.postinst "\$NAME" "\$VERSION"' "$t/postinst"
check "sh2000-dkms: prerm runs dkms remove" grep -q 'dkms remove -m "\$NAME" -v "\$VERSION" --all' "$t/prerm"
check "sh2000-dkms: maintainer scripts parse" q sh -n "$t/postinst" "$t/prerm"

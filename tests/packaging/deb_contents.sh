# shellcheck shell=bash disable=SC2154  # the caller sets the variables named below
# Sourced by deb_install: what each package holds, and that no file is in
# two packages or in none. Uses debs, ver, src, b, t, L, tools. Leaves each
# package's file list in $t/<package>.files.
files() { dpkg-deb -c "${debs[$1]}" | awk '{print $6}' | sed 's|^\./|/|; s|/$||'; }
for p in "${!debs[@]}"; do files "$p" >"$t/$p.files"; done
contains() { grep -Fqx "$2" "$t/$1.files"; }
headers_of() { grep '^/usr/include/.*\.h$' "$t/$1.files"; }

# --- the libraries ----------------------------------------------------------------
for l in libsh2000 libsh2000-motion libsh2000-sim; do
	for f in $L/$l.so.0 $L/$l.so.$ver; do
		check "$l has $f" contains "$l" "$f"
	done
	n=$(grep -c '^/usr/lib/' "$t/$l.files")
	# the two above and the directory /usr/lib/<triplet>
	check "$l holds no other library ($n entries under /usr/lib/)" [ "$n" -eq 3 ]
done

# Each -dev package: its library's archive, link and pkg-config file, its
# CMake targets, and exactly the public headers of its layer's folders.
declare -A dev_layers=([libsh2000-dev]="device protocol" [libsh2000-motion-dev]=motion
	[libsh2000-sim-dev]=sim)
declare -A dev_cmake=([libsh2000-dev]=sh2000Targets [libsh2000-motion-dev]=sh2000MotionTargets
	[libsh2000-sim-dev]=sh2000SimTargets)
declare -A dev_pcfile=([libsh2000-dev]=sh2000 [libsh2000-motion-dev]=sh2000-motion
	[libsh2000-sim-dev]=sh2000-sim)
for dev in "${!dev_layers[@]}"; do
	l=${dev%-dev}
	for f in $L/$l.so $L/$l.a $L/pkgconfig/${dev_pcfile[$dev]}.pc \
		$L/cmake/sh2000/${dev_cmake[$dev]}.cmake; do
		check "$dev has $f" contains "$dev" "$f"
	done
	want=$(for layer in ${dev_layers[$dev]}; do
		for h in "$src/libsh2000/$layer/include/sh2000/"*.h; do
			echo "/usr/include/sh2000/${h##*/}"
		done
	done
	[ "$dev" = libsh2000-dev ] && echo /usr/include/sh2000/uapi/sh2000.h)
	got=$(headers_of "$dev")
	check "$dev has the headers of $(echo "${dev_layers[$dev]}" | sed 's/ / and /')/include (+ uapi in libsh2000-dev), no others: $(echo "$got" | sed 's|.*/||' | tr '\n' ' ')" \
		[ "$(sort <<<"$want")" = "$(sort <<<"$got")" ]
done
for f in $L/cmake/sh2000/sh2000Config.cmake $L/cmake/sh2000/sh2000ConfigVersion.cmake; do
	check "libsh2000-dev has $f" contains libsh2000-dev "$f"
done

# --- tools and driver ------------------------------------------------------------
for tool in "${tools[@]}"; do
	check "sh2000-tools has /usr/bin/$tool" contains sh2000-tools "/usr/bin/$tool"
done
for m in "$src"/tools/*/*.1; do
	[ -f "$m" ] || continue
	check "sh2000-tools has man page ${m##*/}" contains sh2000-tools "/usr/share/man/man1/${m##*/}.gz"
done
while read -r f; do
	check "sh2000-dkms has /usr/src/sh2000-$ver/$f" contains sh2000-dkms "/usr/src/sh2000-$ver/$f"
done < <(driver_files "$src")
n_src=$(grep -c "^/usr/src/sh2000-$ver/.*[^/]$" "$t/sh2000-dkms.files" | tr -d ' ')
n_want=$(driver_files "$src" | wc -l)
dirs=$(grep -c "^/usr/src/sh2000-$ver/\(driver\|driver/uapi\)\$" "$t/sh2000-dkms.files")
check "sh2000-dkms: /usr/src/sh2000-$ver holds the driver sources only ($n_src entries)" \
	[ "$n_src" -eq $((n_want + dirs)) ]
check "sh2000-dkms has the udev rule" contains sh2000-dkms /usr/lib/udev/rules.d/60-sh2000.rules
check "sh2000-dkms has the modprobe.d example" contains sh2000-dkms /usr/share/doc/sh2000-dkms/examples/sh2000.conf

# --- every package ------------------------------------------------------------------
for p in "${!debs[@]}"; do
	check "$p has /usr/share/doc/$p/copyright and changelog.Debian.gz" \
		q sh -c "grep -Fqx /usr/share/doc/$p/copyright '$t/$p.files' && grep -Fqx /usr/share/doc/$p/changelog.Debian.gz '$t/$p.files'"
done
# install() rules without a COMPONENT (e.g. in tools/*/CMakeLists.txt) land
# in "Unspecified", which no package takes: each such file must also be
# installed by cmake/Install.cmake's rules, i.e. be in a package.
DESTDIR=$t/unspec cmake --install "$b" --component Unspecified >/dev/null 2>&1
orphans=$(cd "$t/unspec" 2>/dev/null && find . -type f -o -type l | sed 's|^\.||' |
	while read -r f; do
		case $f in */share/man/*) f=$f.gz ;; esac
		cat "$t"/*.files | grep -Fqx "$f" || echo "$f"
	done)
check "every file any install() rule installs is in a package${orphans:+: $orphans}" [ -z "$orphans" ]
dup=$(cat "$t"/*.files | sort | uniq -d | while read -r f; do
	[ -n "$f" ] && ! grep -q "^$f/" "$t"/*.files && echo "$f"; done)
check "no file in two packages${dup:+: $dup}" [ -z "$dup" ]
bad=$(cat "$t"/*.files | grep -E '^/usr/local|^/debian|^/DEBIAN|/build|\.o$|\.ko$|\.cmd$|\.mod\.c$' | head -n 5)
check "no /usr/local, debian/, build paths or build outputs${bad:+: $bad}" [ -z "$bad" ]
if [ -n "${debs[sh2000-linuxcnc]:-}" ]; then
	for f in /usr/lib/linuxcnc/modules/hal_sh2000.so /usr/share/man/man9/hal_sh2000.9.gz \
		/usr/share/doc/sh2000-linuxcnc/examples/sh2000-sim/sh2000-sim.ini; do
		check "sh2000-linuxcnc has $f" contains sh2000-linuxcnc "$f"
	done
fi
if [ -n "${debs[python3-sh2000]:-}" ]; then
	# Where Debian's python3 finds it: the tree's Python files, the
	# extension for this python3's ABI (EXT_SUFFIX), no byte-code (postinst
	# compiles), the guide.
	py=/usr/lib/python3/dist-packages/sh2000
	ext=$(/usr/bin/python3 -c 'import sysconfig; print(sysconfig.get_config_var("EXT_SUFFIX"))')
	for f in $py/_sh2000$ext /usr/share/doc/python3-sh2000/python.md; do
		check "python3-sh2000 has $f" contains python3-sh2000 "$f"
	done
	want=$(cd "$src/python/sh2000" && ls -- *.py | sed "s|^|$py/|" | LC_ALL=C sort)
	got=$(grep "^$py/.*\.py\$" "$t/python3-sh2000.files" | LC_ALL=C sort)
	check "python3-sh2000 has the tree's $(echo "$want" | wc -l) Python files" [ "$got" = "$want" ]
	n=$(grep -c "^$py/" "$t/python3-sh2000.files")
	check "python3-sh2000: nothing else in $py ($n files)" [ "$n" -eq $(($(echo "$want" | wc -l) + 1)) ]
	check "python3-sh2000 holds no byte-code" no grep -Eq '__pycache__|\.pyc$' "$t/python3-sh2000.files"
fi

#!/usr/bin/env bash
# The Debian package CPack builds (docs/install.md): its Depends must name
# the package of every shared library the shipped binaries load (found by
# ldd, owned per dpkg -S), and nothing for mbx's static internals or -dev
# packages; the payload must be what `cmake --install` puts in /usr.
# usage: deb_test.sh <build dir> <work dir>
set -euo pipefail
build=$1 work=$2
rm -rf "$work"
mkdir -p "$work"
fail() { echo "deb_test: $*" >&2; exit 1; }

cpack -G DEB -B "$work" --config "$build/CPackConfig.cmake" >"$work/cpack.log" 2>&1 \
    || { cat "$work/cpack.log"; fail "cpack failed"; }
deb=$(find "$work" -maxdepth 1 -name 'mbx_*.deb' | head -1)
[[ -n "$deb" ]] || fail "no .deb produced"
depends=$(dpkg-deb -f "$deb" Depends)
echo "Depends: $depends"
# Package names only, one per line ("libfoo1 (>= 1.2), libbar" -> libfoo1, libbar).
depends_names=$(tr ',|' '\n\n' <<<"$depends" | sed 's/(.*)//; s/^ *//; s/ *$//' | sed '/^$/d')
if grep -q -- '-dev' <<<"$depends"; then fail "Depends names a -dev package: $depends"; fi

dpkg-deb -x "$deb" "$work/root"
for f in usr/include/mbx/mbx.h usr/bin/mbx usr/lib/libmbx.so.0 usr/lib/libmbx_files.so.0 \
         usr/lib/cmake/mbx/mbxConfig.cmake usr/lib/pkgconfig/mbx.pc usr/lib/python3/dist-packages/mbx/__init__.py; do
    [[ -e "$work/root/$f" ]] || fail "$f is not in the package"
done
if find "$work/root" -name '*.a' | grep -q .; then fail "static libraries in the package"; fi

# Every library the binaries need, outside the package itself, must come from a Depends package.
owner_of() {
    local path=$1 real
    real=$(realpath "$path")
    for candidate in "$path" "$real" "${real#/usr}" "/usr$real"; do
        dpkg -S "$candidate" 2>/dev/null | head -1 | cut -d: -f1 && return 0
    done
    return 1
}
checked=0
for bin in usr/lib/libmbx.so.0 usr/lib/libmbx_files.so.0 usr/bin/mbx; do
    # Direct needs only (readelf); ldd says where each resolves. What those
    # libraries need in turn is their packages' own Depends.
    resolved=$(LD_LIBRARY_PATH="$work/root/usr/lib" ldd "$work/root/$bin")
    for soname in $(readelf -d "$work/root/$bin" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p'); do
        [[ "$soname" == libmbx* ]] && continue
        # "soname => /path (addr)", or "/path/soname (addr)" for the dynamic loader.
        path=$(awk -v s="$soname" '$1 == s && $2 == "=>" {print $3} substr($1, length($1) - length(s)) == "/" s {print $1}' <<<"$resolved" | head -1)
        [[ "$path" == /* ]] || fail "$bin needs $soname, which does not resolve"
        pkg=$(owner_of "$path") || fail "$bin needs $soname ($path), which no Debian package owns"
        grep -Fxq "$pkg" <<<"$depends_names" || fail "$bin needs $soname from $pkg, not in Depends"
        checked=$((checked + 1))
    done
done
((checked > 5)) || fail "only $checked libraries checked"
echo "deb_test: $(basename "$deb"): $checked needed libraries, all from Depends"

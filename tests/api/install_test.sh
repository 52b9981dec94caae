#!/usr/bin/env bash
# The install test: `cmake --install` of a configured build into a temporary prefix, then the examples
# configured, built and run as a separate project that finds corebox with find_package(corebox), and
# falling_balls built once more from pkg-config's flags alone.
# Usage: install_test.sh SRC BUILD_DIR
set -euo pipefail
src=$1 build=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
prefix=$tmp/prefix

cmake --install "$build" --prefix "$prefix" > "$tmp/install.log"
for f in include/corebox/corebox.h include/corebox/corebox_c.h lib/cmake/corebox/coreboxConfig.cmake lib/pkgconfig/corebox.pc; do
    [[ -f $prefix/$f ]] || { echo "install_test: $f was not installed" >&2; cat "$tmp/install.log" >&2; exit 1; }
done
# Nothing internal leaks into the installed headers.
if grep -rlE '#include "(scene|backend|simulation|vec3)\.h"|cuda_runtime|epoxy|GLFW|imgui' "$prefix/include"; then
    echo "install_test: an installed header includes an internal or GL/CUDA header" >&2
    exit 1
fi

# The examples as an outside project: only the installed prefix is known to it.
cmake -S "$src/examples" -B "$tmp/examples" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release > "$tmp/configure.log" ||
    { cat "$tmp/configure.log" >&2; exit 1; }
cmake --build "$tmp/examples" -j2 > "$tmp/build.log" || { cat "$tmp/build.log" >&2; exit 1; }
"$tmp/examples/falling_balls" > "$tmp/falling.txt"
grep -q '^ball 9 at' "$tmp/falling.txt" || { echo "install_test: falling_balls printed no ball 9" >&2; cat "$tmp/falling.txt" >&2; exit 1; }
"$tmp/examples/pool_break" > "$tmp/pool.txt"
grep -q 'relative difference' "$tmp/pool.txt" || { cat "$tmp/pool.txt" >&2; exit 1; }

# pkg-config: the flags alone build and run it too.
export PKG_CONFIG_PATH=$prefix/lib/pkgconfig
# shellcheck disable=SC2046
c++ -std=c++17 "$src/examples/falling_balls.cpp" -o "$tmp/falling_pc" $(pkg-config --cflags --libs corebox) -Wl,-rpath,"$prefix/lib"
"$tmp/falling_pc" | grep -q '^ball 9 at'
echo "install_test: installed to a temporary prefix; falling_balls and pool_break built by find_package(corebox) and by pkg-config, and ran"
cat "$tmp/falling.txt" | tail -2

#!/usr/bin/env bash
# Each public header compiles alone, in its own translation unit, with nothing on the include path but
# include/ (no GL, CUDA, ImGui, CLI11 or internal headers): C++17 for every header, C99 as well for
# corebox_c.h. Usage: headers_alone.sh SRC CXX CC
set -euo pipefail
src=$1 cxx=$2 cc=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
count=0
for header in "$src"/include/corebox/*.h; do
    name=$(basename "$header")
    printf '#include <corebox/%s>\n#include <corebox/%s>\nint main() { return 0; }\n' "$name" "$name" > "$tmp/alone.cpp"
    "$cxx" -std=c++17 -Wall -Wextra -Werror -pedantic -fsyntax-only -I "$src/include" "$tmp/alone.cpp"
    count=$((count + 1))
done
printf '#include <corebox/corebox_c.h>\nint main(void) { return 0; }\n' > "$tmp/alone.c"
"$cc" -std=c99 -Wall -Wextra -Werror -pedantic -fsyntax-only -I "$src/include" "$tmp/alone.c"
echo "headers_alone: $count public headers compile alone (C++17), corebox_c.h also as C99"

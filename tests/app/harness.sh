# The shared frame of the app tests (sourced): a scratch folder removed on exit, pass/fail counters
# (the caller ends with `finish`), and pixel probes over png_stats.py for screenshots.
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
passed=0
failed=0
fail() { echo "FAIL: $*"; failed=$((failed + 1)); }
pass() { passed=$((passed + 1)); }
stats() { python3 "$(dirname "${BASH_SOURCE[0]}")/png_stats.py" "$@"; }
fraction() { stats "$@" | cut -d' ' -f2; }
above() { python3 -c "import sys; sys.exit(0 if float(sys.argv[1]) > float(sys.argv[2]) else 1)" "$1" "$2"; }

#!/usr/bin/env bash
# compute-sanitizer TOOL over the small GPU collision scene; exit 77 (ctest: skipped) without a GPU
# or without compute-sanitizer, non-zero when the tool reports anything.
set -u
tool=$1 binary=$2
if ! nvidia-smi -L >/dev/null 2>&1; then echo "no GPU: compute-sanitizer $tool skipped"; exit 77; fi
sanitizer=$(command -v compute-sanitizer || echo /usr/local/cuda/bin/compute-sanitizer)
if [ ! -x "$sanitizer" ]; then echo "compute-sanitizer not found: $tool skipped"; exit 77; fi
exec "$sanitizer" --tool "$tool" --error-exitcode 1 "$binary" --gtest_filter='CudaSanitized.*'

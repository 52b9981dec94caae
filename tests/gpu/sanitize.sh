#!/usr/bin/env bash
# compute-sanitizer TOOL over the small GPU collision scene (one GPU, and two where present); exit 77
# (ctest: skipped) without a GPU or without compute-sanitizer, non-zero when the tool reports anything.
# memcheck: every kernel and API call of corebox; the NCCL run apart, with API errors not reported
# (NCCL's start-up probes kernels of other architectures: its errors, not corebox's), memory errors
# still reported. racecheck: shared-memory hazards in the kernels, on one GPU and on the direct-access
# path (the only kernel change with several GPUs); copies and NCCL run no corebox kernel of their own.
# Both also run the pairs-once all-pairs pass (shared-memory column sums; memcheck also its share of
# two GPUs, peer reads) and the list pass with its collision screen and the walls-at-once stage
# (CudaPairsOnce.*, CudaNeighbourList.TheCollisionScreen*); memcheck also the steps that run ahead into buffers of their
# own (CudaNeighbourList.RunningAhead*), a small pile, whose contact sweeps
# run in one cooperative launch (CudaSanitized.ASmallPile*), and impact rounds on candidate rows
# (CudaSanitized.ImpactRoundsOnCandidateRows); racecheck does not, since it did not get through
# that launch's grid-wide barriers (80 steps of 160 balls still running after 120 s on an H100).
set -u
tool=$1 binary=$2
if ! nvidia-smi -L >/dev/null 2>&1; then echo "no GPU: compute-sanitizer $tool skipped"; exit 77; fi
sanitizer=$(command -v compute-sanitizer || echo /usr/local/cuda/bin/compute-sanitizer)
if [ ! -x "$sanitizer" ]; then echo "compute-sanitizer not found: $tool skipped"; exit 77; fi
if [ "$tool" = memcheck ]; then
  "$sanitizer" --tool memcheck --error-exitcode 1 "$binary" --gtest_filter='CudaSanitized.*:CudaPairsOnce.*:CudaNeighbourList.TheCollisionScreen*:CudaNeighbourList.RunningAhead*:CudaCellList.RebuildIfMoved*:-*Nccl*' || exit 1
  exec "$sanitizer" --tool memcheck --report-api-errors no --error-exitcode 1 "$binary" --gtest_filter='CudaSanitized.*Nccl*:CudaPairsOnce.*Nccl*'
fi
exec "$sanitizer" --tool "$tool" --error-exitcode 1 "$binary" \
  --gtest_filter='CudaSanitized.SmallSceneWithCollisions:CudaSanitized.*DirectAccess:CudaPairsOnce.GivesTheSameBitsRunToRun:CudaNeighbourList.TheCollisionScreen*'

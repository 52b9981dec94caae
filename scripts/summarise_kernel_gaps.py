#!/usr/bin/env python3
"""Sums the windows of a kernel-gaps CSV (tools/kernel_times.cpp, KERNEL_TIMES_GAPS; scripts/kernel-times
--gaps) and prints where the GPU stood idle the longest: each pair of activities a wait sat between (the
one that ran last before it, the one that ended it), with the waits' count and mean. A host's sync shows
as a copy to the host followed by a wait; a graph's or a node's overhead as the kernels around it.

    summarise_kernel_gaps.py CSV [--from W] [--to W] [--top N]

--from / --to: the windows [W0, W1) to sum (a pile's landing, its settled seconds), default all.
"""
import collections

from summarise_kernel_times import short_names, windowed_rows


def main():
    args, rows = windowed_rows(__doc__)
    names = short_names(sorted({r["before"] for r in rows} | {r["after"] for r in rows}))
    waits = collections.defaultdict(lambda: [0, 0])
    for r in rows:
        w = waits[(names[r["before"]], names[r["after"]])]
        w[0] += int(r["count"])
        w[1] += int(r["ns"])
    total = sum(ns for _, ns in waits.values())
    print(f"{args.csv}: the GPU idle {total / 1e6:.1f} ms in {sum(c for c, _ in waits.values())} waits")
    for (before, after), (count, ns) in sorted(waits.items(), key=lambda kv: -kv[1][1])[: args.top]:
        print(f"  {ns / 1e6:9.1f} ms {count:8d} x {ns / count / 1e3:7.1f} us  {before[:40]} -> {after[:40]}")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Sums the windows of a kernel-times CSV (tools/kernel_times.cpp, scripts/kernel-times) and prints
the GPU's busy time and the kernels (copies, memsets, API calls) that took the most, with their launches
and mean time a launch, names demangled (c++filt) and shortened.

    summarise_kernel_times.py CSV [--from W] [--to W] [--top N]

--from / --to: the windows [W0, W1) to sum (a pile's landing, its settled seconds), default all.
"""
import argparse
import collections
import csv
import re
import shutil
import subprocess


def short_names(names):
    """Demangled, without argument lists, template arguments and the project's namespaces."""
    demangled = list(names)
    if shutil.which("c++filt"):
        text = subprocess.run(["c++filt"], input="\n".join(names), capture_output=True, text=True).stdout
        demangled = text.split("\n")[: len(names)]
    out = {}
    for raw, name in zip(names, demangled):
        name = name.replace("(anonymous namespace)::", "").replace("void ", "")
        name = re.sub(r"\(.*", "", name)
        name = re.sub(r"<.*", "", name)
        out[raw] = name.replace("corebox::gpu::", "").replace("corebox::", "")
    return out


def windowed_rows(description):
    """The command line (CSV, --from, --to, --top) and the CSV's rows of the windows [from, to)."""
    parser = argparse.ArgumentParser(description=description, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("csv")
    parser.add_argument("--from", dest="first", type=int, default=0)
    parser.add_argument("--to", dest="last", type=int, default=None)
    parser.add_argument("--top", type=int, default=20)
    args = parser.parse_args()
    with open(args.csv, newline="") as f:
        rows = [r for r in csv.DictReader(f) if int(r["window"]) >= args.first and (args.last is None or int(r["window"]) < args.last)]
    return args, rows


def main():
    args, rows = windowed_rows(__doc__)
    if not rows:
        print("no windows in that range")
        return
    names = short_names(sorted({r["name"] for r in rows if r["name"] != "BUSY"}))
    ns, launches = collections.Counter(), collections.Counter()
    busy = 0
    windows = {int(r["window"]) for r in rows}
    for r in rows:
        if r["name"] == "BUSY":
            busy += int(r["ns"])
            continue
        ns[names[r["name"]]] += int(r["ns"])
        launches[names[r["name"]]] += int(r["count"])
    print(f"{args.csv}: windows {min(windows)} to {max(windows)}, GPU busy {busy / 1e6:.1f} ms")
    for name, total in ns.most_common(args.top):
        print(f"  {name[:70]:70s} {total / 1e6:10.2f} ms {launches[name]:8d} launches {total / 1e3 / launches[name]:9.1f} us each")


if __name__ == "__main__":
    main()

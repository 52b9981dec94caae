#!/usr/bin/env python3
"""Draws docs/images/p2p.png from the results of `corebox bench p2p` (docs/results/p2p*.csv).

The report's Figure 5 on our GPUs: the time for every GPU to fetch its neighbour's buffer against the
buffer's size, log-log, one line per method (DT-S, DT-A, DA, NCCL all-gather; and per GPU count when
the files hold several). A line drawn dashed went through host memory (no peer access between the
GPUs); a method that was refused or failed has no line and is named under the chart. The GPUs, driver
and the command of each file are written under the chart, so the figure names what made it.

Usage: scripts/plot_p2p.py [RESULTS.csv ...] [--out PNG]
"""
import argparse
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from bench_csv import BenchCsv, number  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parent.parent
NAMES = {"dts": "DT-S (cudaMemcpyPeer)", "dta": "DT-A (cudaMemcpyPeerAsync)", "da": "DA (peer-read kernel)",
         "nccl": "NCCL (ncclAllGather)"}
COLORS = {"dts": "tab:blue", "dta": "tab:green", "da": "tab:red", "nccl": "tab:purple"}


def size_label(b):
    for unit, scale in (("GiB", 1 << 30), ("MiB", 1 << 20), ("KiB", 1 << 10)):
        if b >= scale:
            return f"{b / scale:g} {unit}"
    return f"{b:g} B"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", nargs="*", type=pathlib.Path)
    parser.add_argument("--out", type=pathlib.Path, default=ROOT / "docs" / "images" / "p2p.png")
    args = parser.parse_args()
    paths = args.results or sorted((ROOT / "docs" / "results").glob("p2p*.csv"))
    if not paths:
        print("no p2p results; run `corebox bench p2p --out docs/results/p2p_NAME` first", file=sys.stderr)
        return 1

    files = [BenchCsv(p) for p in paths]
    several_p = len({r["gpus"] for f in files for r in f.rows}) > 1
    # A file's stem names a line only where two files hold the same GPU count.
    counts = [r["gpus"] for f in files for r in {r["gpus"]: r for r in f.rows}.values()]
    shared_p = {p for p in counts if counts.count(p) > 1}
    fig, ax = plt.subplots(figsize=(11, 6.5))
    notes, missing = [], []
    for k, f in enumerate(files):
        notes.append(f"{f.path.name}: {f.hardware_line()}\n    {f.command}")
        series = {}
        for r in f.rows:
            series.setdefault((int(r["gpus"]), r["method"]), []).append(r)
        for (p, method), rows in sorted(series.items()):
            ok = [r for r in rows if r["outcome"] == "ok"]
            if not ok:
                missing.append(f"{method} on {p} GPUs ({f.path.name}): {rows[0]['outcome']}: {rows[0]['message'][:160]}")
                continue
            ok.sort(key=lambda r: int(r["bytes"]))
            label = NAMES.get(method, method)
            if several_p:
                label += f", {p} GPUs"
            if str(p) in shared_p:
                label += f" [{f.path.stem}]"
            through_host = any(r["path"] == "host" for r in ok)
            if through_host:
                label += ", through host"
            ax.plot([int(r["bytes"]) for r in ok], [number(r["median_s"]) * 1e6 for r in ok],
                    color=COLORS.get(method, "tab:gray"), linestyle="--" if through_host else "-",
                    marker="os^v"[k % 4], markersize=4, label=label)
            unverified = [r for r in ok if r["verified"] != "yes"]
            for r in unverified:
                ax.plot(int(r["bytes"]), number(r["median_s"]) * 1e6, marker="x", color="black", markersize=9)
            if unverified:
                missing.append(f"{method} on {p} GPUs: {len(unverified)} sizes not verified (crosses)")
    ax.set_xscale("log", base=2)
    ax.set_yscale("log")
    ticks = sorted({int(r["bytes"]) for f in files for r in f.rows})
    ticks = ticks[::max(1, len(ticks) // 10)]
    ax.set_xticks(ticks)
    ax.set_xticklabels([size_label(b) for b in ticks], rotation=30)
    ax.set_xlabel("buffer per GPU")
    ax.set_ylabel("transfer time, median [us]")
    p_text = ", ".join(map(str, sorted({int(r["gpus"]) for f in files for r in f.rows})))
    ax.set_title(f"Every GPU fetches its neighbour's buffer at once ({p_text} GPUs): the report's Figure 5")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="upper left")
    footer = notes + ([""] + ["not drawn: " + m for m in missing] if missing else [])
    fig.text(0.01, 0.01, "\n".join(footer), fontsize=6.5, family="monospace", va="bottom")
    fig.subplots_adjust(left=0.08, right=0.97, top=0.93, bottom=0.16 + 0.035 * len(footer))
    args.out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.out, dpi=120)
    print(f"wrote {args.out.relative_to(ROOT) if args.out.is_relative_to(ROOT) else args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""Draws docs/images/table1.png from the results of `corebox bench table1` (docs/results/table1*.csv).

The report's Table 1 on our GPUs: milliseconds per RK4 step (pair forces and hard-core collisions)
against the particle count N, log-log, one line per GPU count and exchange method (one GPU has no
exchange), and the report's own lines (4 x Tesla C2070, DT-S, DT-A and DA) dashed in grey, read from
the report_*_ms columns of the same files. Failed configurations have no point and are named under
the chart, with the GPUs, driver and command of each file.

Usage: scripts/plot_table1.py [RESULTS.csv ...] [--out PNG]
"""
import argparse
import pathlib
import sys

import matplotlib
import matplotlib.ticker

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from bench_csv import BenchCsv, number  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parent.parent
# Colour by exchange method (one GPU, which exchanges nothing, in black), marker and line by GPU count.
EXCHANGE_COLORS = {"none": "black", "dts": "tab:blue", "dta": "tab:green", "da": "tab:red", "nccl": "tab:purple"}
P_STYLES = [("o", "-"), ("s", "-"), ("^", "--"), ("D", "-."), ("v", ":"), ("P", "-"), ("X", "--"), ("*", "-.")]
REPORT = [("report_dts_ms", "DT-S", ":"), ("report_dta_ms", "DT-A", "--"), ("report_da_ms", "DA", "-.")]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", nargs="*", type=pathlib.Path)
    parser.add_argument("--out", type=pathlib.Path, default=ROOT / "docs" / "images" / "table1.png")
    args = parser.parse_args()
    paths = args.results or sorted((ROOT / "docs" / "results").glob("table1*.csv"))
    if not paths:
        print("no table1 results; run `corebox bench table1 --out docs/results/table1_NAME` first", file=sys.stderr)
        return 1

    files = [BenchCsv(p) for p in paths]
    if args.results:
        draw(files, args.out)
        return 0
    # By default one chart per host: table1.png for the largest host measured (its runs cover every P the
    # smaller hosts ran), table1_<P>gpus.png for each smaller host with several GPUs (docs/multi_gpu.md
    # shows each under its host's table). A host's files (the report's N, the large N) join into one
    # line per P and exchange.
    hosts = sorted({f.gpu_count for f in files}, reverse=True)
    for host in hosts:
        if host != hosts[0] and host < 2:
            continue
        out = args.out if host == hosts[0] else args.out.with_name(f"{args.out.stem}_{host}gpus{args.out.suffix}")
        draw([f for f in files if f.gpu_count == host], out)
    return 0


def draw(files, out):
    precisions = sorted({r["precision"] for f in files for r in f.rows})
    several_hosts = len({f.gpu_count for f in files}) > 1
    fig, ax = plt.subplots(figsize=(12, 7))
    notes, failed = [], []
    report = {}
    series = {}
    for f in files:
        notes.append(f"{f.path.name}: {f.hardware_line()}\n    {f.command}")
        for r in f.rows:
            for column, _, _ in REPORT:
                if number(r[column]) is not None:
                    report.setdefault(column, {})[int(r["n"])] = number(r[column])
            if r["outcome"] != "ok":
                failed.append(f"N = {r['n']} {r['precision']} P = {r['gpus']} {r['exchange']}: {r['outcome']}: {r['message'][:140]}")
                continue
            series.setdefault((f.gpu_count, int(r["gpus"]), r["exchange"], r["precision"]), []).append(r)
    for (host, p, exchange, precision), rows in sorted(series.items()):
        rows.sort(key=lambda r: int(r["n"]))
        marker, line = P_STYLES[min(p - 1, len(P_STYLES) - 1)]
        label = "1 GPU" if p == 1 else f"{p} GPUs, {exchange}"
        if len(precisions) > 1:
            label += f", {precision}"
        if several_hosts:
            label += f" [{host}-GPU host]"
        ax.plot([int(r["n"]) for r in rows], [number(r["ms_per_step"]) for r in rows], linestyle=line, marker=marker,
                markersize=5, color=EXCHANGE_COLORS.get(exchange, "tab:gray"),
                alpha=1.0 if precision == precisions[0] else 0.55, label=label)
    for column, name, line in REPORT:
        points = sorted(report.get(column, {}).items())
        if points:
            ax.plot([n for n, _ in points], [ms for _, ms in points], color="grey", linestyle=line, linewidth=1.2,
                    label=f"report: 4 x Tesla C2070, {name}")
    ax.set_xscale("log", base=2)
    ax.set_yscale("log")
    sizes = sorted({int(r["n"]) for f in files for r in f.rows})
    ax.set_xticks(sizes)
    ax.set_xticklabels([str(n) for n in sizes], rotation=30)
    ax.xaxis.set_minor_locator(matplotlib.ticker.NullLocator())
    ax.set_xlabel("particles N")
    ax.set_ylabel("ms per RK4 step with collisions (median of batches)")
    ax.set_title(f"The report's Table 1: RK4 with collisions, {', '.join(precisions)}, one GPU and several, every exchange")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0)
    footer = notes + ([""] + ["failed: " + m for m in failed[:8]] if failed else [])
    if len(failed) > 8:
        footer.append(f"failed: ... and {len(failed) - 8} more (see the CSV)")
    fig.text(0.01, 0.01, "\n".join(footer), fontsize=6.5, family="monospace", va="bottom")
    fig.subplots_adjust(left=0.07, right=0.74, top=0.94, bottom=0.1 + 0.03 * len(footer))
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=120)
    plt.close(fig)
    print(f"wrote {out.relative_to(ROOT) if out.is_relative_to(ROOT) else out}")


if __name__ == "__main__":
    sys.exit(main())

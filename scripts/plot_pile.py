#!/usr/bin/env python3
"""Draws docs/images/pile_benchmark.png from the results of `corebox bench pile` (docs/results/pile_*.json).

Milliseconds per 1/60 s frame against the number of balls, one line per engine, backend and
precision (corebox CPU and CUDA in fp32 and fp64, Bullet). A run that failed (an instability: what
`corebox run` reports as exit code 3) is drawn as a cross at the time per frame of the frames it
completed, with the simulated time it reached; a run that finished but is not at rest, lets balls
escape, overlaps by 1% of a diameter or more, or gains energy is drawn hollow. The hardware and the
commands of the runs are written under the chart, so the figure names what made it.

Usage: scripts/plot_pile.py [RESULTS.json ...] [--out PNG]
"""
import argparse
import json
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parent.parent
OVERLAP_GOAL = 0.01


def series_name(r):
    if r["engine"] == "bullet":
        return f"Bullet ({r['precision']}, 1 thread)"
    device = "CPU" if r["backend"] == "cpu" else "CUDA"
    return f"corebox {device} {r['precision']}"


def meets_targets(r, tolerance):
    return (r["outcome"] == "ok" and r["time_to_rest"] is not None and r["outside"] == 0
            and r["max_overlap_fraction"] < OVERLAP_GOAL and r["energy_change_relative"] <= tolerance)


def style(name):
    if name.startswith("Bullet"):
        return {"color": "black", "linestyle": "--", "marker": "s"}
    colors = {"corebox CPU fp32": "tab:blue", "corebox CPU fp64": "tab:cyan",
              "corebox CUDA fp32": "tab:red", "corebox CUDA fp64": "tab:orange"}
    return {"color": colors.get(name, "tab:green"), "linestyle": "-", "marker": "o"}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", nargs="*", type=pathlib.Path)
    parser.add_argument("--out", type=pathlib.Path, default=ROOT / "docs" / "images" / "pile_benchmark.png")
    args = parser.parse_args()
    paths = args.results or sorted((ROOT / "docs" / "results").glob("pile_*.json"))
    if not paths:
        print("no pile results; run `corebox bench pile --out docs/results/pile_cpu` first", file=sys.stderr)
        return 1

    series = {}
    notes = []
    for path in paths:
        data = json.loads(path.read_text())
        if data.get("benchmark") != "pile":
            continue
        tolerance = data["scene"]["no_energy_gain_tolerance"]
        host = data["host"]
        notes.append(f"{path.name}: {data['device']}; host {host['cpu']} ({host['hardware_threads']} threads); "
                     f"{data['timestamp']}\n    {data['command']}")
        for r in data["results"]:
            if r["frames"] == 0:
                continue  # failed before its first frame: no time to show
            r = dict(r, met=meets_targets(r, tolerance))
            series.setdefault(series_name(r), []).append(r)

    fig, ax = plt.subplots(figsize=(12, 6.2))
    for name in sorted(series, key=lambda s: (s.startswith("Bullet"), s)):
        runs = sorted(series[name], key=lambda r: r["n"])
        st = style(name)
        ax.plot([r["n"] for r in runs], [r["ms_per_frame_mean"] for r in runs], color=st["color"],
                linestyle=st["linestyle"], label=name, zorder=2)
        for r in runs:
            x, y = r["n"], r["ms_per_frame_mean"]
            if r["outcome"] != "ok":
                ax.plot(x, y, marker="x", markersize=11, markeredgewidth=2.5, color=st["color"], zorder=3)
                ax.annotate(f"failed at t = {r['seconds_simulated']:.2f} s", (x, y), textcoords="offset points",
                            xytext=(7, -13), ha="left", fontsize=8, color=st["color"])
            else:
                face = st["color"] if r["met"] else "white"
                ax.plot(x, y, marker=st["marker"], markersize=7, color=st["color"], markerfacecolor=face, zorder=3)
    for fps in (60, 30):
        ax.axhline(1e3 / fps, color="grey", linewidth=0.8, linestyle=":")
        ax.text(1, 1e3 / fps, f" {fps} frames/s", transform=ax.get_yaxis_transform(),
                fontsize=8, color="grey", va="bottom", ha="right")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.margins(x=0.25)
    ax.set_xlabel("balls N")
    ax.set_ylabel("ms per 1/60 s frame (4 steps), mean over the run")
    ax.set_title("Ball pile: balls dropped into a 30 x 30 x 60 box (e = 0.5, g = 9.81, dt = 1/240)")
    ax.grid(True, which="both", alpha=0.3)
    handles, labels = ax.get_legend_handles_labels()
    handles += [plt.Line2D([], [], marker="o", color="grey", linestyle=""),
                plt.Line2D([], [], marker="o", color="grey", markerfacecolor="white", linestyle=""),
                plt.Line2D([], [], marker="x", color="grey", markeredgewidth=2.5, linestyle="")]
    labels += ["at rest, no escape, overlap < 1%, no energy gain", "finished, but a goal missed",
               "failed (instability): time over the frames completed"]
    ax.legend(handles, labels, fontsize=8, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0)
    fig.text(0.01, 0.01, "\n".join(notes), fontsize=6.5, family="monospace", va="bottom")
    fig.subplots_adjust(left=0.07, bottom=0.1 + 0.045 * len(notes), top=0.93, right=0.68)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.out, dpi=120)
    print(f"wrote {args.out.relative_to(ROOT) if args.out.is_relative_to(ROOT) else args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

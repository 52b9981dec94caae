#!/usr/bin/env python3
"""Draws docs/images/sandbox_frames.png: the sandbox example's time per frame, frame by frame.

Reads the --stats files of `sandbox` (docs/results/sandbox_*.json by default; files without per-frame
figures, from before they were written, are left out) and draws one panel per file: the whole frame,
the simulation (advance() and the state read), of it the impact rounds and the contact phase, and the
drawing, against the frame number, with the 60 Hz line (16.7 ms). What each panel ran on and its
command line are in its title and under the chart.

Usage: scripts/plot_sandbox_frames.py [STATS.json ...] [--out PNG]
"""
import argparse
import json
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parent.parent
FRAME_60HZ_MS = 1000.0 / 60.0


def load(paths):
    runs = []
    for path in paths:
        d = json.loads(pathlib.Path(path).read_text())
        if "per_frame_frame_ms" not in d:
            continue
        d["_file"] = pathlib.Path(path).name
        runs.append(d)
    return sorted(runs, key=lambda d: (d["backend"], d["n_start"], d.get("pipelined", False)))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("stats", nargs="*", help="sandbox --stats files (default: docs/results/sandbox_*.json)")
    parser.add_argument("--out", default=str(ROOT / "docs" / "images" / "sandbox_frames.png"))
    args = parser.parse_args()
    paths = args.stats or sorted(str(p) for p in (ROOT / "docs" / "results").glob("sandbox_*.json"))
    runs = load(paths)
    if not runs:
        raise SystemExit("no sandbox statistics with per-frame figures among: " + ", ".join(paths))
    fig, axes = plt.subplots(len(runs), 1, figsize=(10, 3.2 * len(runs) + 0.4 * len(runs)), squeeze=False)
    notes = []
    for ax, d in zip(axes[:, 0], runs):
        frames = range(len(d["per_frame_frame_ms"]))
        ax.plot(frames, d["per_frame_frame_ms"], color="black", lw=1.2, label="frame")
        ax.plot(frames, d["per_frame_sim_ms"], color="tab:blue", lw=1, label="simulation")
        ax.plot(frames, d["per_frame_contacts_ms"], color="tab:green", lw=0.8, label="of it: contact phase")
        ax.plot(frames, d["per_frame_impacts_ms"], color="tab:orange", lw=0.8, label="of it: impact rounds")
        ax.plot(frames, d["per_frame_render_ms"], color="tab:purple", lw=0.8, label="drawing")
        ax.axhline(FRAME_60HZ_MS, color="red", ls="--", lw=0.8, label="60 Hz")
        hardware = d.get("gpu") or f"{d['cpu']} (CPU)"
        frame = d["frame_ms"]
        ax.set_title(f"{d['n_start']:,} balls, {d['backend']} {d['precision']}, {hardware}, "
                     f"{'pipelined' if d.get('pipelined') else 'sequential'} frames: "
                     f"frame mean {frame['mean']:.1f} / median {frame['median']:.1f} ms", fontsize=9)
        ax.set_ylabel("ms")
        ax.set_ylim(0, 1.05 * max(max(d["per_frame_frame_ms"][10:] or [0]), 2 * FRAME_60HZ_MS))
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, ncol=6, loc="upper right")
        notes.append(f"{d['_file']}: {d['command_line']}")
    axes[-1, 0].set_xlabel("frame (1/60 s of simulated time each, 4 substeps)")
    fig.text(0.01, 0.005, "\n".join(notes), fontsize=6, va="bottom", family="monospace")
    fig.tight_layout(rect=(0, 0.03 * len(runs), 1, 1))
    fig.savefig(args.out, dpi=110)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""The sandbox example's frame times in docs/library.md, from its --stats files in docs/results/.

Reads docs/results/sandbox_*.json (written by `sandbox --stats FILE`) and rewrites the table between
the markers <!-- sandbox-table:begin --> and <!-- sandbox-table:end --> in docs/library.md.
"""
import glob
import json
import os
import re

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
doc = os.path.join(root, "docs", "library.md")


def row(path):
    d = json.load(open(path))
    # Early files name the CUDA backend only ("cuda"); the GL renderer names the same GPU then.
    gpu = d["gpu"] if d["gpu"] not in (None, "cuda") else (d["gl_renderer"].split("/")[0] if d["gpu"] else None)
    where = gpu or (d["cpu"] + ", 2 cores")
    frame, sim, render = d["frame_ms"], d["sim_ms"], d["render_ms"]
    # The rate is the measured frames over the wall time they spanned (paced runs wait for each refresh
    # outside a frame's time); files from before `measured_s` give 1000 / the mean frame time.
    hz = d["fps_mean"] if "measured_s" in d else 1000.0 / frame["mean"]
    depth = ", flat depth" if d.get("exact_depth") is False else ""
    # Files from before pipelined frames and the samples choice: sequential frames, 4 samples a pixel.
    frames = "pipelined" if d.get("pipelined", False) else "sequential"
    paced = f", paced {d['paced_hz']} Hz" if d.get("paced_hz", 0) else ""
    # The solver's caps as the run set them (0: corebox's own, 64 impact rounds, 16 sweeps and 32 listings);
    # files from before the fields name them on the command line only.
    def cap(field, flag):
        if field in d:
            return d[field]
        found = re.search(flag + r" (\d+)", d["command_line"])
        return int(found.group(1)) if found else 0
    sweeps, rounds = cap("contact_sweeps", "--contact-sweeps"), cap("impact_rounds", "--impact-rounds")
    listings = cap("contact_listings", "--contact-listings")
    solver = f", {rounds} impact rounds" if rounds else ""
    solver += f", {sweeps} sweeps" if sweeps else ""
    solver += f", {listings} listings" if listings else ""
    samples = d.get("samples", 4)
    # Frames past 1/60 s and the slowest, after the skipped start-up frames.
    measured = d.get("per_frame_frame_ms", [])[d.get("skipped_frames", 10):]
    past = sum(1 for ms in measured if ms > 1000.0 / 60.0)
    late = f"{past} of {len(measured)}, {max(measured):.1f}" if measured else "n/a"
    return (d["n_start"], d["backend"], frames != "pipelined", paced, solver,
            f"| {d['n_start']:,} | {d['backend']} {d['precision']} | {where} | {d['gl_renderer'].split(' (')[0]}, {samples or 1} sample{'s' if samples > 1 else ''}{depth} "
            f"| {frames}{paced}{solver} | {sim['mean']:.1f} / {sim['median']:.1f} / {sim['p95']:.1f} | {render['mean']:.1f} "
            f"| {frame['mean']:.1f} / {frame['median']:.1f} / {frame['p95']:.1f} "
            f"| {hz:.0f} | {late} | {d['pair_collisions']:,} | `{os.path.basename(path)}` |")


rows = sorted(row(p) for p in glob.glob(os.path.join(root, "docs", "results", "sandbox_*.json")))
table = ["| balls | backend | hardware | GL | frames, solver caps | simulation ms mean / median / p95 | render ms | frame ms mean / median / p95 | frames/s | frames past 1/60 s, slowest ms | ball impacts | file |",
         "|---|---|---|---|---|---|---|---|---|---|---|---|"] + [r[-1] for r in rows]
text = open(doc).read()
block = "<!-- sandbox-table:begin -->\n" + "\n".join(table) + "\n<!-- sandbox-table:end -->"
text, n = re.subn(r"<!-- sandbox-table:begin -->.*?<!-- sandbox-table:end -->", block, text, flags=re.S)
if n != 1:
    raise SystemExit("docs/library.md has no sandbox-table markers")
open(doc, "w").write(text)
print(f"docs/library.md: {len(rows)} sandbox runs")

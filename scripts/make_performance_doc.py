#!/usr/bin/env python3
"""Writes docs/performance.md from the benchmark results in docs/results/*.json.

Every table names the hardware, the command and the time of the run that produced it; nothing in
the document is typed by hand. Run after a benchmark: scripts/bench-cpu (or the GPU benchmarks).
"""
import json
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
RESULTS = ROOT / "docs" / "results"
OUTPUT = ROOT / "docs" / "performance.md"


def force_table(data):
    lines = [
        f"### Force pass: {data['backend']} on {data['device']}",
        "",
        f"- model: {data['model']}",
        f"- host: {data['host']['cpu']}, {data['host']['hardware_threads']} hardware threads",
        f"- command: `{data['command']}`",
        f"- measured: {data['timestamp']}",
        "",
    ]
    # Records from before the pairs-once kernel have no kernel column: every ordered pair evaluated.
    if any("kernel" in r for r in data["results"]):
        lines += [
            "Pair interactions are counted as NVIDIA's nbody counts them (N (N - 1) a pass, whatever the kernel does);",
            "evaluations are the pairs the kernel computed: `pairs_once` evaluates each pair once (Newton's third law),",
            "`ordered` every ordered pair. P: the GPUs sharing the pass (records without it ran on one).",
            "",
            "| precision | N | P | kernel | pair interactions / s | a GPU | pair evaluations / s | passes | seconds |",
            "|---|---:|---:|---|---:|---:|---:|---:|---:|",
        ]
        for r in data["results"]:
            gpus = r.get("gpus", 1)
            lines.append(
                f"| {r['precision']} | {r['n']} | {gpus} | {r['kernel']} | {r['pair_interactions_per_second']:.3e} |"
                f" {r['pair_interactions_per_second'] / gpus:.3e} |"
                f" {r['pair_evaluations_per_second']:.3e} | {r['passes']} | {r['seconds']:.2f} |"
            )
        return "\n".join(lines) + "\n"
    lines += ["| precision | N | pair interactions / s | passes | seconds |", "|---|---:|---:|---:|---:|"]
    for r in data["results"]:
        lines.append(
            f"| {r['precision']} | {r['n']} | {r['pair_interactions_per_second']:.3e} | {r['passes']} | {r['seconds']:.2f} |"
        )
    return "\n".join(lines) + "\n"


# Targets on one H200 (DESIGN.md sec. 6 and the CUDA backend's issue), checked against the records.
TARGETS = [
    ("force pass fp32, N >= 65536", lambda r: r["kind"] == "force_pass" and r["precision"] == "fp32" and r["n"] >= 65536,
     "min", 1.5e12, "pair interactions/s"),
    ("force pass fp64, N >= 65536", lambda r: r["kind"] == "force_pass" and r["precision"] == "fp64" and r["n"] >= 65536,
     "min", 0.6e12, "pair interactions/s"),
    ("RK4 full step with collisions, N = 65536, fp32",
     lambda r: r["kind"] == "step" and r["precision"] == "fp32" and r["method"] == "rk4" and r["n"] == 65536, "max", 15.0, "ms"),
    ("headless interop rendering, 10^6 particles at 1920x1080",
     lambda r: r["kind"] == "frame" and r["method"] == "render" and r["n"] >= 1000000, "extra", 60.0, "frames/s"),
]


def targets(rows):
    out = ["#### Targets", "", "| target | goal | measured | met |", "|---|---:|---:|---|"]
    for name, select, how, goal, unit in TARGETS:
        picked = [r for r in rows if select(r)]
        if not picked:
            continue
        if how == "min":
            value = min(r["value"] for r in picked)
            ok = value >= goal
            out.append(f"| {name} | >= {goal:.3g} {unit} | {value:.3g} (lowest over N) | {'yes' if ok else 'no'} |")
        elif how == "max":
            value = max(r["value"] for r in picked)
            ok = value <= goal
            out.append(f"| {name} | <= {goal:g} {unit} | {value:.2f} | {'yes' if ok else 'no'} |")
        else:
            value = min(r["extra"] for r in picked)
            ok = value >= goal
            out.append(f"| {name} | >= {goal:g} {unit} | {value:.1f} | {'yes' if ok else 'no'} |")
    return out


def throughput_tables(data):
    head = [
        f"### Throughput: {data['backend']} on {data['device']}",
        "",
        f"- model: {data['model']}",
        f"- host: {data['host']['cpu']}, {data['host']['hardware_threads']} hardware threads",
        f"- command: `{data['command']}`",
        f"- measured: {data['timestamp']}",
        "",
    ]
    rows = data["results"]
    force = ["#### Force pass", "", "| precision | N | pair interactions / s |", "|---|---:|---:|"]
    force += [f"| {r['precision']} | {r['n']} | {r['value']:.3e} |" for r in rows if r["kind"] == "force_pass"]
    step = ["#### Full step (integrate + collide)", "", "| precision | method | N | ms / step | steps / s | collisions / step |",
            "|---|---|---:|---:|---:|---:|"]
    step += [f"| {r['precision']} | {r['method']} | {r['n']} | {r['value']:.2f} | {1e3 / r['value']:.1f} | {r['extra']:.0f} |"
             for r in rows if r["kind"] == "step"]
    frame = ["#### Frames (headless)", "", "| stage | N | ms / frame | frames / s |", "|---|---:|---:|---:|"]
    frame += [f"| {r['method']} | {r['n']} | {r['value']:.2f} | {r['extra']:.1f} |" if r["extra"] else
              f"| {r['method']} | {r['n']} | {r['value']:.2f} | |" for r in rows if r["kind"] == "frame"]
    parts = head + force + [""] + step + [""] + targets(rows) + [""]
    if len(frame) > 4:
        parts += frame + [""]
    return "\n".join(parts)


def pile_tables(data):
    """`corebox bench pile`: one row per run, corebox and Bullet side by side, and the issue's targets."""
    lines = [
        f"### Ball pile: {data['backend']} on {data['device']}",
        "",
        f"- scene: {data['scene']['description']}; box {data['scene']['box_rule']}; {data['scene']['placement']};"
        f" {data['scene']['frame']}",
        f"- rest: {data['scene']['rest']}; energy: {data['scene']['energy']}",
        f"- Bullet: {data['bullet']}",
        f"- host: {data['host']['cpu']}, {data['host']['hardware_threads']} hardware threads",
        f"- command: `{data['command']}`",
        f"- measured: {data['timestamp']}",
        "- chart: `docs/images/pile_benchmark.png` (`scripts/plot_pile.py`)",
        "",
        "| engine | precision | N | outcome | simulated s | ms / frame | ms / frame, last s | max overlap | outside |"
        " energy change | time to rest s | round-cap hits |",
        "|---|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in data["results"]:
        engine = "Bullet" if r["engine"] == "bullet" else f"corebox {r['backend']}"
        rest = f"{r['time_to_rest']:.2f}" if r["time_to_rest"] is not None else "not reached"
        caps = "" if r["round_cap_hits"] is None else str(r["round_cap_hits"])
        lines.append(
            f"| {engine} | {r['precision']} | {r['n']} | {r['outcome']} | {r['seconds_simulated']:.2f} |"
            f" {r['ms_per_frame_mean']:.1f} | {r['ms_per_frame_last_second']:.1f} | {r['max_overlap_fraction']:.4f} |"
            f" {r['outside']} | {r['energy_change_relative']:+.2e} | {rest} | {caps} |"
        )
    failures = [r for r in data["results"] if r["outcome"] != "ok"]
    if failures:
        lines += ["", "Failures:", ""]
        lines += [f"- corebox {r['backend']} {r['precision']} N = {r['n']}: {r['message']}" for r in failures]
    lines += ["", "#### Targets", "", "| target | run | measured | met |", "|---|---|---|---|"]
    for t in data["targets"]:
        lines.append(f"| {t['target']} | {t['backend']} {t['precision']} N = {t['n']} | {t['measured']} |"
                     f" {'yes' if t['met'] else 'no'} |")
    return "\n".join(lines) + "\n"


def main():
    sections = []
    for path in sorted(RESULTS.glob("*.json")):
        data = json.loads(path.read_text())
        if data.get("benchmark") == "force_pass":
            sections.append(force_table(data) + f"\nSource: `docs/results/{path.name}`\n")
        elif data.get("benchmark") == "throughput":
            sections.append(throughput_tables(data) + f"\nSource: `docs/results/{path.name}`\n")
        elif data.get("benchmark") == "pile":
            sections.append(pile_tables(data) + f"\nSource: `docs/results/{path.name}`\n")
    if not sections:
        print("no results in docs/results; run a benchmark first", file=sys.stderr)
        return 1
    text = (
        "# Performance\n\n"
        "Generated by `scripts/make_performance_doc.py` from `docs/results/*.json`; do not edit by hand.\n"
        "Each benchmark writes its JSON with the hardware and the exact command, so every number below\n"
        "can be reproduced.\n\n" + "\n".join(sections)
    )
    OUTPUT.write_text(text)
    print(f"wrote {OUTPUT.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

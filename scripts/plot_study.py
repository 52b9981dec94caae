#!/usr/bin/env python3
"""Draws the speed-against-accuracy charts of `corebox study` results (docs/results/study_*.json).

One PNG per study, docs/images/study_<scene>_<backend>.png, three panels:
  1. state error at the horizon T against force passes per unit time (log-log, one line per method,
     fp64 solid, fp32 dashed, the reference's own error as a floor);
  2. the largest excursion of the conserved sum over the long run L against the same cost;
  3. the largest stable step of each method, as omega*dt in units where velocity Verlet's measured
     limit is its linear bound 2, beside the linear bound on the imaginary axis of each method.
Every figure names the study's command, machine and time. Usage:
  scripts/plot_study.py [RESULT.json ...] [--out-dir DIR]
"""
import argparse
import json
import math
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parent.parent

# Linear stability bounds on the imaginary axis, omega*dt (tests/physics/test_stability.cpp measures
# each on the LJ oscillator): Euler and RK2 have none (0: they gain energy at every step).
LINEAR_BOUND = {
    "euler": 0.0, "rk2": 0.0, "rk4": 2.83, "dp5": 1.0, "hairer10": 1.16, "verlet": 2.0,
    "forest_ruth": 1.57, "pefrl": 2.99, "blanes_moan": 3.16, "yoshida6": 2.27, "yoshida8": 2.36,
}
ORDER = list(LINEAR_BOUND)
COLOURS = dict(zip(ORDER, plt.cm.tab20.colors[::2] + plt.cm.tab20.colors[1::2]))


def positive(v):
    return v is not None and isinstance(v, (int, float)) and math.isfinite(v) and v > 0


def series(data, method, precision, key):
    pts = []
    for r in data["runs"]:
        if r["method"] != method or r["precision"] != precision or r["outcome"] != "ok":
            continue
        if r["tolerance"] and r["tolerance"] > 0:
            continue
        if positive(r.get(key)) and positive(r.get("force_passes_per_time")):
            pts.append((r["force_passes_per_time"], r[key]))
    return sorted(pts)


def adaptive_points(data, precision, key):
    return sorted((r["force_passes_per_time"], r[key]) for r in data["runs"]
                  if r["method"] == "dp5" and r["precision"] == precision and r["tolerance"] and r["outcome"] == "ok"
                  and positive(r.get(key)) and positive(r.get("force_passes_per_time")))


def plot(data, out):
    fig, axes = plt.subplots(1, 3, figsize=(18, 6.2))
    methods = [m for m in ORDER if any(r["method"] == m for r in data["runs"])]
    # The legend names each method once, on its fp64 line, or its fp32 line in an fp32-only study.
    label_precision = "fp64" if any(r["precision"] == "fp64" for r in data["runs"]) else "fp32"
    for ax, key, title in ((axes[0], "state_error", f"state error at T = {data['horizon']:.3g} (RMS, sigma)"),
                           (axes[1], "energy_error_max", f"max |E - E0| / energy scale over L = {data['long_run']:.3g}")):
        for m in methods:
            for precision, style in (("fp64", "-"), ("fp32", "--")):
                pts = series(data, m, precision, key)
                if pts:
                    ax.plot(*zip(*pts), style, marker="o", ms=3, color=COLOURS[m],
                            label=m if precision == label_precision else None)
        for precision, style in (("fp64", "-"), ("fp32", "--")):
            pts = adaptive_points(data, precision, key)
            if pts:
                ax.plot(*zip(*pts), style, marker="s", ms=4, color="black",
                        label="dp5 adaptive" if precision == label_precision else None)
        if key == "state_error" and positive(data.get("reference_error")):
            ax.axhline(data["reference_error"], color="grey", lw=0.8, ls=":")
            ax.text(ax.get_xlim()[0], data["reference_error"], " reference's own error", color="grey", va="bottom", fontsize=8)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("force passes per unit time (cost)")
        ax.set_title(title, fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=7, ncol=2, title="solid fp64, dashed fp32", title_fontsize=7)

    ax = axes[2]
    limits = {(s["method"], s["precision"]): s for s in data.get("stability", [])}
    lp = "fp64" if ("verlet", "fp64") in limits else "fp32"  # an fp32-only study shows its fp32 limits
    verlet = limits.get(("verlet", lp))
    if verlet and positive(verlet["stable_dt"]):
        omega = 2.0 / verlet["stable_dt"]  # the scene's fastest frequency, as Verlet's limit sees it
        names = [m for m in methods if (m, lp) in limits]
        xs = range(len(names))
        measured = [omega * limits[(m, lp)]["stable_dt"] for m in names]
        ax.bar([x - 0.2 for x in xs], measured, width=0.4, color=[COLOURS[m] for m in names], label=f"measured ({lp})")
        ax.bar([x + 0.2 for x in xs], [LINEAR_BOUND[m] for m in names], width=0.4, color="lightgrey", edgecolor="grey",
               label="linear bound")
        for x, m in zip(xs, names):
            s = limits[(m, lp)]
            ax.text(x - 0.2, omega * s["stable_dt"], s["failure"].replace("_", " "), rotation=90, fontsize=6, ha="center",
                    va="bottom")
        ax.set_xticks(list(xs))
        ax.set_xticklabels(names, rotation=45, ha="right", fontsize=8)
        ax.set_ylabel("largest stable omega*dt (omega from Verlet's limit)")
        ax.legend(fontsize=8)
    else:
        ax.text(0.5, 0.5, "no stability search in this study", ha="center", transform=ax.transAxes)
    ax.set_title("stability: largest stable step, and how the next one failed", fontsize=10)

    scene = pathlib.Path(data["scene"]).stem
    fig.suptitle(f"corebox study of {scene}: {data['particles']} particles on {data['device']}, thermostat {data['thermostat']}",
                 fontsize=11)
    fig.text(0.01, 0.01, f"{data['command']}\n{data['host']['cpu']}; {data['timestamp']}; reference {data['reference']}",
             fontsize=7, family="monospace")
    fig.tight_layout(rect=(0, 0.05, 1, 0.95))
    fig.savefig(out, dpi=90)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", nargs="*", type=pathlib.Path)
    parser.add_argument("--out-dir", type=pathlib.Path, default=ROOT / "docs" / "images")
    args = parser.parse_args()
    paths = args.results or sorted((ROOT / "docs" / "results").glob("study_*.json"))
    if not paths:
        raise SystemExit("no results: run `corebox study SCENE --out docs/results/study_NAME` first")
    args.out_dir.mkdir(parents=True, exist_ok=True)
    for path in paths:
        out = args.out_dir / f"{path.stem}.png"
        plot(json.loads(path.read_text()), out)
        print(f"wrote {out.relative_to(ROOT) if out.is_relative_to(ROOT) else out}")


if __name__ == "__main__":
    main()

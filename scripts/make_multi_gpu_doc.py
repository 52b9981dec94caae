#!/usr/bin/env python3
"""Writes docs/multi_gpu.md from the results of `corebox bench table1` and `corebox bench p2p`.

Reads docs/results/table1*.csv and docs/results/p2p*.csv (or the files named), and writes the
report's Table 1 and Figure 5 as measured here: every number comes from those files, with the GPUs,
driver, link topology and the command recorded in them; nothing in the page is typed by hand. Draw
the charts it shows first (scripts/plot_table1.py, scripts/plot_p2p.py).

Usage: scripts/make_multi_gpu_doc.py [RESULTS.csv ...] [--out MD]
"""
import argparse
import pathlib
import sys

from bench_csv import BenchCsv, number

ROOT = pathlib.Path(__file__).resolve().parent.parent
RESULTS = ROOT / "docs" / "results"
METHOD_ORDER = ["dts", "dta", "da", "nccl"]
METHOD_NAMES = {"dts": "DT-S", "dta": "DT-A", "da": "DA", "nccl": "NCCL", "none": "-"}
REPORT_COLUMN = {"dts": "report_dts_ms", "dta": "report_dta_ms", "da": "report_da_ms"}


def fmt(value, spec):
    return "" if value is None else format(value, spec)


def size_label(b):
    for unit, scale in (("GiB", 1 << 30), ("MiB", 1 << 20), ("KiB", 1 << 10)):
        if b >= scale:
            return f"{b / scale:g} {unit}"
    return f"{b} B"


def relative(path):
    path = pathlib.Path(path).resolve()
    return path.relative_to(ROOT) if path.is_relative_to(ROOT) else path


def provenance(f):
    lines = [f"- GPUs: {f.gpu_count} visible to CUDA; driver {f.driver}"]
    lines += [f"  - {g}" for g in f.gpus]
    lines += [f"- command: `{f.command}`", f"- source: `{relative(f.path)}`"]
    lines += [f"- {note}" for note in f.notes]
    return lines


def topology(f):
    if not f.topology or f.topology == ["unknown (no nvidia-smi)"]:
        return ["Link topology: not recorded (no nvidia-smi on the machine)."]
    return ["Link topology (`nvidia-smi topo -m` on the machine that ran it):", "", "```"] + f.topology + ["```"]


def table1_pivot(f, precision):
    """The report's layout: one row per N, ms per step per GPU count and exchange, then the report's own."""
    rows = [r for r in f.rows if r["precision"] == precision]
    columns = sorted({(int(r["gpus"]), r["exchange"]) for r in rows},
                     key=lambda c: (c[0], METHOD_ORDER.index(c[1]) if c[1] in METHOD_ORDER else -1))
    names = ["1 GPU" if p == 1 else f"{p} GPUs {METHOD_NAMES.get(e, e)}" for p, e in columns]
    out = [f"ms per step, {precision} (failed: the outcome; the report: 4 x Tesla C2070):", "",
           "| N | " + " | ".join(names) + " | report DT-S | report DT-A | report DA |",
           "|---:|" + "---:|" * (len(columns) + 3)]
    for n in sorted({int(r["n"]) for r in rows}):
        cells = []
        for p, e in columns:
            r = next((r for r in rows if int(r["n"]) == n and int(r["gpus"]) == p and r["exchange"] == e), None)
            cells.append("" if r is None else fmt(number(r["ms_per_step"]), ".3f") if r["outcome"] == "ok" else r["outcome"])
        first = next(r for r in rows if int(r["n"]) == n)
        cells += [fmt(number(first[c]), ".2f") for c in ("report_dts_ms", "report_dta_ms", "report_da_ms")]
        out.append(f"| {n} | " + " | ".join(cells) + " |")
    return out + [""]


def table1_section(f):
    rows = f.rows
    out = [f"### Table 1 on {f.device()}", ""] + provenance(f) + [""]
    for precision in sorted({r["precision"] for r in rows}):
        out += table1_pivot(f, precision)
    # Records from before the phase columns have none: the table leaves them out.
    phases = bool(rows) and "ms_forces" in rows[0]
    out += ["Every configuration" + (" (forces, integrate, collide: where a step's time went on the home GPU's"
                                     " stream, GPU events, mean ms a step):" if phases else ":"), ""]
    out += ["| N | precision | P | exchange | ms / step | speed-up | efficiency | pair interactions / s |"
            " collisions / step |" + (" rounds / step | forces | integrate | collide |" if phases else "") +
            " report ms / step (4 x C2070, same exchange) |",
            "|---:|---|---:|---|---:|---:|---:|---:|---:|" + ("---:|" * 4 if phases else "") + "---:|"]
    for r in rows:
        if r["outcome"] != "ok":
            continue
        report = number(r[REPORT_COLUMN[r["exchange"]]]) if r["exchange"] in REPORT_COLUMN else None
        phase_cells = (f" {fmt(number(r['rounds_per_step']), '.1f')} | {fmt(number(r['ms_forces']), '.3f')} |"
                       f" {fmt(number(r['ms_integrate']), '.3f')} | {fmt(number(r['ms_collide']), '.3f')} |") if phases else ""
        out.append(f"| {r['n']} | {r['precision']} | {r['gpus']} | {METHOD_NAMES.get(r['exchange'], r['exchange'])} |"
                   f" {fmt(number(r['ms_per_step']), '.3f')} | {fmt(number(r['speedup']), '.2f')} |"
                   f" {fmt(number(r['efficiency']), '.2f')} | {fmt(number(r['pair_interactions_per_second']), '.3e')} |"
                   f" {fmt(number(r['collisions_per_step']), '.0f')} |{phase_cells} {fmt(report, '.2f')} |")
    failed = [r for r in rows if r["outcome"] != "ok"]
    if failed:
        out += ["", "Configurations that did not run to the end:", ""]
        out += [f"- N = {r['n']} {r['precision']} P = {r['gpus']} {METHOD_NAMES.get(r['exchange'], r['exchange'])}:"
                f" {r['outcome']}: {r['message']}" for r in failed]
    # The fastest configuration per N and precision: where splitting over GPUs starts to pay.
    best = {}
    for r in rows:
        if r["outcome"] == "ok":
            key = (int(r["n"]), r["precision"])
            if key not in best or number(r["ms_per_step"]) < number(best[key]["ms_per_step"]):
                best[key] = r
    out += ["", "Fastest configuration per N:", "", "| N | precision | P | exchange | ms / step | speed-up over 1 GPU |",
            "|---:|---|---:|---|---:|---:|"]
    for (n, precision), r in sorted(best.items()):
        out.append(f"| {n} | {precision} | {r['gpus']} | {METHOD_NAMES.get(r['exchange'], r['exchange'])} |"
                   f" {fmt(number(r['ms_per_step']), '.3f')} | {fmt(number(r['speedup']), '.2f')} |")
    return out + [""] + topology(f) + [""]


def scaling_section(files):
    """Strong scaling per host: the fastest exchange for each N and P, all of one host's files together."""
    out = []
    for host in sorted({f.gpu_count for f in files}, reverse=True):
        rows = [r for f in files if f.gpu_count == host for r in f.rows if r["outcome"] == "ok"]
        counts = sorted({int(r["gpus"]) for r in rows})
        if len(counts) < 2:
            continue
        sources = ", ".join(f"`{relative(f.path)}`" for f in files if f.gpu_count == host)
        out += [f"### Strong scaling on the {host}-GPU host (fastest exchange per P; from {sources})", "",
                "| N | precision | " + " | ".join(f"P = {p}" for p in counts) + " |",
                "|---:|---|" + "---|" * len(counts)]
        for n, precision in sorted({(int(r["n"]), r["precision"]) for r in rows}):
            cells = []
            for p in counts:
                mine = [r for r in rows if int(r["n"]) == n and r["precision"] == precision and int(r["gpus"]) == p]
                if not mine:
                    cells.append("")
                    continue
                r = min(mine, key=lambda r: number(r["ms_per_step"]))
                cell = f"{number(r['ms_per_step']):.3f} ms"
                if p > 1:
                    cell += (f" {METHOD_NAMES.get(r['exchange'], r['exchange'])},"
                             f" {fmt(number(r['speedup']), '.2f')}x, {fmt(number(r['efficiency']) * 100, '.1f')}%")
                cells.append(cell)
            out.append(f"| {n} | {precision} | " + " | ".join(cells) + " |")
        out.append("")
        # scripts/plot_table1.py draws the largest host as table1.png (shown above) and each other as its own.
        chart = ROOT / "docs" / "images" / f"table1_{host}gpus.png"
        if chart.exists():
            out += [f"![ms per step against N on the {host}-GPU host](images/{chart.name})", ""]
    return out


def p2p_section(f):
    rows = f.rows
    counts = sorted({int(r["gpus"]) for r in rows})
    out = [f"### Figure 5 on {f.device()} ({', '.join(map(str, counts))} GPUs)", ""] + provenance(f) + [""]
    methods = [m for m in METHOD_ORDER if any(r["method"] == m for r in rows)]
    for p in counts:
        mine = [r for r in rows if int(r["gpus"]) == p]
        out += [f"Median transfer time in microseconds (bandwidth received per GPU, GB/s), {p} GPUs:", "",
                "| size per GPU | " + " | ".join(METHOD_NAMES[m] for m in methods) + " |",
                "|---:|" + "---:|" * len(methods)]
        for b in sorted({int(r["bytes"]) for r in mine}):
            cells = []
            for m in methods:
                r = next((r for r in mine if r["method"] == m and int(r["bytes"]) == b), None)
                if r is None or r["outcome"] != "ok":
                    cells.append(r["outcome"] if r else "")
                    continue
                mark = "" if r["verified"] == "yes" else " (not verified)"
                via = " via host" if r["path"] == "host" else ""
                cells.append(f"{number(r['median_s']) * 1e6:.1f} ({number(r['gb_per_s_per_gpu']):.1f}){via}{mark}")
            out.append(f"| {size_label(b)} | " + " | ".join(cells) + " |")
        out.append("")
        notes = {}
        for r in mine:
            if r["outcome"] != "ok":
                notes.setdefault(r["method"], f"{r['outcome']}: {r['message']}")
        out += [f"- {METHOD_NAMES[m]}: {text}" for m, text in notes.items()]
        if notes:
            out.append("")
    return out + topology(f) + [""]


def best_row(f, n, gpus, precision="fp32"):
    """The fastest successful configuration among f.rows at (n, gpus, precision), or None."""
    rows = [r for r in f.rows if int(r["n"]) == n and int(r["gpus"]) == gpus and r["precision"] == precision
            and r["outcome"] == "ok"]
    return min(rows, key=lambda r: number(r["ms_per_step"])) if rows else None


# The multi-GPU targets corebox set itself (fp32, RK4 with collisions, H200s with NVLink), and the
# nbody figure they are set against: NVIDIA's cuda-samples nbody on two H200s at N = 65536 (1.81e12
# against 1.41e12 pair interactions/s on one), measured on the same machine kind.
TARGET_SMALL_MS = 0.1        # N = 1024, ms a step
TARGET_ONE_GPU_MS = 11.0     # N = 65536, one GPU
TARGET_TWO_GPU_MS = 6.0      # N = 65536, two GPUs
TARGET_SPEEDUP = 1.85        # N = 65536, two GPUs over one
TARGET_ONE_GPU_RATE = 2.0e12  # pair interactions/s, one GPU, N >= 65536
TARGET_PER_GPU_RATE = 1.5e12  # pair interactions/s a GPU, two GPUs, N >= 262144
NBODY_TWO_GPU_SPEEDUP = 1.29
PHASES = ("ms_forces", "ms_integrate", "ms_collide")


def value(r, column):
    """A row's cell as a number, None where the column is missing or empty (records made before it)."""
    return number(r.get(column)) if r else None


def targets_section(files):
    """The multi-GPU targets (one and two GPUs, fp32) against the fullest record with two GPUs and phase
    columns, and for the targets missed, where a step's time went (what P GPUs cannot shrink)."""
    two = [f for f in files if f.rows and any(int(r["gpus"]) == 2 for r in f.rows) and all(c in f.rows[0] for c in PHASES)]
    if not two:
        return []
    f = max(two, key=lambda g: (len(g.rows), g.path.name))  # the fullest record (not file times: a clone sets them)
    one_small, one_large, two_large = best_row(f, 1024, 1), best_row(f, 65536, 1), best_row(f, 65536, 2)
    table = []
    missed = 0

    def row(name, shown, ok):
        nonlocal missed
        missed += 0 if ok else 1
        table.append(f"| {name} | {shown} | {'yes' if ok else 'no'} |")

    if one_small:
        ms = value(one_small, "ms_per_step")
        row(f"N = 1024, <= {TARGET_SMALL_MS:g} ms a step", f"{ms:.3f} ms (1 GPU)", ms <= TARGET_SMALL_MS)
    if one_large:
        ms = value(one_large, "ms_per_step")
        row(f"N = 65536, <= {TARGET_ONE_GPU_MS:g} ms a step on 1 GPU", f"{ms:.3f} ms", ms <= TARGET_ONE_GPU_MS)
        rate = value(one_large, "pair_interactions_per_second")
        row(f"1 GPU, N >= 65536, >= {TARGET_ONE_GPU_RATE:.1e} pair interactions/s", f"{rate:.3g} at N = 65536",
            rate >= TARGET_ONE_GPU_RATE)
    if two_large:
        ms = value(two_large, "ms_per_step")
        row(f"N = 65536, <= {TARGET_TWO_GPU_MS:g} ms a step on 2 GPUs", f"{ms:.3f} ms ({METHOD_NAMES[two_large['exchange']]})",
            ms <= TARGET_TWO_GPU_MS)
    speedup = None
    if one_large and two_large:
        speedup = value(one_large, "ms_per_step") / value(two_large, "ms_per_step")
        row(f"N = 65536, >= {TARGET_SPEEDUP:g}x on 2 GPUs", f"{speedup:.2f}x (nbody: {NBODY_TWO_GPU_SPEEDUP:g}x)",
            speedup >= TARGET_SPEEDUP)
    big2 = [r for r in f.rows if int(r["n"]) >= 262144 and int(r["gpus"]) == 2 and r["outcome"] == "ok" and r["precision"] == "fp32"]
    if big2:
        r = max(big2, key=lambda r: value(r, "pair_interactions_per_second"))
        per_gpu = value(r, "pair_interactions_per_second") / 2
        row(f"P = 2, N >= 262144, >= {TARGET_PER_GPU_RATE:.1e} pair interactions/s a GPU", f"{per_gpu:.3g} at N = {r['n']}",
            per_gpu >= TARGET_PER_GPU_RATE)
    count = {1: "one", 2: "two", 3: "three"}.get(missed, str(missed))
    title = "## The targets" + ("" if missed == 0 else f", and what bounds the {count} missed")
    out = [title, "",
           f"From `{relative(f.path)}` (fp32, RK4 with collisions; the fastest exchange where several GPUs; pair"
           " interactions counted as nbody counts them, N^2 a pass).", "", "| target | measured | met |", "|---|---|---|"]
    out += table + [""]
    phases_large = one_large and two_large and all(value(x, c) is not None for x in (one_large, two_large) for c in PHASES)
    if phases_large and speedup < TARGET_SPEEDUP:
        f1, c1 = value(one_large, "ms_forces"), value(one_large, "ms_collide")
        f2, i2, c2 = value(two_large, "ms_forces"), value(two_large, "ms_integrate"), value(two_large, "ms_collide")
        t1 = value(one_large, "ms_per_step")
        ideal = t1 / (t1 - f1 / 2)
        out += [f"Where a step's time went at N = 65536 (GPU events on the home GPU): one GPU {f1:.3f} ms between the"
                f" force events (its whole RK graph, stage updates included) and {c1:.3f} ms in the collision stage;"
                f" two GPUs {f2:.3f} ms between the force events (each GPU's share of the pairs, the wait for the other"
                f" GPU and the adding of their sums; half of one GPU's figure is {f1 / 2:.3f}), {i2:.3f} ms in the rest"
                f" of the integration and {c2:.3f} ms in the collision stage, which runs on the home GPU on the gathered"
                f" state (docs/architecture.md) while the other waits. With the force events' time halved and nothing"
                f" else changed, two GPUs would give about {ideal:.2f}x: "
                + (f"the work kept on one GPU alone holds the speed-up below {TARGET_SPEEDUP:g}x." if ideal < TARGET_SPEEDUP else
                   "what stays on one GPU leaves no room for the rest.")
                + " Profiled on one H200 (ncu, one kernel at a time), the largest part of that stage at this N is the"
                " end-of-step accelerations of the particles about to be resolved, a pass over all N for each of a"
                " round's new rows, bound by its pair arithmetic (kernels/force_kernels.cu: rowBlocksKernel); much of"
                " the rest is the cell list's radix sort, rebuilt each round. Closing the gap needs that stage split"
                " between the GPUs with the one-GPU result kept (each GPU resolving the events of its own slice,"
                " events matched across slices), not a faster exchange.", ""]
    if one_small and value(one_small, "ms_per_step") > TARGET_SMALL_MS and all(value(one_small, c) is not None for c in PHASES):
        rounds = value(one_small, "rounds_per_step")
        out += [f"At N = 1024 a step is {value(one_small, 'ms_per_step'):.3f} ms: {value(one_small, 'ms_forces'):.3f}"
                f" in the RK step (one CUDA graph of four force passes and stage updates) and"
                f" {value(one_small, 'ms_collide'):.3f} in the collision stage"
                + (f" ({rounds:.1f} impact rounds a step)" if rounds is not None else "") +
                ". That stage is a chain of kernels of a few microseconds each (opening, per round a cell list, a"
                " search, the new rows' accelerations and the resolution, then the contact count, step check and"
                " tally), run back to back with one host wait: bounded by how many small launches it makes, not by"
                " arithmetic. Its rounds fused into one launch of one block saved little and did not keep the"
                " separate kernels' bits (src/cuda/cuda_collisions.cpp); the whole stage captured with the RK step in"
                " one graph, with fewer, fused launches whose results are checked bit for bit against the separate"
                " kernels, is what is left to try.", ""]
    return out


def p2p_figures(files):
    """The sentence that puts numbers on the paragraph above: each method's time at 1 MiB and 1 GiB on two GPUs."""
    two = [f for f in files if any(int(r["gpus"]) == 2 for r in f.rows)]
    if not two:
        return []
    f = two[0]
    parts = []
    for size in (1 << 20, 1 << 30):
        cells = []
        for m in METHOD_ORDER:
            r = [r for r in f.rows if r["method"] == m and int(r["bytes"]) == size and int(r["gpus"]) == 2 and r["outcome"] == "ok"]
            if r:
                seconds = number(r[0]["median_s"])
                cells.append(f"{METHOD_NAMES[m]} {seconds * 1e6:.0f} us" if size < (1 << 30) else
                             f"{METHOD_NAMES[m]} {seconds * 1e3:.2f} ms ({number(r[0]['gb_per_s_per_gpu']):.0f} GB/s a GPU)")
        if cells:
            parts.append(f"{size_label(size)}: " + ", ".join(cells))
    if not parts:
        return []
    at = {m: [r for r in f.rows if r["method"] == m and int(r["bytes"]) == 1 << 30 and int(r["gpus"]) == 2 and r["outcome"] == "ok"]
          for m in ("dts", "dta")}
    ratio = (f" ({value(at['dts'][0], 'median_s') / value(at['dta'][0], 'median_s'):.2f} times DT-A's time)"
             if at["dts"] and at["dta"] else "")
    return [f"On two GPUs (`{relative(f.path)}`), each GPU fetching its neighbour's buffer: " + "; ".join(parts) + "."
            f" DT-S at 1 GiB is the slowest{ratio}, as its copies run one after another; NCCL's all-gather stays"
            " below DT-A's rate at this size (its transfers go through the channels NCCL sets up rather than"
            " straight from the copy engines, our reading, not profiled).", ""]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", nargs="*", type=pathlib.Path)
    parser.add_argument("--out", type=pathlib.Path, default=ROOT / "docs" / "multi_gpu.md")
    args = parser.parse_args()
    paths = args.results or sorted(RESULTS.glob("table1*.csv")) + sorted(RESULTS.glob("p2p*.csv"))
    files = [BenchCsv(p) for p in paths]
    table1 = [f for f in files if f.rows and "exchange" in f.rows[0]]
    p2p = [f for f in files if f.rows and "bytes" in f.rows[0]]
    if not table1 and not p2p:
        print("no table1 or p2p results; run `corebox bench table1 --out docs/results/table1_NAME` first",
              file=sys.stderr)
        return 1
    text = [
        "# Several GPUs: the report's Table 1 and Figure 5 measured here",
        "",
        f"Generated by `scripts/make_multi_gpu_doc.py` from {', '.join(f'`{relative(f.path)}`' for f in files)};"
        " do not edit by hand. Each result file records the GPUs, driver, link topology and the exact command,"
        " so every number below can be reproduced.",
        "",
        "Reproduce (on a machine with two or more GPUs; build with `cmake --preset release && cmake --build build`):",
        "",
        "```sh",
        *[f.command.replace("corebox ", "build/corebox ", 1) for f in files],
        "scripts/plot_table1.py && scripts/plot_p2p.py && scripts/make_multi_gpu_doc.py",
        "```",
        "",
    ]
    if table1:
        text += ["## Table 1: ms per RK4 step, one GPU and several", "",
                 "The report's model at a fixed density (it does not state which; we use number density 0.5, see each"
                 " file's notes), RK4 with hard-core collisions, every exchange method. Speed-up and efficiency are"
                 " against one GPU at the same N and precision; the report's column is its own Table 1 (four Tesla"
                 " C2070, 2012) for the same N and method.", "",
                 "![ms per step against N](images/table1.png)", "", "(`scripts/plot_table1.py`)", "",
                 "For comparison (DESIGN.md sec. 6, measured on the same machine kind): NVIDIA's cuda-samples nbody"
                 " (gravity, fp32, no collisions) gains 1.29x from two H200s and 1.27x from four at N = 65536. Here the"
                 " force passes split evenly and only O(N) work stays on one GPU (the collision stage on the gathered"
                 " state, the exchanges), so the speed-up at that N is set by how that fixed part compares with N^2 / P:"
                 " see the speed-up column; at small N that part is all there is, and one GPU is fastest"
                 " (`--gpus auto` follows this table).", "",
                 "Which force pass the records ran: `table1_h200x1*` and `table1_h200x2*` evaluate each pair once"
                 " (Newton's third law) on one GPU and, where the tile pairs fill every GPU, on several sharing one"
                 " pass (kernels/pairs_once_kernels.cu); `table1_h200x4*` and `table1_h200x8*` were measured before"
                 " that, when every GPU, one GPU too, evaluated every ordered pair of its rows, so their one-GPU"
                 " column is slower and their speed-ups larger. `table1_h200x1*` and `table1_h200x2*` also run the"
                 " collision stage's rounds queued on the device with one wait a step and, on one GPU, the RK step as"
                 " one CUDA graph (src/cuda/cuda_rk_graph.cpp), whose force events then bracket the stage updates too"
                 " (ms_forces includes them, ms_integrate is what is left); at N = 1024 that took a step from 0.34 to"
                 " 0.14 ms. Records with phase columns say where a step's time"
                 " went (forces, the rest of the integration, the collision stage on the home GPU): what stays on one"
                 " GPU bounds the speed-up.", ""]
        text += targets_section(table1)
        text += scaling_section(table1)
        for f in table1:
            text += table1_section(f)
    if p2p:
        text += ["## Figure 5: moving a buffer between GPUs", "",
                 "Every GPU fetches its neighbour's buffer at the same time: DT-S (`cudaMemcpyPeer`), DT-A"
                 " (`cudaMemcpyPeerAsync`), DA (a kernel reading the peer's memory over unified addressing) and an"
                 " NCCL all-gather.", "", "![transfer time against size](images/p2p.png)", "", "(`scripts/plot_p2p.py`)",
                 "",
                 "Why the methods differ here, unlike in the report (read against the tables below): at small sizes"
                 " each method pays its fixed cost (DA one kernel launch, DT-A an asynchronous copy and an event,"
                 " DT-S a blocking call per copy, NCCL its protocol set-up per collective); at large sizes DT-S issues"
                 " its copies one after another, so the links carry one direction at a time and it reaches about half"
                 " the bandwidth of DT-A, whose copies run together in both directions near the NVLink rate; DA is"
                 " bounded by how fast the SMs of the receiving GPU can issue remote loads; NCCL moves the data through"
                 " its own pipelined channels. On the report's C2070s over PCIe the link itself was the limit for every"
                 " method, so the curves lay together.", ""]
        text += p2p_figures(p2p)
        for f in p2p:
            text += p2p_section(f)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text("\n".join(text).rstrip() + "\n")
    print(f"wrote {relative(args.out)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""Reads the CSV files of `corebox bench p2p` and `corebox bench table1` (src/bench/gpu_records.h).

Such a file starts with comment lines ("# ..."): the command that made it, notes on what was measured
and how it was timed, the GPUs CUDA saw, the driver and the output of `nvidia-smi topo -m`; then the
header row and one row per measurement. The plotting and document scripts read everything they show
from these files, so no figure is typed by hand.
"""
import csv
import io
import pathlib


class BenchCsv:
    def __init__(self, path):
        self.path = pathlib.Path(path)
        comments, body = [], []
        for line in self.path.read_text().splitlines():
            if line.startswith("#") and not body:
                comments.append(line[2:] if line.startswith("# ") else line[1:])
            else:
                body.append(line)
        self.rows = list(csv.DictReader(io.StringIO("\n".join(body))))
        self.command = comments[0] if comments else ""
        self.notes, self.gpus, self.topology = [], [], []
        self.driver = "unknown"
        self.gpu_count = 0
        part = "notes"
        for line in comments[1:]:
            if part == "topology":
                self.topology.append(line)
            elif line.startswith("gpus visible to CUDA:"):
                self.gpu_count = int(line.split(":", 1)[1])
                part = "gpus"
            elif part == "gpus" and line.startswith("  GPU "):
                self.gpus.append(line.strip())
            elif line.startswith("driver:"):
                self.driver = line.split(":", 1)[1].strip()
            elif line == "topology (nvidia-smi topo -m):":
                part = "topology"
            elif line.startswith("topology:"):  # "topology: unknown (no nvidia-smi)"
                self.topology = [line.split(":", 1)[1].strip()]
                part = "done"
            elif part == "notes":
                self.notes.append(line)

    def device(self):
        """The first GPU's description without its "GPU 0: " label, for titles."""
        return self.gpus[0].split(": ", 1)[1] if self.gpus else "unknown GPU"

    def hardware_line(self):
        return f"{self.gpu_count} GPUs visible, GPU 0: {self.device()}; driver {self.driver}"


def number(text):
    """A CSV cell as a float, or None where it is empty (a failed configuration, a size the report lacks)."""
    return float(text) if text not in ("", None) else None

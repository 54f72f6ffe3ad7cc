"""What the plot scripts of `accelbench reproduce` share (plot_woo92.py,
plot_havran.py): a paper's figures file, the measured images of a table
(rows of one table, variant and scene summed over workloads, as the printed
tables sum them) and the figures' footer. The CSV reader, number parsing,
errors and saving are plot.py's."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot as common  # noqa: E402

num = common.num
DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "data")

# The columns every reproduce CSV has and these helpers read.
REQUIRED = ("table", "variant", "grid_res", "scene", "workload", "rays", "trace_ms",
            "trace_ms_min", "trace_ms_max", "tests_per_ray", "box_tests_per_ray", "mem_bytes")


def figure_value(text):
    """A figure as printed: 'm:ss' (or 'h:mm:ss') as seconds, else a float."""
    value = 0.0
    for part in text.split(":"):
        value = 60 * value + float(part)
    return value


def load_figures(paper):
    """{table: {row: {quantity: value}}} from data/PAPER_figures.csv, rows in file order."""
    rows = common.load_rows(os.path.join(DATA, f"{paper}_figures.csv"), ("table", "row", "quantity", "value"))
    figs = {}
    for r in rows:
        figs.setdefault(r["table"], {}).setdefault(r["row"], {})[r["quantity"]] = r["value"]
    return figs


class Image:
    """One measured image: the rows of one (table, variant, scene), summed over workloads."""

    def __init__(self, rows):
        self.rows = rows
        self.scene = rows[0]["scene"]
        self.grid = rows[0]["grid_res"]
        self.ms = sum(num(r["trace_ms"]) or 0 for r in rows)
        self.ms_min = sum(num(r["trace_ms_min"]) or 0 for r in rows)
        self.ms_max = sum(num(r["trace_ms_max"]) or 0 for r in rows)
        self.embree_ms = sum(num(r.get("embree_ms")) or 0 for r in rows)
        # time over the Embree samples interleaved with it: ratios of these are stable on a shared machine
        self.vs_embree = self.ms / self.embree_ms if self.embree_ms else None
        rays = sum(num(r["rays"]) or 0 for r in rows)
        self.rays = rays
        self.tests = self.per_ray("tests_per_ray")
        self.boxes = self.per_ray("box_tests_per_ray")
        self.mem = num(rows[0]["mem_bytes"]) or 0

    def per_ray(self, column):
        """A per-ray counter over all the image's rays (each set weighted by its rays)."""
        if not self.rays:
            return 0
        return sum((num(r.get(column)) or 0) * (num(r["rays"]) or 0) for r in self.rows) / self.rays

    def err(self):
        """Lower/upper error bar lengths from the min-max of the repeats."""
        return max(0.0, self.ms - self.ms_min), max(0.0, self.ms_max - self.ms)


def images(rows, table):
    """{(variant, scene): Image} for one table, in first-seen order."""
    groups = {}
    for r in rows:
        if r["table"] == table:
            groups.setdefault((r["variant"], r["scene"]), []).append(r)
    return {k: Image(v) for k, v in groups.items()}


def footer(fig, rows):
    """Small footer with machine/cpu, threads, repeats and git revision."""
    def uniq(col):
        return common.column_values(rows, col)
    fig.text(0.01, 0.005, f"machine: {uniq('machine')} | cpu: {uniq('cpu')} | timed threads: {uniq('threads')} | "
             f"repeat: {uniq('repeat')} | git: {uniq('git_rev')}", fontsize=7, color="0.35", ha="left", va="bottom")

"""Draws the work-precision charts from bench_work_precision's CSV: one panel per problem,
error against CPU time, log-log, one line per integrator.

    build/bench/bench_work_precision > work_precision.csv
    python bench/plot_work_precision.py work_precision.csv docs/work_precision.png
"""

import csv
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

TITLES = {
    "top": "torque-free top",
    "separatrix": "top near the separatrix",
    "spring": "spring",
    "drag": "projectile with linear drag",
    "chain": "chain of three boxes on springs",
}
STYLE = {"euler": "o-", "midpoint": "s-", "rk4": "^-", "cvode-adams": "D-", "cvode-bdf": "v-",
         "rosenbrock": "P-", "ark-imex": "X-"}


def main(source, target):
    rows = list(csv.DictReader(open(source)))
    problems = list(dict.fromkeys(r["problem"] for r in rows))
    fig, axes = plt.subplots(1, len(problems), figsize=(4.2 * len(problems), 4.2))
    for axis, problem in zip(axes, problems):
        lines = defaultdict(list)
        quantity = ""
        for r in rows:
            if r["problem"] == problem and float(r["error"]) < 1e9:
                lines[r["method"]].append((float(r["cpu_us"]) / 1e3, float(r["error"])))
                quantity = r["quantity"]
        for method, points in lines.items():
            points.sort()
            axis.loglog([p[0] for p in points], [p[1] for p in points], STYLE.get(method, "x-"),
                        label=method, markersize=4)
        axis.set_title(TITLES.get(problem, problem))
        axis.set_xlabel("CPU time (ms)")
        axis.set_ylabel(f"largest error, {quantity}")
        axis.grid(True, which="major", alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(target, dpi=90)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])

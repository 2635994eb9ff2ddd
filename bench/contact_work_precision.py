"""The contact work-precision chart: `tumble accuracy` on contact scenes, error against CPU time
for every method of the sweep (the explicit fixed steps at 1, 2 and 4 times their default
step's rate, rosenbrock at 1/240 and 1/1000 s, CVODE Adams, BDF and ark-imex at rtol 1e-3 to
1e-9), one panel per scene. Rows the sweep lists as failed (a step budget used up) are left out
of the panels and kept in the CSV with their reason.

    python bench/contact_work_precision.py build/cli/tumble docs/contact_work_precision.csv \
        docs/contact_work_precision.png

Each scene's table is `tumble accuracy`'s own: the error is the largest displacement of a body's
points at its radius of gyration over the frames compared (up to the horizon on chaotic scenes),
against the sweep's reference, and the CPU time is that of one run (not a median: compare
ratios within a panel).
"""

import csv
import re
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

# (scene file, its duration in the sweep, the panel's title)
SCENES = [
    ("head_on_pairs", None, "head-on pairs (e = 0.8), 0.25 s"),
    ("bowl", None, "marbles in a bowl, 1.5 s"),
    ("stack", 0.25, "stack of boxes, first 0.25 s"),
    ("dice", 0.5, "12 dice, first 0.5 s (to the horizon)"),
]
STYLE = {"euler": "o-", "midpoint": "s-", "rk4": "^-", "cvode-adams": "D-", "cvode-bdf": "v-",
         "rosenbrock": "P-", "ark-imex": "X-"}
ROW = re.compile(r"^(euler|midpoint|rk4|cvode-adams|cvode-bdf|ark-imex|rosenbrock)\s+"
                 r"(dt \S+|rtol \S+)\s+(.*)$")


def sweep(tumble, scene, duration):
    """Runs tumble accuracy on one example scene and returns its rows and the footer."""
    command = [tumble, "accuracy", f"examples/scenes/{scene}.json"]
    if duration is not None:
        command += ["--duration", str(duration)]
    result = subprocess.run(command, capture_output=True, text=True, check=False)
    if result.returncode != 0:
        sys.exit(f"contact_work_precision: {' '.join(command)} failed ({result.returncode}): "
                 f"{result.stderr.strip().splitlines()[-1:]}")
    rows, footer = [], []
    for line in result.stdout.splitlines():
        match = ROW.match(line)
        if match is None:
            if line.startswith(("reference", "horizon", "cheapest", "the cvode-bdf")):
                footer.append(line)
            continue
        method, setting, rest = match.groups()
        fields = rest.split()
        if rest.startswith("failed") or rest.startswith("refused"):
            rows.append(dict(scene=scene, method=method, setting=setting, error_m="",
                             cpu_ms="", derivatives="", outcome=rest))
        else:
            rows.append(dict(scene=scene, method=method, setting=setting, error_m=fields[0],
                             cpu_ms=fields[3], derivatives=fields[4], outcome="ok"))
    return rows, footer


def draw(rows, target):
    fig, axes = plt.subplots(1, len(SCENES), figsize=(4.4 * len(SCENES), 4.4))
    for axis, (scene, _, title) in zip(axes, SCENES):
        for method, style in STYLE.items():
            points = sorted((float(r["cpu_ms"]), float(r["error_m"])) for r in rows
                            if r["scene"] == scene and r["method"] == method
                            and r["outcome"] == "ok")
            if points:
                axis.loglog([p[0] for p in points], [p[1] for p in points], style,
                            label=method, markersize=4)
        axis.set_title(title, fontsize=10)
        axis.set_xlabel("CPU time (ms)")
        axis.set_ylabel("largest error, m")
        axis.grid(True, which="major", alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(target, dpi=90)


def main(tumble, table, chart):
    rows = []
    for scene, duration, _ in SCENES:
        found, footer = sweep(tumble, scene, duration)
        rows += found
        print(f"{scene}: {len(found)} rows; " + " | ".join(footer), file=sys.stderr)
    with open(table, "w", newline="") as out:
        writer = csv.DictWriter(out, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    draw(rows, chart)


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit("usage: contact_work_precision.py TUMBLE OUT.csv OUT.png")
    main(*sys.argv[1:])

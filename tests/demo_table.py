"""The demo's table in the docs is what the demo prints today, apart from the times.

    python3 demo_table.py TUMBLE_DEMO docs/integrators.md [--write]

Runs the demo and compares each row of its table (integrator, setting, steps, derivative
evaluations, flips, energy drift, L drift, orientation error) with the document's, word for
word; only the last column, the wall time of one run, may differ. Exits 1 naming the first row
that differs. --write puts the demo's table into the document instead, each time the median of
5 runs."""

import subprocess
import sys

METHODS = ("euler", "midpoint", "rk4", "cvode-adams", "cvode-bdf")


def table(text):
    """The rows of the demo's table in text, each as its words without the time column."""
    lines = [line.split() for line in text.splitlines()]
    return [words[:-1] for words in lines if words and words[0] in METHODS]


def write(document, text, outputs):
    """Replaces the document's table block (header and rows) with the demo's, each row's time the
    median of the runs' (the machine is shared: one run's times are noise)."""
    runs = [[line.rstrip() for line in output.splitlines() if line.startswith("integrator ") or
             (line.split() or [""])[0] in METHODS] for output in outputs]
    rows = []
    for lines in zip(*runs):
        row = lines[0]
        if row.split()[0] in METHODS:
            times = sorted(float(line.split()[-1]) for line in lines)
            median = f"{times[len(times) // 2]:.2f}"
            kept = row[:row.rfind(" ")].rstrip()
            row = kept + median.rjust(len(row) - len(kept))
        rows.append(row)
    lines = text.splitlines(keepends=True)
    first = next(i for i, line in enumerate(lines) if line.startswith("integrator   setting"))
    last = first + 1
    while last < len(lines) and (lines[last].split() or [""])[0] in METHODS:
        last += 1
    with open(document, "w", encoding="utf-8") as f:
        f.write("".join(lines[:first]) + "".join(row + "\n" for row in rows) +
                "".join(lines[last:]))


def main():
    demo, document = sys.argv[1:3]
    output = subprocess.run([demo], check=True, capture_output=True, text=True).stdout
    printed = table(output)
    with open(document, encoding="utf-8") as f:
        text = f.read()
    if sys.argv[3:] == ["--write"]:
        more = [subprocess.run([demo], check=True, capture_output=True, text=True).stdout
                for _ in range(4)]
        write(document, text, [output] + more)
        return 0
    documented = table(text)
    if not printed:
        print("the demo printed no table", file=sys.stderr)
        return 1
    for number, (mine, theirs) in enumerate(zip(documented, printed), start=1):
        if mine != theirs:
            print(f"{document} row {number}: {' '.join(mine)}\n   demo prints: {' '.join(theirs)}",
                  file=sys.stderr)
            return 1
    if len(documented) != len(printed):
        print(f"{document} has {len(documented)} rows, the demo prints {len(printed)}",
              file=sys.stderr)
        return 1
    print(f"{len(printed)} rows agree")
    return 0


if __name__ == "__main__":
    sys.exit(main())

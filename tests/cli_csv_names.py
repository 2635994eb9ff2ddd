"""Body names with a comma, a quote and a line break come back intact through the CSV.

    python3 cli_csv_names.py TUMBLE SCENE.json OUT.csv

Runs `tumble run` and reads its output with Python's csv module (RFC 4180): one row per body
per frame, every row 15 fields, and the body column holding exactly the scene file's names, in
order, frame after frame. A writer that does not quote forges extra fields and rows."""

import csv
import json
import subprocess
import sys

tumble, scene, out = sys.argv[1:4]
subprocess.run([tumble, "run", scene, "--out", out], check=True)
with open(scene) as f:
    description = json.load(f)
names = [body["name"] for body in description["bodies"]]
frames = round(description["output"]["duration"] * description["output"]["fps"]) + 1
with open(out, newline="") as f:
    rows = list(csv.reader(f))
header, body_rows = rows[0], rows[1:]
assert header[:2] == ["t", "body"] and len(header) == 15, header
assert len(body_rows) == frames * len(names), f"{len(body_rows)} rows for {frames} frames"
assert all(len(row) == 15 for row in body_rows), [row for row in body_rows if len(row) != 15]
assert [row[1] for row in body_rows] == names * frames, [row[1] for row in body_rows[:8]]
print(f"{len(body_rows)} rows, names intact: {names}")

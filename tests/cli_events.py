"""tumble run --events: the contact events file against free fall, in CSV and JSON.

    python3 cli_events.py TUMBLE SCENE.json WORKDIR

SCENE is tests/scenes/bouncing_ball.json: a ball (r = 5 cm) dropped with its lowest point
h = 0.25 m above the ground. Its first hit is at sqrt(2 h / g) = 0.22576 s at sqrt(2 g h) =
2.2147 m/s: RK4 integrates the fall exactly and the fixed-step locator carries the free cubic
to its zero, so both to 1e-9 (tests/test_contact_events_api.c measures 1e-14). Begin and end
alternate, hits follow their begins; the CSV and the JSON hold the same events; an extension
other than .csv or .json is refused (exit 2, no file); a failed write (a .csv that is
/dev/full) is exit 1 with a message, never a silent 0; a .glb output carries the same events
as scenes[0].extras.tumble_events."""

import csv
import json
import math
import os
import struct
import subprocess
import sys

tumble, scene, work = sys.argv[1:4]
os.makedirs(work, exist_ok=True)
paths = {ext: os.path.join(work, "events." + ext) for ext in ("csv", "json")}
for path in paths.values():
    subprocess.run([tumble, "run", scene, "--out", os.devnull, "--events", path], check=True)

with open(paths["csv"], newline="") as f:
    rows = list(csv.reader(f))
header = "t,kind,body_a,body_b,x,y,z,nx,ny,nz,speed,impulse".split(",")
assert rows[0] == header, rows[0]
events = [dict(zip(header, row)) for row in rows[1:]]
with open(paths["json"]) as f:
    objects = json.load(f)
assert len(objects) == len(events), (len(objects), len(events))
for e, o in zip(events, objects):
    assert float(e["t"]) == o["t"] and e["kind"] == o["kind"] and e["body_b"] == o["body_b"]
    assert float(e["impulse"]) == o["impulse"] and [float(e[k]) for k in "xyz"] == o["point"]

g, h = 9.81, 0.25
hit = next(e for e in events if e["kind"] == "hit")
assert hit["body_a"] == "ball" and hit["body_b"] == "ground", hit
assert abs(float(hit["t"]) - math.sqrt(2 * h / g)) < 1e-9, hit["t"]
assert abs(float(hit["speed"]) - math.sqrt(2 * g * h)) < 1e-9, hit["speed"]
assert [float(hit[k]) for k in ("nx", "ny", "nz")] == [0.0, 0.0, -1.0], hit
touching = False
for k, e in enumerate(events):
    assert k == 0 or float(e["t"]) >= float(events[k - 1]["t"])
    if e["kind"] == "hit":
        assert events[k - 1]["kind"] == "begin"
        continue
    assert touching == (e["kind"] == "end"), (k, e)
    touching = not touching
    assert e["kind"] == "begin" or float(e["impulse"]) > 0

# the glb carries the same events in its scene's extras, for a sound designer's script
glb = os.path.join(work, "events.glb")
subprocess.run([tumble, "run", scene, "--out", glb, "--events", paths["csv"]], check=True)
with open(glb, "rb") as f:
    data = f.read()
length = struct.unpack("<I", data[12:16])[0]
extras = json.loads(data[20 : 20 + length])["scenes"][0]["extras"]["tumble_events"]
assert extras == objects, (extras[:2], objects[:2])

bad = os.path.join(work, "events.txt")
run = subprocess.run([tumble, "run", scene, "--out", os.devnull, "--events", bad],
                     capture_output=True, text=True)
assert run.returncode == 2 and "must end in .csv or .json" in run.stderr, run
assert not os.path.exists(bad)

full = os.path.join(work, "full.csv")
if os.path.exists("/dev/full"):
    if os.path.lexists(full):
        os.remove(full)
    os.symlink("/dev/full", full)
    run = subprocess.run([tumble, "run", scene, "--out", os.devnull, "--events", full],
                         capture_output=True, text=True)
    assert run.returncode == 1 and "full.csv" in run.stderr, run
    # an unfinished regular file is removed, never a device (the test may run as root)
    assert os.path.exists("/dev/full") and os.path.lexists(full)
    os.remove(full)
print(f"{len(events)} events; first hit at {hit['t']} s, {hit['speed']} m/s")

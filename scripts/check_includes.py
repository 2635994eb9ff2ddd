#!/usr/bin/env python3
"""Checks that includes point down the layers (DESIGN.md, "Layout"): each folder of src/ may
include its own headers, the public ones (tumble/) and those of the folders below it, never one
above; and that src/scene/ names no effect kind and no constraint (the scene holds effect and
constraint rows by pointer and includes neither effects/, contact/ nor constraints/, so adding a
kind or a joint type never touches it).

    scripts/check_includes.py [SRC_FOLDER]

Prints every include that points up and every kind named in src/scene/ (code only, comments
and strings blanked), and exits 1 if there is one.
"""
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_sizes import blank_comments_and_literals  # noqa: E402

# The folders each folder may include besides its own and tumble/; a folder not listed (io,
# export: the top) may include any.
BELOW = {
    "core": set(),
    "math": {"core"},
    "mass": {"core", "math"},
    "ode": {"core", "math"},
    "scene": {"ode", "mass", "core", "math"},
    "contact": {"scene", "ode", "mass", "core", "math"},
    "constraints": {"contact", "scene", "ode", "mass", "core", "math"},
    "effects": {"constraints", "contact", "scene", "ode", "mass", "core", "math"},
}

# What only an effect kind's own files say: its parameter types and its functions.
KIND = re.compile(
    r"\btb__(?:\w+_params|(?:gravity|load|drag|spring|ground|contact|friction|user)_\w+)\b"
)

# What only src/constraints/ says: the joints' types and functions.
CONSTRAINT = re.compile(r"\btb_{1,2}(?:joint|joints|block_update)\w*\b|\bTB_(?:_)?JOINT\w*\b")

INCLUDE = re.compile(r'^\s*#\s*include\s+"([a-z_]+)/', re.M)


def sources(root):
    for folder, _, names in sorted(os.walk(root)):
        for name in sorted(names):
            if name.endswith((".c", ".h")):
                yield os.path.join(folder, name)


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else "src"
    problems = []
    checked = 0
    for path in sources(root):
        layer = os.path.relpath(path, root).split(os.sep)[0]
        with open(path, encoding="utf-8") as source:
            text = source.read()
        checked += 1
        allowed = BELOW.get(layer)
        for match in INCLUDE.finditer(text):
            target = match.group(1)
            if allowed is not None and target not in allowed | {layer, "tumble"}:
                line = text.count("\n", 0, match.start()) + 1
                problems.append(f"{path}:{line}: {layer}/ includes {target}/, a layer above it")
        if layer == "scene":
            code = blank_comments_and_literals(text)
            for match in KIND.finditer(code):
                line = code.count("\n", 0, match.start()) + 1
                problems.append(f"{path}:{line}: scene/ names an effect kind: {match.group(0)}")
            for match in CONSTRAINT.finditer(code):
                line = code.count("\n", 0, match.start()) + 1
                problems.append(f"{path}:{line}: scene/ names a constraint: {match.group(0)}")
    for message in problems:
        print(message, file=sys.stderr)
    if checked == 0:
        print("check_includes: no source found (wrong folder?)", file=sys.stderr)
        return 1
    print(f"check_includes: {checked} files, {len(problems)} includes or names out of place")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""Checks the house rule on sizes: no function over 60 lines and no file over 600 lines in the
given folders (default src, cli, include), C sources and headers.

A function is measured from the first line of its definition (return type and name) to its
closing brace, both included. Functions are found by a scan of the text with comments, string
and character literals blanked out: a brace opened at file level (outside any other brace)
after a closing parenthesis, in a declaration that is not a struct, union, enum or initialiser,
starts a function body. The code is clang-formatted, so this scan sees what a reader sees.

    scripts/check_sizes.py [--max-function N] [--max-file N] [FOLDER_OR_FILE...]

Prints every function and file over its limit and exits 1 if there is one; --list prints the
longest functions as well.
"""
import argparse
import os
import re
import sys


def blank_comments_and_literals(text):
    """The text with comments and the contents of string and character literals replaced by
    spaces (newlines kept, so line numbers stay), and preprocessor lines blanked."""
    out = []
    i, n = 0, len(text)
    at_line_start = True
    while i < n:
        c = text[i]
        if at_line_start and c == "#":
            # a preprocessor line, with its continuations
            while i < n and text[i] != "\n":
                if text[i] == "\\" and i + 1 < n and text[i + 1] == "\n":
                    out.append(" \n")
                    i += 2
                    continue
                out.append(" ")
                i += 1
            continue
        if c == "/" and i + 1 < n and text[i + 1] == "*":
            end = text.find("*/", i + 2)
            end = n if end < 0 else end + 2
            out.append(re.sub(r"[^\n]", " ", text[i:end]))
            i = end
            continue
        if c == "/" and i + 1 < n and text[i + 1] == "/":
            end = text.find("\n", i)
            end = n if end < 0 else end
            out.append(" " * (end - i))
            i = end
            continue
        if c in "\"'":
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            j = min(j + 1, n)
            out.append(c + " " * (j - i - 2) + c if j - i >= 2 else text[i:j])
            i = j
            at_line_start = False
            continue
        out.append(c)
        if c == "\n":
            at_line_start = True
        elif not c.isspace():
            at_line_start = False
        i += 1
    return "".join(out)


def functions(text):
    """(name, first line, last line) of every function definition in the C text."""
    clean = blank_comments_and_literals(text)
    found = []
    depth = 0
    declaration_start = 0  # index where the current file-level declaration began
    body_start = None
    line_of = [0] * (len(clean) + 1)
    line = 1
    for index, c in enumerate(clean):
        line_of[index] = line
        if c == "\n":
            line += 1
    line_of[len(clean)] = line
    for index, c in enumerate(clean):
        if c == "{":
            if depth == 0:
                head = clean[declaration_start:index]
                words = head.split()
                is_function = (
                    head.rstrip().endswith(")")
                    and "=" not in head
                    and not any(w in ("struct", "union", "enum") for w in words[:3])
                )
                body_start = declaration_start if is_function else None
            depth += 1
        elif c == "}":
            depth -= 1
            if depth == 0:
                if body_start is not None:
                    head = clean[body_start:index]
                    match = re.search(r"([A-Za-z_]\w*)\s*\(", head)
                    name = match.group(1) if match else "?"
                    first = body_start
                    while first < index and clean[first].isspace():
                        first += 1
                    found.append((name, line_of[first], line_of[index]))
                body_start = None
                declaration_start = index + 1
        elif c == ";" and depth == 0:
            declaration_start = index + 1
    return found


def sources(paths):
    for path in paths:
        if os.path.isfile(path):
            yield path
            continue
        for folder, _, names in sorted(os.walk(path)):
            for name in sorted(names):
                if name.endswith((".c", ".h")):
                    yield os.path.join(folder, name)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--max-function", type=int, default=60)
    parser.add_argument("--max-file", type=int, default=600)
    parser.add_argument("--list", type=int, default=0, help="print the N longest functions")
    parser.add_argument("paths", nargs="*", default=["src", "cli", "include"])
    args = parser.parse_args()
    over = []
    everything = []
    for path in sources(args.paths):
        with open(path, encoding="utf-8") as source:
            text = source.read()
        lines = text.count("\n") + (0 if text.endswith("\n") or not text else 1)
        if lines > args.max_file:
            over.append(f"{path}: {lines} lines (at most {args.max_file} a file)")
        for name, first, last in functions(text):
            length = last - first + 1
            everything.append((length, f"{path}:{first}: {name}"))
            if length > args.max_function:
                over.append(
                    f"{path}:{first}: {name}: {length} lines (at most {args.max_function} a "
                    "function)"
                )
    for length, where in sorted(everything, reverse=True)[: args.list]:
        print(f"{length:4d} {where}")
    for message in over:
        print(message, file=sys.stderr)
    if not everything:
        print("check_sizes: no function found (wrong folder?)", file=sys.stderr)
        return 1
    print(f"check_sizes: {len(everything)} functions, {len(over)} over the limits")
    return 1 if over else 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""Puts a script's table into a document: replaces what lies between the markers
<!-- NAME: begin --> and <!-- NAME: end --> of FILE by the table in TABLE, headed by a
note naming `scripts/NAME.sh --write` and VERSION (the program and commit that made it).
So the tables the docs show are the scripts' output, not copies.

    write_between_markers.py NAME FILE TABLE VERSION

Used by scripts/abundance_counts.sh and scripts/thesis_counts.sh.
"""
import sys

name, path, table_path, version = sys.argv[1:5]
table = open(table_path).read()
text = open(path).read()
begin, end = f"<!-- {name}: begin -->", f"<!-- {name}: end -->"
if begin not in text or end not in text:
    sys.exit(f"{path} has no {name} markers")
head, rest = text.split(begin, 1)
_, tail = rest.split(end, 1)
note = f"Written by `scripts/{name}.sh --write` with {version}.\n\n"
open(path, "w").write(head + begin + "\n" + note + table + end + tail)

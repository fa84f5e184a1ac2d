#!/usr/bin/env python3
"""The rooms' one-way include order (docs/architecture.md, "Dependencies"): a file of a room may
include headers of its own room and of rooms before it, never of a room after it. Each room but
main is a static library of CMakeLists.txt (GIMP_ROOMS, in the same order), linked only to the
rooms before it, so a call against the order fails the link and an include against it fails here.
Exits 1 naming every include against the order, and when GIMP_ROOMS differs from ORDER.

Usage: tools/check_rooms.py [repo root]; run at every build (CMakeLists.txt)."""
import os
import re
import sys

ORDER = ["core", "geometry", "grid", "input", "particles", "physics", "transfer", "cracks",
         "diagnostics", "io", "stability", "solver", "main"]
INCLUDE = re.compile(r'^\s*#\s*include\s+"gimp/([a-z_]+)/([^"]+)"', re.M)


def room_of(path):
    """The room of a repo file (src/<room>/..., include/gimp/<room>/..., src/main.cpp)."""
    parts = path.split("/")
    if parts[0] == "src":
        return "main" if len(parts) == 2 else parts[1]
    return parts[2]


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..")
    bad = []
    for top in ("src", "include/gimp"):
        for d, _, files in os.walk(os.path.join(root, top)):
            for f in sorted(files):
                if not f.endswith((".cpp", ".hpp")):
                    continue
                path = os.path.relpath(os.path.join(d, f), root)
                mine = room_of(path)
                if mine not in ORDER:
                    bad.append("%s: room '%s' is not in the order %s" % (path, mine, ORDER))
                    continue
                with open(os.path.join(root, path)) as fh:
                    text = fh.read()
                for room, header in INCLUDE.findall(text):
                    theirs = room
                    if theirs not in ORDER:
                        bad.append("%s: includes gimp/%s/%s of unknown room" % (path, room, header))
                    elif ORDER.index(theirs) > ORDER.index(mine):
                        bad.append("%s (room %s) includes gimp/%s/%s of room %s, which comes "
                                   "after it" % (path, mine, room, header, theirs))
    cmake = open(os.path.join(root, "CMakeLists.txt")).read()
    listed = re.search(r"set\(GIMP_ROOMS([^)]*)\)", cmake)
    if not listed or listed.group(1).split() != ORDER[:-1]:
        bad.append("CMakeLists.txt: set(GIMP_ROOMS ...) is not %s" % " ".join(ORDER[:-1]))
    for line in bad:
        print("check_rooms: " + line, file=sys.stderr)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""The rooms' one-way include order (docs/architecture.md, "Dependencies"): a file of a room may
include headers of its own room and of rooms before it, never of a room after it. Exits 1 naming
every include against the order that is not in KNOWN (the few that remain until their piece
moves; an entry there that no longer occurs is an error too, so the list only shrinks).

Usage: tools/check_rooms.py [repo root]; run at every build (CMakeLists.txt) and by ctest."""
import os
import re
import sys

ORDER = ["core", "grid", "input", "particles", "physics", "transfer", "cracks", "diagnostics",
         "io", "stability", "solver", "main"]
# Plain polyline geometry used by the grid and the scene reader: it sits with grid.
PLACED = {"cracks/geometry.hpp": "grid", "src/cracks/geometry.cpp": "grid"}
# Includes against the order that remain, as (file, included header).
KNOWN = {
    ("include/gimp/grid/lattice.hpp", "gimp/input/scene.hpp"),
    ("include/gimp/input/bodies.hpp", "gimp/particles/shape.hpp"),
    ("include/gimp/input/validate.hpp", "gimp/particles/swarm.hpp"),
    ("src/input/validate.cpp", "gimp/particles/seed.hpp"),
    ("include/gimp/physics/internal_force.hpp", "gimp/transfer/block_kernels.hpp"),
    ("src/physics/tracking.cpp", "gimp/cracks/fields.hpp"),
}
INCLUDE = re.compile(r'^\s*#\s*include\s+"gimp/([a-z_]+)/([^"]+)"', re.M)


def room_of(path):
    """The room of a repo file (src/<room>/..., include/gimp/<room>/..., src/main.cpp)."""
    for key, room in PLACED.items():
        if path.endswith(key):
            return room
    parts = path.split("/")
    if parts[0] == "src":
        return "main" if len(parts) == 2 else parts[1]
    return parts[2]


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..")
    bad, seen = [], set()
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
                    theirs = PLACED.get("%s/%s" % (room, header), room)
                    if theirs not in ORDER:
                        bad.append("%s: includes gimp/%s/%s of unknown room" % (path, room, header))
                    elif ORDER.index(theirs) > ORDER.index(mine):
                        pair = (path, "gimp/%s/%s" % (room, header))
                        seen.add(pair)
                        if pair not in KNOWN:
                            bad.append("%s (room %s) includes gimp/%s/%s of room %s, which comes "
                                       "after it" % (path, mine, room, header, theirs))
    for pair in sorted(KNOWN - seen):
        bad.append("%s no longer includes %s: remove it from KNOWN in tools/check_rooms.py" % pair)
    for line in bad:
        print("check_rooms: " + line, file=sys.stderr)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())

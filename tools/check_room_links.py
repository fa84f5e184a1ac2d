#!/usr/bin/env python3
"""The rooms' one-way order at link level (docs/architecture.md, "Dependencies"): no room's
library may use a symbol that only a later room defines. The include check (check_rooms.py) sees
headers; this sees what the compiled rooms call, templates and inline code included. Exits 1
naming each such symbol, demangled, with the room that uses it and the room that defines it.

Usage: tools/check_room_links.py NM LIB_core.a LIB_geometry.a ... (in GIMP_ROOMS order); run after
the rooms are built (CMakeLists.txt)."""
import os
import subprocess
import sys


def symbols(nm, lib):
    """(defined, undefined) mangled names of a static library's objects."""
    out = subprocess.run([nm, "-P", lib], capture_output=True, text=True, check=True).stdout
    defined, undefined = set(), set()
    for line in out.splitlines():
        parts = line.split()
        if len(parts) < 2 or parts[0].endswith(":"):
            continue  # an archive member's header
        name, kind = parts[0], parts[1]
        if kind == "U":
            undefined.add(name)
        elif kind not in ("w", "v"):  # weak undefined references do not count as definitions
            defined.add(name)
    return defined, undefined


def room_name(lib):
    base = os.path.basename(lib)
    return base[len("libgimp_"):-len(".a")] if base.startswith("libgimp_") else base


def main():
    nm, libs = sys.argv[1], sys.argv[2:]
    tables = [symbols(nm, lib) for lib in libs]
    bad = []
    for i, (_, undefined) in enumerate(tables):
        earlier = set().union(*(d for d, _ in tables[: i + 1]))
        for j in range(i + 1, len(tables)):
            for name in sorted((undefined - earlier) & tables[j][0]):
                bad.append((room_name(libs[i]), room_name(libs[j]), name))
    if bad:
        names = subprocess.run(["c++filt"], input="\n".join(b[2] for b in bad), capture_output=True,
                               text=True).stdout.splitlines()
        for (user, owner, raw), shown in zip(bad, names or [b[2] for b in bad]):
            print("check_room_links: room %s uses %s, defined only in room %s, which comes after "
                  "it" % (user, shown or raw, owner), file=sys.stderr)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())

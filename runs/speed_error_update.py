#!/usr/bin/env python3
"""Error and cost of the update schemes with APIC: MUSL (the default) against USL on the
manufactured solution of docs/validation.md (options/mms_skb1d.opts, one period), at small
(A = 1e-4) and large (A = 0.05) amplitude, h = 1/16 ... 1/128 at the scene's dt = 0.1 h / c.
The error is the largest L-inf displacement error over the period (summary.json mms_linf).
Writes the Markdown table of docs/performance.md (*USL and USF with APIC in lanes*) to stdout;
the wall times are those of this 1D strip (a few hundred particles), not a throughput measure:
bench/run_all.sh runs the benchmark block with both schemes.

Usage: /usr/bin/python3 runs/speed_error_update.py [--gimp build/gimp] [--work DIR] [--no-run]
"""
import os

import series

ROOT = series.ROOT
CELLS = (16, 32, 64, 128)
AMPLITUDES = ("1e-4", "0.05")
SCHEMES = ("musl", "usl")


def runs():
    for A in AMPLITUDES:
        for n in CELLS:
            h = repr(1.0 / n)
            for u in SCHEMES:
                extra = ["-gimp_h", h, "-gimp_body0_box", "0,0,1," + h, "-gimp_bc3_y", h,
                         "-gimp_mms_amplitude", A, "-gimp_update", u, "-gimp_transfer", "apic"]
                yield ((A, n, u), "mms_skb1d.opts", extra, u)


def main():
    a = series.parse_args("speed_error_update")
    err, wall = {}, {}
    for key, _, _, s in series.run_series(a, list(runs()), cwd=os.path.join(ROOT, "options")):
        err[key] = s["measures"]["mms_linf"]
        wall[key] = s["wall_seconds"]
    head = "| h |" + "".join(" A = %s, %s |" % (A, u.upper()) for A in AMPLITUDES for u in SCHEMES)
    print(head)
    print("| --- |" + " --- |" * (len(AMPLITUDES) * len(SCHEMES)))
    for n in CELLS:
        print("| 1/%d |" % n + "".join(" %.4e |" % err[(A, n, u)] for A in AMPLITUDES
                                       for u in SCHEMES))
    total = {u: sum(w for k, w in wall.items() if k[2] == u) for u in SCHEMES}
    print()
    print("wall seconds, all runs: " + ", ".join("%s %.2f" % (u.upper(), total[u]) for u in SCHEMES))


if __name__ == "__main__":
    main()

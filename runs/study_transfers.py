#!/usr/bin/python3
"""Velocity transfers: the table of docs/validation.md, section "Velocity transfers".

Usage: /usr/bin/python3 runs/study_transfers.py --gimp build/gimp --work build/WORK_transfers
       [--root .]

For FLIP, PIC (-gimp_transfer flip -gimp_flip 1 / 0), APIC and XPIC(2): the block of
options/rest_tension.opts pulled to rest on one level and on three
(options/rest_tension_levels.opts): steps to rest (kinetic / strain energy < 1e-10), the worst
particle displacement against the exact linear field (relative to its largest value), the worst
particle stress against the exact one (relative to the traction) outside the loaded side's cell
column and in it; the undamped bar's energy drift over 20 periods; the spinning square's
angular momentum with APIC's spin term (tests/transfers_measure.py). Then APIC and PIC with
USF, USL and MUSL on one level (positions at free edges for every update scheme).
"""
import argparse
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tests"))
import transfers_measure as tm  # noqa: E402

SCHEMES = [("FLIP", ["-gimp_transfer", "flip", "-gimp_flip", "1"]),
           ("PIC", ["-gimp_transfer", "flip", "-gimp_flip", "0"]),
           ("APIC", ["-gimp_transfer", "apic"]),
           ("XPIC(2)", ["-gimp_transfer", "xpic", "-gimp_xpic_order", "2"])]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--gimp", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--root", default=ROOT)
    a = ap.parse_args()
    a.gimp, a.work, a.root = (os.path.abspath(p) for p in (a.gimp, a.work, a.root))
    a.extra = ""
    os.makedirs(a.work, exist_ok=True)
    print("| transfer | levels | steps to rest | max displacement error | max stress error "
          "(outside / in the loaded column) | bar energy drift, 20 periods | max angular "
          "momentum change |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for name, opts in SCHEMES:
        tag = name.replace("(", "").replace(")", "").lower()
        drift, _ = tm.bar_energy(a, tag, opts)
        L = tm.spin(a, tag, opts)
        dL = max(abs(x / L[0] - 1) for x in L)
        for levels in (False, True):
            r = tm.rest(a, "%s_%d" % (tag, levels), opts, levels)
            steps = str(r["steps"]) if r["status"] == "at_rest" else "%s (%s)" % (r["steps"],
                                                                                   r["status"])
            print("| %s | %d | %s | %.2e | %.2e / %.2e | %s | %s |" % (
                name, 3 if levels else 1, steps, r["du"], r["ds_in"], r["ds"],
                "%.2e" % drift if not levels else "", "%.2e" % dL if not levels else ""))
    print()
    print("| transfer | update | steps to rest | max displacement error | max stress error "
          "(outside / in the loaded column) |")
    print("| --- | --- | --- | --- | --- |")
    for name, opts in (SCHEMES[2], SCHEMES[1]):
        for update in ("usf", "usl", "musl"):
            tag = "%s_%s" % (name.lower(), update)
            r = tm.rest(a, tag, opts + ["-gimp_update", update], False)
            print("| %s | %s | %d | %.2e | %.2e / %.2e |" % (name, update.upper(), r["steps"],
                                                           r["du"], r["ds_in"], r["ds"]))


if __name__ == "__main__":
    main()

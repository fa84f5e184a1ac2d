"""The double cantilever beam at rest with per-level time steps (label long, about 2.5 minutes):
options/dcb.opts (2 mm, and 1 mm in the 20 x 20 mm box at the tip; PIC) run to rest with USL,
single-rate and with -gimp_multirate true -gimp_multirate_forces node (R = 2; about half the
particles step with 2 dt).

Checks:
  * both runs come to rest;
  * K_I by VCCT and by the J-integral within 0.2 % of the single-rate run's (measured 0.002 %);
  * the external work over the strain energy (2 for a dead load on a linear body at rest) within
    1e-3 of the single-rate run's; the energy ledger itself does not close with PIC, whose
    transfers dissipate (about 40 % of the work in either run), so it is not compared;
  * the wall times are printed (measured 94 s and 46 s: the per-step cost falls 1.24 times and
    the multi-rate run meets the rest criterion earlier, PIC dissipating less on level 0).
"""
import os

import gimptest

args = gimptest.parse_args()
c = gimptest.Checks()
res = {}
for tag, extra in (("single", []), ("node", ["-gimp_multirate", "true",
                                             "-gimp_multirate_forces", "node"])):
    out = gimptest.run(args, "options/dcb.opts", ["-gimp_update", "usl"] + extra,
                       outdir=os.path.join(args.work, tag))
    res[tag] = gimptest.summary(out)
a, b = res["single"], res["node"]
c.check("both at rest", a["status"] == b["status"] == "at_rest",
        "single-rate %s after %d steps in %.1f s; node rule %s after %d steps in %.1f s" %
        (a["status"], a["steps"], a["wall_seconds"], b["status"], b["steps"], b["wall_seconds"]))
for key in ("KI_vcct", "KI_J"):
    ka, kb = a["cracks"][0][key], b["cracks"][0][key]
    c.check("%s within 0.2 %% of the single-rate run" % key, abs(kb / ka - 1) < 2e-3,
            "%.5f against %.5f Pa m^0.5 (%+.4f %%)" % (kb, ka, 100 * (kb / ka - 1)))
ra = a["energy"]["external_work"] / a["energy"]["strain"]
rb = b["energy"]["external_work"] / b["energy"]["strain"]
c.check("external work / strain energy within 1e-3 of the single-rate run's",
        abs(rb / ra - 1) < 1e-3, "%.6f against %.6f" % (rb, ra))
c.done()

"""Hole edge convergence on the effectively infinite plate with 4, 5, 6 and 7 levels (finest cell
a / 4, a / 8, a / 16, a / 32 next to the hole; about 13 minutes on one core): the fitted edge
curve converges monotonically to Kirsch's, its largest error at a / 32 is at most 0.03 p, and kt
is within 1 % of 3 there (the bounds of docs/validation.md "Hole edge convergence"
gives the measured values)."""
import check_hole
import gimptest

LEVELS = (4, 5, 6, 7)

args = gimptest.parse_args()
c = gimptest.Checks()
ms = [check_hole.static(args, n)[0] for n in LEVELS]
errs = [m["hoop_max_error"] for m in ms]
c.check("monotone", all(a > b for a, b in zip(errs, errs[1:])),
        "max edge error %s p at a / 4, 8, 16, 32" % ", ".join("%.4f" % e for e in errs))
c.check("finest edge error", errs[-1] <= 0.03, "%.4f p (tol 0.03 p)" % errs[-1])
c.check("finest kt", abs(ms[-1]["kt"] / 3 - 1) <= 0.01,
        "kt %.4f (%+.2f %%, tol 1 %%)" % (ms[-1]["kt"], 100 * (ms[-1]["kt"] / 3 - 1)))
c.done()

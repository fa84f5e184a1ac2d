"""A 3D body spinning free of load (options/spin3d.opts: a 4 x 3 x 2 box, omega = (0.03, 0.1,
-0.05) rad/s about its centre, no principal axis, so omega turns while L stays):
  - the seeded velocities are the rigid rotation omega x (X - c), c the box's centre, at every
    particle (to 1e-12 of |omega| r);
  - with the default transfer (APIC) the angular momentum vector sum_p m_p (x_p x v_p +
    eps : B_p^T) stays within 1e-10 of |L0| over 4000 steps, on one level and on three
    (options/spin3d_levels.opts), the particles crossing the levels' faces as the box turns;
  - the box turns: the particle farthest from the centre moves by more than a cell.
(docs/validation.md, *Velocity transfers*; the 2D square: tests/check_transfers.py)
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import gimptest  # noqa: E402

OMEGA = np.array([0.03, 0.1, -0.05])
CENTRE = np.array([2.0, 1.5, 1.0])

args = gimptest.parse_args()
c = gimptest.Checks()
import h5py  # noqa: E402

for levels in (False, True):
    name = "three levels" if levels else "one level"
    lv = ["-options_file", os.path.join(args.root, "options/spin3d_levels.opts")] if levels else []
    out = gimptest.run(args, "options/spin3d.opts", lv,
                       outdir=os.path.join(args.work, "levels" if levels else "one"))
    L, moved = [], 0.0
    with h5py.File(os.path.join(out, "fields.h5"), "r") as f:
        frames = sorted(f["particles"].keys())
        for k in frames:
            g = f["particles"][k]
            m, x, v = g["m"][:], g["x"][:], g["v"][:]
            B = g["B"][:] if "B" in g else np.zeros((len(m), 9))  # no affine field (FLIP)
            spin = np.stack([B[:, 7] - B[:, 5], B[:, 2] - B[:, 6], B[:, 3] - B[:, 1]], axis=1)
            L.append((m[:, None] * (np.cross(x, v) + spin)).sum(axis=0))
            if k == frames[0]:
                r = x - CENTRE
                rigid = np.cross(OMEGA, r)
                err = np.abs(v - rigid).max() / (np.linalg.norm(OMEGA) * np.linalg.norm(r, axis=1).max())
                far = np.argmax(np.linalg.norm(r, axis=1))
                x0 = x[far]
            else:
                moved = np.linalg.norm(x[far] - x0)
    c.check("seeded rotation, " + name, err < 1e-12,
            "max |v - omega x (X - c)| / (|omega| r_max) = %.1e over %d particles" % (err, len(m)))
    worst = max(np.linalg.norm(l - L[0]) for l in L) / np.linalg.norm(L[0])
    c.check("angular momentum, " + name, worst < 1e-10,
            "max |L - L0| / |L0| = %.2e over %d frames of 4000 steps (L0 = %s)" %
            (worst, len(L), np.array2string(L[0], precision=6)))
    c.check("it turns, " + name, moved > 1.0,
            "the particle farthest from the centre moved %.2f m (h = 1 m)" % moved)
c.done()

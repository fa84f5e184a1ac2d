"""Energy conservation of an elastic block drifting across grid levels (options/drift_energy.opts).

An undamped, vibrating neo-Hookean block (192 particles) drifts from level 0 through levels 1
and 2 to level 0 on the other side and back again under a uniform body force along x: every
particle crosses four level boundaries each way (coarse -> fine -> finer -> fine -> coarse), for
1e5 steps. Asserts:
  * the run completed all 1e5 steps (summary status "completed");
  * no particle was lost (summary particle count equals the seeded count);
  * no NaN or infinity in any history.csv column;
  * the total energy kinetic + strain - external work + damping stays within 1 % of its initial
    value at every history row (every 100 steps);
  * the block went where the scene says: its trailing edge passed the last level boundary
    (x = 2.0) on the way out and its leading edge came back left of the first (x = 0.8), and the
    momentum reversed (so the crossings happened both ways).

Extra options (besides those of gimptest.parse_args):
  --ranks N      MPI ranks (default 1; with 2 the block also crosses the rank boundary)
  --steps N      steps (default 100000, as in the scene file)
  --reference    also run the same scene on the uniform level-0 grid and print its energy error
"""
import argparse
import math
import os
import sys
import time

import gimptest

OPTS = "options/drift_energy.opts"
TOL = 0.01               # relative deviation of the total energy
N_PARTICLES = 192        # 0.4 x 0.3 m block, 12 level-0 cells x 16 particles
LEVEL_X = (0.8, 1.2, 1.6, 2.0)  # level boundaries crossed along x

pre = argparse.ArgumentParser(add_help=False)
pre.add_argument("--ranks", type=int, default=1)
pre.add_argument("--steps", type=int, default=100000)
pre.add_argument("--reference", action="store_true")
mine, rest = pre.parse_known_args()
sys.argv = sys.argv[:1] + rest
args = gimptest.parse_args()


def energy_error(hist):
    e = hist["total"]
    e0 = e[0]
    dev = [abs(x - e0) / abs(e0) for x in e]
    k = max(range(len(dev)), key=lambda i: dev[i])
    return e0, dev, k


def run(tag, extra=(), opts=OPTS):
    out = os.path.join(args.work, tag)
    t0 = time.time()
    gimptest.run(args, opts, ["-ts_max_steps", str(mine.steps)] + list(extra),
                 ranks=mine.ranks, outdir=out)
    return out, time.time() - t0


chk = gimptest.Checks()
out, wall = run("drift_energy")
s = gimptest.summary(out)
hist = gimptest.history(out)
e0, dev, k = energy_error(hist)
t = hist["time"]
xl = [0.2125 + u for u in hist["left_ux"]]   # probe particles: left and right column of the block
xr = [0.5875 + u for u in hist["right_ux"]]
turn = max(range(len(xl)), key=lambda i: xl[i])

print("drift_energy: %d steps, %d ranks, %d particles, %.1f s wall" %
      (s["steps"], s["ranks"], s["particles"], wall))
print("%10s %12s %12s %12s %12s %10s %8s %8s" %
      ("t [s]", "kinetic", "strain", "ext. work", "total", "rel. dev", "x_left", "x_right"))
stride = max(1, (len(t) - 1) // 20)
for i in list(range(0, len(t), stride)) + ([len(t) - 1] if (len(t) - 1) % stride else []):
    print("%10.4f %12.5e %12.5e %12.5e %12.5e %10.2e %8.4f %8.4f" %
          (t[i], hist["kinetic"][i], hist["strain"][i], hist["external_work"][i],
           hist["total"][i], dev[i], xl[i], xr[i]))
print("largest deviation %.3e at t = %.4f s; final %.3e" % (dev[k], t[k], dev[-1]))

crossings = 0
for edge in (xl, xr):
    for xb in LEVEL_X:
        crossings += sum(1 for a, b in zip(edge, edge[1:]) if (a - xb) * (b - xb) < 0)

chk.check("completed", s["status"] == "completed" and s["steps"] == mine.steps,
          "status %s after %d of %d steps" % (s["status"], s["steps"], mine.steps))
chk.check("particles", s["particles"] == N_PARTICLES,
          "%d particles at the end (seeded %d)" % (s["particles"], N_PARTICLES))
finite = all(math.isfinite(v) for col in hist.values() for v in col)
chk.check("finite", finite, "all %d history columns finite in %d rows" % (len(hist), len(t)))
chk.check("energy", dev[k] <= TOL,
          "max |E - E0| / E0 = %.3e (<= %g) at t = %.3f s, E0 = %.4f J" % (dev[k], TOL, t[k], e0))
chk.check("path", xl[turn] > LEVEL_X[-1] and xr[-1] < LEVEL_X[0],
          "block's left edge reached x = %.3f (> %.1f) at t = %.2f s, right edge back at %.3f "
          "(< %.1f); %d edge crossings of level boundaries" %
          (xl[turn], LEVEL_X[-1], t[turn], xr[-1], LEVEL_X[0], crossings))
px = hist["momentum_x"]
chk.check("reversal", px[0] > 0 and px[-1] < 0 and abs(px[-1] + px[0]) <= 0.02 * px[0],
          "momentum_x %.4f -> %.4f kg m/s (exact: -%.4f)" % (px[0], px[-1], px[0]))

if mine.reference:
    # The scene without its level options (gimp rejects options a scene does not use).
    uniform = os.path.join(args.work, "drift_energy_uniform.opts")
    with open(os.path.join(args.root, OPTS)) as f, open(uniform, "w") as g:
        g.writelines(line for line in f if not line.startswith("-gimp_level"))
    ref, wref = run("drift_energy_uniform", opts=uniform)
    hr = gimptest.history(ref)
    _, dr, kr = energy_error(hr)
    print("uniform level-0 grid (reference, not asserted): max deviation %.3e at t = %.3f s, "
          "final %.3e, %.1f s wall" % (dr[kr], hr["time"][kr], dr[-1], wref))
chk.done()

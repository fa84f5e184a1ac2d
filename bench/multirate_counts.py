#!/usr/bin/env python3
"""Instructions per fine step of the per-level step against the single step (callgrind).

Timings on this machine move by 10-30 % from minute to minute; instruction counts do not. For
each scene this runs the single step and the per-level step (-gimp_multirate true) under
callgrind, counting only the stepping loop (Solver::advance), twice (--steps A B fine steps) so
that the difference leaves out what the first steps alone do, and prints per fine step:

  kernels   the particle kernels (stencils, P2G, forces, G2P, velocity gradient, stress update,
            checks): work that falls with the particles a sub-step moves;
  nodal     the rest: passes over the nodal Vecs (sums, masks, the grid update, the rate
            classes' starts and ends, zeroing and copies) and the classes' bookkeeping, which
            every sub-step adds whatever its particles;
  ratio     single / per-level, against the particle-work ratio (R N over sum_c (R / m_c) N_c,
            from the per-level run's class sizes) and as a share of it ("of work", 80 % asked).

"bytes" is the part of nodal that callgrind counts in libc's memset and memcpy: those zero and
copy the nodal arrays with rep stosb / rep movsb, which callgrind counts once per byte, while
the processor moves 32 or more bytes a cycle. "no bytes" is the ratio without them.

"kernels only" is the ratio the per-level step would reach with free nodal passes: the bound
that the particle kernels set (a class at a level border holds the particles with row stencils,
which cost several times a block particle's and step more often).

Usage: bench/multirate_counts.py [--scenes block3_tenth block3] [--transfer apic|flip]
                                  [--steps 8 24] [--build DIR] [--single]
--single counts the single step alone (any scene, e.g. --single --scenes block: the 2D default
step of bench/block.opts).
A scene is bench/NAME.opts, else options/NAME.opts, in 2D or 3D. Needs valgrind; about two minutes
per 2D scene, ten per 3D one.
"""
import argparse
import os
import re
import subprocess
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
KERNELS = (r"buildStencils|blockRun|blockLanes|appendNodes|appendThreeNodeBlock|forEachIndex|"
           r"appendFromPattern|patternOf|setLevelBlock|"
           r"particlesToGrid|internalForce|gridToParticles|velocityGradient|updateDeformation|"
           r"jaumannUpdate|updateDomain|neoHookean|checkParticles|inverseInertia|Stencils<\d>::"
           r"forEach|interpolate|setBlock|soleBlock|levelReach|coarsestReaching|strainEnergy")


STRINGS = r"__mem(set|cpy|move)_"


def scene_file(name):
    for d in ("bench", "options"):
        p = os.path.join(ROOT, d, name + ".opts")
        if os.path.exists(p):
            return p
    raise SystemExit("no scene %s in bench/ or options/" % name)


def dimension(opts):
    with open(opts) as f:
        return 3 if re.search(r"^-gimp_dim\s+3\b", f.read(), re.M) else 2


def count(build, opts, multirate, transfer, steps, tmp):
    tag = "%s_%s_%d" % (os.path.basename(opts), multirate, steps)
    out = os.path.join(tmp, tag + ".cg")
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    dim = dimension(opts)
    run = subprocess.run(
        ["valgrind", "--tool=callgrind", "--callgrind-out-file=" + out,
         "--toggle-collect=gimp::Solver<%d>::advance()" % dim, os.path.join(build, "gimp"),
         "-options_file", opts, "-ts_max_steps", str(steps), "-gimp_transfer", transfer,
         "-gimp_multirate", multirate, "-gimp_output_dir", os.path.join(tmp, tag), "-info"],
        check=True, capture_output=True, text=True, env=env)
    classes = None
    m = re.search(r"particles per rate class:(.*)", run.stdout + run.stderr)
    if m:
        classes = [(int(n), int(e)) for n, e in re.findall(r"(\d+) \(every (\d+)\)", m.group(1))]
    text = subprocess.run(["callgrind_annotate", "--threshold=100", out], check=True,
                          capture_output=True, text=True).stdout
    kernels = nodal = strings = 0.0
    for line in text.splitlines():
        m = re.match(r"\s*([\d,]+)\s+\(\s*[\d.]+%\)\s+(.*)", line)
        if not m or "PROGRAM TOTALS" in m.group(2):
            continue
        n = float(m.group(1).replace(",", ""))
        if re.search(KERNELS, m.group(2)):
            kernels += n
        else:
            nodal += n
            if re.search(STRINGS, m.group(2)):
                strings += n
    return kernels, nodal, strings, classes


def per_step(build, opts, multirate, transfer, steps, tmp):
    """Instructions per fine step between steps[0] and steps[1]: kernels, nodal, the bytes of
    nodal's string operations; the classes."""
    k0, n0, s0, _ = count(build, opts, multirate, transfer, steps[0], tmp)
    k1, n1, s1, classes = count(build, opts, multirate, transfer, steps[1], tmp)
    d = steps[1] - steps[0]
    return (k1 - k0) / d, (n1 - n0) / d, (s1 - s0) / d, classes


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenes", nargs="+", default=["block3_tenth", "block3"])
    ap.add_argument("--transfer", default="apic", choices=["apic", "flip"])
    ap.add_argument("--steps", type=int, nargs=2, default=[8, 24],
                    help="the two run lengths in fine steps (multiples of R)")
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--single", action="store_true", help="the single step alone")
    a = ap.parse_args()
    subprocess.run([os.path.join(ROOT, "bench", "machine.sh")], check=False)
    print("instructions per fine step [M], %s, fine steps %d to %d (callgrind, Solver::advance)"
          % (a.transfer.upper(), a.steps[0], a.steps[1]))
    if a.single:
        print("| scene | single: kernels | nodal | total | bytes |")
        print("| --- | --- | --- | --- | --- |")
    else:
        print("| scene | single: kernels, nodal (bytes) | per-level: kernels, nodal (bytes) "
              "| ratio | no bytes | kernels only | work | of work | no bytes, of work |")
        print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    with tempfile.TemporaryDirectory() as tmp:
        for name in a.scenes:
            opts = scene_file(name)
            k1, n1, s1, _ = per_step(a.build, opts, "false", a.transfer, a.steps, tmp)
            if a.single:
                print("| %s | %.2f | %.2f | %.2f | %.2f |"
                      % (name, k1 / 1e6, n1 / 1e6, (k1 + n1) / 1e6, s1 / 1e6))
                continue
            k2, n2, s2, classes = per_step(a.build, opts, "true", a.transfer, a.steps, tmp)
            R = max(e for _, e in classes)
            work = R * sum(n for n, _ in classes) / sum(R / e * n for n, e in classes)
            ratio = (k1 + n1) / (k2 + n2)
            bare = (k1 + n1 - s1) / (k2 + n2 - s2)
            print("| %s | %.2f, %.2f (%.2f) | %.2f, %.2f (%.2f) | %.2f | %.2f | %.2f | %.2f "
                  "| %.0f %% | %.0f %% |"
                  % (name, k1 / 1e6, n1 / 1e6, s1 / 1e6, k2 / 1e6, n2 / 1e6, s2 / 1e6, ratio, bare,
                     (k1 + n1) / k2, work, 100 * ratio / work, 100 * bare / work))


if __name__ == "__main__":
    main()

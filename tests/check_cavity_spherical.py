#!/usr/bin/env python3
"""A short spherical cavity expansion (inputs/cavity_spherical_2d.nml made smaller by
scripts/cavity_expansion.py: outer radius b0 = 4 a0, h = a0/6, the pressure ramped to
3.0 s_u over 3.2 s and held for 0.8 s) run by dpmpm on the given ranks, against the
closed form of doc/theory.md 9.9: the elastic displacement of the shell 1.5 a0 < R0 < 2 a0
against Lame's thick sphere before first yield, and the cavity pressure against the
closed form's at the measured radius at the end. Bounds: the measured errors plus half
(doc/verification.md, "Spherical cavity expansion").

    check_cavity_spherical.py <dpmpm> <mpiexec> <nranks> <scene.nml> <work dir>
"""
import os
import subprocess
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import cavity_expansion as ce  # noqa: E402

B0, N, RAMP, HOLD, P_END = 4.0, 6, 3.2, 0.8, 3.0e4
ELASTIC_BOUND = 0.26    # relative error of the shell's mean displacement, elastic range
END_BOUND = 0.24        # |p - p_ref(a)| / s_u at the end of the hold
A_MIN = 1.12            # the cavity's radius at the end at least this (a0)


def main():
    exe, mpiexec, nranks, scene, work = sys.argv[1:6]
    os.makedirs(work, exist_ok=True)
    sc = ce.scene(scene, N, ".", b0=B0, ramp=RAMP, p_end=P_END, t_end=RAMP + HOLD,
                  name=f"cavity_sph_short_np{nranks}")
    nml = os.path.join(work, sc.name + ".nml")
    sc.write(nml)
    run = subprocess.run([mpiexec, "--oversubscribe", "-n", nranks, os.path.abspath(exe), nml],
                         cwd=work, capture_output=True, text=True, timeout=300)
    if run.returncode != 0:
        print(run.stdout[-3000:], run.stderr[-3000:])
        return 1
    sph = ce.Sphere(sc, 1.0, B0)
    m = ce.compare(sph, *ce.measure(os.path.join(work, sc.name + ".h5"), sph))
    print(f"{nranks} ranks: elastic shell displacement {m['elastic']:+.2%} of Lame (bound "
          f"{ELASTIC_BOUND:.0%}); at the end p = {m['p_end'] / sph.su:.3f} s_u, a = "
          f"{m['a_end']:.4f} a0, p - p_ref(a) = {m['dp_end']:+.4f} s_u (bound {END_BOUND}); "
          f"closed form a_ref(p) = {m['a_ref_end']:.4f} a0")
    fails = []
    if not abs(m["elastic"]) <= ELASTIC_BOUND:
        fails.append("elastic displacement")
    if not abs(m["dp_end"]) <= END_BOUND:
        fails.append("pressure at the end")
    if not m["a_end"] > A_MIN:
        fails.append(f"the cavity did not expand to {A_MIN} a0")
    if fails:
        print("FAIL: " + ", ".join(fails))
        return 1
    print("PASS")
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""A short cavity expansion in Tresca soil run by dpmpm on the given ranks, against its
closed form: the elastic displacement of the ring (shell) 1.5 a0 < r0 < 2 a0 against
Lame's thick cylinder (sphere) before first yield, and the cavity pressure against the
closed form's at the measured radius at the end. The scene is made smaller by
scripts/cavity_expansion.py: outer radius b0 = 4 a0, h = a0/6, the pressure ramped over
3.2 s and held for 0.8 s.
- cylindrical (inputs/cavity_cylindrical_2d.nml, doc/theory.md 9.7): to 1.8 s_u, a/a0 of
  about 1.18 at the end;
- spherical (inputs/cavity_spherical_2d.nml, axisymmetric, doc/theory.md 9.9): to 3.0 s_u.
Bounds: the measured errors plus half (doc/verification.md, "Cylindrical cavity
expansion" and "Spherical cavity expansion").

    check_cavity_expansion.py <dpmpm> <mpiexec> <nranks> <scene.nml> <work dir> [spherical]
"""
import os
import subprocess
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import cavity_expansion as ce  # noqa: E402

B0, N, RAMP, HOLD = 4.0, 6, 3.2, 0.8
#: per geometry: end pressure (Pa), the closed form's class, the run's name, the bound on the
#: relative error of the mean elastic displacement, the bound on |p - p_ref(a)| / s_u at the
#: end of the hold, and the least radius at the end (a0)
GEOMETRIES = {
    "cylindrical": (1.8e4, ce.Cylinder, "cavity_short", "ring", 0.15, 0.019, 1.15),
    "spherical": (3.0e4, ce.Sphere, "cavity_sph_short", "shell", 0.26, 0.24, 1.12),
}


def main():
    exe, mpiexec, nranks, scene, work = sys.argv[1:6]
    geometry = sys.argv[6] if len(sys.argv) > 6 else "cylindrical"
    p_end, form, name, body, elastic_bound, end_bound, a_min = GEOMETRIES[geometry]
    os.makedirs(work, exist_ok=True)
    sc = ce.scene(scene, N, ".", b0=B0, ramp=RAMP, p_end=p_end, t_end=RAMP + HOLD,
                  name=f"{name}_np{nranks}")
    nml = os.path.join(work, sc.name + ".nml")
    sc.write(nml)
    run = subprocess.run([mpiexec, "--oversubscribe", "-n", nranks, os.path.abspath(exe), nml],
                         cwd=work, capture_output=True, text=True, timeout=300)
    if run.returncode != 0:
        print(run.stdout[-3000:], run.stderr[-3000:])
        return 1
    cav = form(sc, 1.0, B0)
    m = ce.compare(cav, *ce.measure(os.path.join(work, sc.name + ".h5"), cav))
    print(f"{nranks} ranks: elastic {body} displacement {m['elastic']:+.2%} of Lame (bound "
          f"{elastic_bound:.0%}); at the end p = {m['p_end'] / cav.su:.3f} s_u, a = "
          f"{m['a_end']:.4f} a0, p - p_ref(a) = {m['dp_end']:+.4f} s_u (bound {end_bound}); "
          f"closed form a_ref(p) = {m['a_ref_end']:.4f} a0")
    fails = []
    if not abs(m["elastic"]) <= elastic_bound:
        fails.append("elastic displacement")
    if not abs(m["dp_end"]) <= end_bound:
        fails.append("pressure at the end")
    if not m["a_end"] > a_min:
        fails.append(f"the cavity did not expand to {a_min} a0")
    if fails:
        print("FAIL: " + ", ".join(fails))
        return 1
    print("PASS")
    return 0


if __name__ == "__main__":
    sys.exit(main())

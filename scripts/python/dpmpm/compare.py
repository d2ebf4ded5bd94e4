"""Two runs compared frame by frame, point sets matched by id.

``compare_runs(a, b)`` returns a ``Comparison``: structural differences (frames, times,
steps, sets, ids) as text, and per dataset the largest absolute difference and the
largest difference relative to the largest magnitude of that dataset in run a
(``max_abs``, ``max_rel``), taken over all frames and points.
"""
import numpy as np


class Comparison:
    """Result of compare_runs: ``problems`` (list of str: anything that prevents a
    point-by-point comparison or differs in integers), ``datasets`` ({(set, dataset):
    {"max_abs", "max_rel", "frame"}}: worst over the frames), ``max_time_diff``."""

    def __init__(self):
        self.problems = []
        self.datasets = {}
        self.max_time_diff = 0.0

    def add(self, sname, dname, frame, max_abs, scale):
        rel = max_abs / scale if scale > 0 else (0.0 if max_abs == 0 else np.inf)
        cur = self.datasets.get((sname, dname))
        if cur is None or rel > cur["max_rel"] or (rel == cur["max_rel"] and max_abs > cur["max_abs"]):
            self.datasets[(sname, dname)] = {"max_abs": float(max_abs), "max_rel": float(rel),
                                             "frame": frame}

    @property
    def max_rel(self):
        return max((d["max_rel"] for d in self.datasets.values()), default=0.0)

    def agrees(self, rtol):
        """No structural difference and every dataset within rtol (relative)."""
        return not self.problems and self.max_rel <= rtol

    def table(self):
        """The comparison as text lines."""
        lines = [f"{'set/dataset':28s} {'max abs diff':>14s} {'max rel diff':>14s}  worst frame"]
        for (s, d), r in sorted(self.datasets.items()):
            lines.append(f"{s + '/' + d:28s} {r['max_abs']:14.6e} {r['max_rel']:14.6e}  "
                         f"{r['frame']}")
        lines.append(f"largest difference of the frame times: {self.max_time_diff:.3e} s")
        lines.extend("DIFFERENT: " + p for p in self.problems)
        return lines


def compare_runs(a, b):
    """Compare two open runs (see the module doc). Datasets present in only one of the
    runs are reported as problems; integer datasets must be equal."""
    c = Comparison()
    if len(a.frames) != len(b.frames):
        c.problems.append(f"{len(a.frames)} frames against {len(b.frames)}")
    for fa, fb in zip(a.frames, b.frames):
        c.max_time_diff = max(c.max_time_diff, abs(fa.time - fb.time))
        if fa.step != fb.step:
            c.problems.append(f"frame {fa.name}: step {fa.step} against {fb.step}")
        if fa.set_names != fb.set_names:
            c.problems.append(f"frame {fa.name}: sets {fa.set_names} against {fb.set_names}")
        for sname in fa.set_names:
            if sname not in fb:
                continue
            pa, pb = fa[sname], fb[sname]
            if not np.array_equal(pa.id, pb.id):
                c.problems.append(f"frame {fa.name}/{sname}: ids differ ({len(pa)} against "
                                  f"{len(pb)} points, "
                                  f"{np.setdiff1d(pa.id, pb.id).size} of a not in b)")
                continue
            for dname in sorted(set(pa.keys()) | set(pb.keys())):
                if dname == "id":
                    continue
                if dname not in pa or dname not in pb:
                    c.problems.append(f"frame {fa.name}/{sname}/{dname}: only in "
                                      f"{'a' if dname in pa else 'b'}")
                    continue
                va, vb = pa[dname], pb[dname]
                if va.shape != vb.shape:
                    c.problems.append(f"frame {fa.name}/{sname}/{dname}: shape {va.shape} "
                                      f"against {vb.shape}")
                    continue
                if va.dtype.kind in "iu" and not np.array_equal(va, vb):
                    c.problems.append(f"frame {fa.name}/{sname}/{dname}: integers differ")
                if va.size == 0:
                    c.add(sname, dname, fa.name, 0.0, 0.0)
                    continue
                va, vb = va.astype(float), vb.astype(float)
                if not (np.all(np.isfinite(va)) and np.all(np.isfinite(vb))):
                    c.problems.append(f"frame {fa.name}/{sname}/{dname}: non-finite values")
                    continue
                c.add(sname, dname, fa.name, float(np.max(np.abs(va - vb))),
                      float(np.max(np.abs(va))))
    return c

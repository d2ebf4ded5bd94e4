#!/usr/bin/env python3
"""Check dpmpm output files against the layout in doc/output.md.

Usage: check_output.py [--contract PATH] FILE.h5 [FILE.h5 ...]

Checks the root attributes, /input, the /diagnostics datasets, every frame
(attributes, point-set datasets, shapes, dtypes) and the content of every
frame: in each point set the ids are unique and the same as in the first
frame (no point lost or doubled), the total mass is the first frame's (to
1e-12 relative), and no dataset holds a non-finite value. Where the input
(/input) drains a face for the pore fluid, fluid points may leave there and
enter there: the fluid ids are then unique, an id that left never comes back,
new ids lie above every earlier one, each point keeps its mass, and the mass
balances with the points that left and entered (drained_faces, check_exchange);
and at every diagnostics record the total mass is the first record's plus the mass that
entered less the mass that left through the drained faces (check_mass_records).
The XDMF sidecar next to each file must be valid XML listing the file's frames
with their times, and every referenced dataset must exist with the declared
dimensions. With --contract, also runs that external layout checker on each file
when the script exists, and says so when it does not.
Exit status 0 when every file passes.
"""
import argparse
import os
import re
import subprocess
import sys
import xml.etree.ElementTree as ET

import h5py
import numpy as np

DIAG_NAMES = ("step", "npoints", "time", "dt", "kinetic_energy", "strain_energy",
              "external_work", "max_speed", "wall_time", "total_mass",
              "momentum_x", "momentum_y", "momentum_z")
SET_NAMES = ("solid", "fluid")
FACE_NAMES = ("x-", "x+", "y-", "y+", "z-", "z+")
# Relative tolerance of the mass balance of a drained scene: the sums over points in
# different orders (frame, entrants, leavers) differ by rounding only: at most 1.9e-16
# of the first frame's mass on the two-layer seepage run (inputs/seepage_layers_1d.nml
# at ten times the head, 2 ranks, 0.2 s: 3 points left and 3 entered; doc/output.md).
BALANCE_RTOL = 1e-12


def namelist_groups(text):
    """The groups of a namelist text as (name, {key: value}) in order; values are the
    raw tokens with quotes removed, keys lower case. Comments (!) are dropped."""
    groups, name, body, quote, comment = [], None, "", None, False
    for ch in text:
        if comment:
            comment = ch != "\n"
            continue
        if quote:
            quote = None if ch == quote else quote
            if name is not None:
                body += ch
            continue
        if ch == "!":
            comment = True
        elif ch in "'\"":
            quote = ch
            if name is not None:
                body += ch
        elif ch == "&" and name is None:
            name, body = "", ""
        elif ch == "/" and name is not None:
            m = re.match(r"(\w+)(.*)", name + body, re.S)
            if m:
                pairs = re.findall(r"(\w+)\s*=\s*('[^']*'|\"[^\"]*\"|[^,\s]+)", m.group(2))
                groups.append((m.group(1).lower(),
                               {k.lower(): v.strip("'\"").strip() for k, v in pairs}))
            name = None
        elif name is not None:
            body += ch
    return groups


def drained_faces(text, ndim):
    """Faces of the grid drained for the pore fluid by the input text (doc/input.md,
    &boundary): fluid = 'drained', or the default at a free or absorbing face (a face
    without a &boundary group is free); impermeable at a fixed or roller face unless
    drained, and where fluid = 'impermeable'. None without an input text (a file
    written without one is checked as closed)."""
    if not text.strip():
        return []
    cond = {f: ("free", "") for f in FACE_NAMES[:2 * ndim]}
    for name, kv in namelist_groups(text):
        if name == "boundary" and kv.get("face", "").lower() in cond:
            cond[kv["face"].lower()] = (kv.get("condition", "free").lower(),
                                        kv.get("fluid", "").lower())
    return [f for f, (c, fl) in cond.items()
            if fl == "drained" or (fl in ("", "default") and c not in ("fixed", "roller"))]


def check_h5(path, bad):
    """Layout of the HDF5 file; appends problems to bad."""
    with h5py.File(path, "r") as f:
        for a in ("dpmpm_version", "git_commit", "nranks", "ndim"):
            if a not in f.attrs:
                bad.append(f"root attribute {a} missing")
        ndim = int(f.attrs.get("ndim", 0))
        if ndim not in (1, 2, 3):
            bad.append(f"root attribute ndim = {ndim}, expected 1, 2 or 3")
        if "input" not in f:
            bad.append("/input missing")
        elif f["input"].shape != () or f["input"].dtype.kind != "S":
            bad.append("/input is not a scalar fixed-length string")

        d = f.get("diagnostics")
        if d is None:
            bad.append("/diagnostics missing")
        else:
            lengths = set()
            for n in DIAG_NAMES:
                if n not in d:
                    bad.append(f"/diagnostics/{n} missing")
                    continue
                ds = d[n]
                want = np.int64 if n in ("step", "npoints") else np.float64
                if ds.dtype != want or ds.ndim != 1 or ds.maxshape != (None,):
                    bad.append(f"/diagnostics/{n}: {ds.dtype} {ds.shape} max {ds.maxshape}, "
                               f"expected extendible 1D {np.dtype(want)}")
                lengths.add(ds.shape[0] if ds.ndim == 1 else -1)
            if len(lengths) > 1:
                bad.append(f"/diagnostics datasets differ in length: {sorted(lengths)}")

        fr = f.get("frames")
        if fr is None or len(fr) == 0:
            bad.append("/frames missing or empty")
            return
        names = sorted(fr.keys())
        if names != [f"{k:06d}" for k in range(len(names))]:
            bad.append(f"frame names are not 000000..{len(names) - 1:06d}: {names[:5]}...")
        # Fluid points leave through drained faces and enter at them: the fluid ids
        # of such a scene are checked as an exchange, not as a fixed set.
        text = f["input"][()] if "input" in f and f["input"].shape == () else b""
        text = text.decode(errors="replace") if isinstance(text, bytes) else str(text)
        open_sets = ("fluid",) if drained_faces(text, ndim) else ()
        # (pore fluid only: a scene without fluid points drains nothing)
        if d is not None and open_sets and any("fluid" in fr[k] for k in names):
            check_mass_records(d, bad)
        first = {}
        for fname in names:
            where = f"/frames/{fname}"
            # A run killed while writing a frame can leave one that HDF5 lists but cannot
            # read: report it and go on with the others.
            try:
                check_frame(fr[fname], where, ndim, first, bad, open_sets)
            except (OSError, KeyError, ValueError, RuntimeError) as e:
                bad.append(f"{where}: cannot be read ({e})")


def check_frame(g, where, ndim, first, bad, open_sets=()):
    """Attributes and point sets of one frame; the sets in open_sets exchange points
    through drained faces."""
    if g.attrs.get("time") is None or g.attrs["time"].dtype != np.float64:
        bad.append(f"{where}: attribute time missing or not float64")
    if g.attrs.get("step") is None or g.attrs["step"].dtype != np.int64:
        bad.append(f"{where}: attribute step missing or not int64")
    sets = [s for s in SET_NAMES if s in g]
    if not sets:
        bad.append(f"{where}: neither a solid nor a fluid group")
    for s in sets:
        check_set(g[s], f"{where}/{s}", ndim, bad)
        check_content(g[s], f"{where}/{s}", first.setdefault(s, {}), bad, s in open_sets)


def check_set(g, where, ndim, bad):
    """One point set: datasets, dtypes, shapes (as seen from h5py), unique ids."""
    if "id" not in g:
        bad.append(f"{where}/id missing")
        return
    n = g["id"].shape[0]
    # Always written, then the optional datasets (&output solid_fields / fluid_fields).
    spec = {"id": ((n,), np.int64), "x": ((n, ndim), np.float64),
            "v": ((n, ndim), np.float64), "mass": ((n,), np.float64),
            "volume": ((n,), np.float64)}
    optional = {"displacement": ((n, ndim), np.float64), "stress": ((n, 6), np.float64),
                "material": ((n,), np.int32), "porosity": ((n,), np.float64),
                "pore_pressure": ((n,), np.float64)}
    # Any other dataset is a state value of a constitutive model (named by the model
    # table, src/materials/dpmpm_model_table.f90): one float64 per point.
    optional.update({name: ((n,), np.float64) for name in g
                     if name not in spec and name not in optional})
    for name, (shape, dtype) in spec.items():
        if name not in g:
            bad.append(f"{where}/{name} missing")
    for name, (shape, dtype) in {**spec, **optional}.items():
        if name in g and (g[name].shape != shape or g[name].dtype != dtype):
            bad.append(f"{where}/{name}: {g[name].dtype} {g[name].shape}, "
                       f"expected {np.dtype(dtype)} {shape}")
    if "porosity" in g and n > 0:
        por = g["porosity"][...]
        if not np.all((por >= 0.0) & (por <= 1.0)):
            bad.append(f"{where}/porosity outside [0, 1]")
    ids = g["id"][...]
    if len(np.unique(ids)) != len(ids):
        bad.append(f"{where}/id not unique")


def check_content(g, where, first, bad, exchange=False):
    """Ids complete and unique, mass conserved, finite values; first holds the first
    frame's ids and mass of this set (filled on the first call). With exchange (a set
    that leaves and enters through drained faces) the ids and mass are checked by
    check_exchange instead."""
    if "id" not in g:
        return
    ids = g["id"][...]
    mass = float(np.sum(g["mass"][...])) if "mass" in g else 0.0
    if exchange:
        check_exchange(ids, g["mass"][...] if "mass" in g else None, mass, where, first, bad)
    else:
        ids = np.sort(ids)
        if not first:
            first["ids"], first["mass"] = ids, mass
        elif not np.array_equal(ids, first["ids"]):
            lost = np.setdiff1d(first["ids"], ids).size
            new = np.setdiff1d(ids, first["ids"]).size
            bad.append(f"{where}: ids differ from the first frame ({lost} missing, {new} new, "
                       f"{len(ids) - len(np.unique(ids))} repeated)")
        elif abs(mass - first["mass"]) > 1e-12 * abs(first["mass"]):
            bad.append(f"{where}: total mass {mass!r}, first frame {first['mass']!r}")
    for name, ds in g.items():
        if ds.dtype.kind == "f" and ds.size and not np.all(np.isfinite(ds[...])):
            bad.append(f"{where}/{name} has non-finite values")


def check_mass_records(d, bad):
    """The diagnostics' mass balance: at every record the total mass is the first
    record's plus the mass that entered through drained faces less the mass that left
    since then (inflow_mass and outflow_mass count from the run's start; files written
    before they were recorded have neither, and are not checked)."""
    if "inflow_mass" not in d or "outflow_mass" not in d or "total_mass" not in d:
        return
    total, inflow, outflow = (d[n][...] for n in ("total_mass", "inflow_mass", "outflow_mass"))
    if not (total.shape == inflow.shape == outflow.shape) or total.size == 0:
        return
    want = total[0] + (inflow - inflow[0]) - (outflow - outflow[0])
    scale = np.maximum.reduce([np.abs(total), np.abs(inflow), np.abs(outflow)])
    off = np.abs(total - want) > BALANCE_RTOL * np.maximum(scale, np.abs(total[0]))
    if np.any(off):
        k = int(np.argmax(off))
        bad.append(f"/diagnostics: {int(np.count_nonzero(off))} records where the total mass is "
                   f"not the first record's + inflow - outflow (record {k}: total {total[k]!r}, "
                   f"expected {want[k]!r})")


def check_exchange(ids, pmass, mass, where, st, bad):
    """A point set whose points leave (outflow) and enter (inflow) between frames. The
    frames record neither the outflow nor the inflow (the diagnostics do:
    check_mass_records), so the balance is taken over the points themselves: a point's mass never
    changes (it is set where the point is made), so the total must equal the first
    frame's plus the mass of the ids that entered (as first seen) less that of the ids
    that left (as last seen). Also: no id twice, an id that left never comes back, and
    new ids lie above every earlier id (inflow numbers them on from the largest).
    st keeps every id seen so far (sorted), its mass and whether it is present."""
    rep = len(ids) - len(np.unique(ids))
    if rep:
        bad.append(f"{where}: {rep} ids repeated")
    u, k = np.unique(ids, return_index=True)
    m = (pmass[k] if pmass is not None and pmass.shape == ids.shape
         else np.zeros(u.size))
    if not st:
        st.update(seen=u, seen_mass=m, present=np.ones(u.size, bool), mass=mass,
                  entered=0.0, left=0.0)
        return
    seen, at = st["seen"], np.searchsorted(st["seen"], u)
    known = np.zeros(u.size, bool)
    if seen.size:
        known = (at < seen.size) & (seen[np.minimum(at, seen.size - 1)] == u)
    back = u[known][~st["present"][at[known]]]
    if back.size:
        bad.append(f"{where}: {back.size} ids that left come back (id {back[0]})")
    new, new_mass = u[~known], m[~known]
    if new.size and seen.size and new[0] <= seen[-1]:
        bad.append(f"{where}: {np.count_nonzero(new <= seen[-1])} new ids not above every "
                   f"earlier id ({seen[-1]})")
    changed = np.count_nonzero(st["seen_mass"][at[known]] != m[known])
    if changed:
        bad.append(f"{where}: {changed} points changed their mass")
    now = np.zeros(seen.size, bool)
    now[at[known]] = True
    st["left"] += float(np.sum(st["seen_mass"][st["present"] & ~now]))
    st["entered"] += float(np.sum(new_mass))
    merged = np.concatenate([seen, new])
    order = np.argsort(merged, kind="stable")
    st["seen"] = merged[order]
    st["seen_mass"] = np.concatenate([st["seen_mass"], new_mass])[order]
    st["present"] = np.concatenate([now, np.ones(new.size, bool)])[order]
    want = st["mass"] + st["entered"] - st["left"]
    scale = max(abs(st["mass"]), abs(st["entered"]), abs(st["left"]), abs(mass))
    if abs(mass - want) > BALANCE_RTOL * scale:
        bad.append(f"{where}: total mass {mass!r}, first frame {st['mass']!r} + entered "
                   f"{st['entered']!r} - left {st['left']!r} = {want!r}")


def check_xmf(h5path, bad):
    """The sidecar parses as XML and every HDF DataItem names an existing dataset
    whose shape matches the declared Dimensions."""
    xmf = os.path.splitext(h5path)[0] + ".xmf"
    if not os.path.exists(xmf):
        bad.append(f"{xmf} missing")
        return
    try:
        root = ET.parse(xmf).getroot()
    except ET.ParseError as e:
        bad.append(f"{xmf}: invalid XML: {e}")
        return
    if root.tag != "Xdmf":
        bad.append(f"{xmf}: root element is {root.tag}, expected Xdmf")
    # One temporal collection of frames; each frame a spatial collection with its time,
    # holding one spatial collection per set with points, named after it, around its grid.
    series = root.findall("Domain/Grid")
    if len(series) != 1 or series[0].get("CollectionType") != "Temporal":
        bad.append(f"{xmf}: the Domain does not hold one temporal collection of frames")
        return
    listed = series[0].findall("Grid")
    with h5py.File(h5path, "r") as f:
        frames = f["frames"] if "frames" in f else {}
        ndim = int(f.attrs.get("ndim", 0))
        names = sorted(frames)
        if len(listed) != len(names):
            bad.append(f"{xmf}: {len(listed)} frames listed, the file has {len(names)}")
        for k, (frame, fr) in enumerate(zip(listed, names)):
            tel = frame.find("Time")
            t = float(tel.get("Value")) if tel is not None else None
            t5 = float(frames[fr].attrs.get("time", np.nan))
            if t is None or abs(t - t5) > 1e-9 * max(1.0, abs(t5)):
                bad.append(f"{xmf}: frame {k} at time {t}, the file's frame {fr} at {t5}")
            # Every set with points in the frame, and nothing else.
            want = sorted(s for s in frames[fr] if frames[fr][s]["id"].shape[0] > 0)
            colls = frame.findall("Grid")
            if sorted(c.get("Name") for c in colls) != want:
                bad.append(f"{xmf}: frame {k} lists the sets "
                           f"{[c.get('Name') for c in colls]}, the file has {want} with points")
            for coll in colls:
                sname = coll.get("Name")
                grids = coll.findall("Grid")
                if len(grids) != 1 or grids[0].get("Name") != sname:
                    bad.append(f"{xmf}: frame {k}: {sname} does not hold one grid named so")
                    continue
                grid = grids[0]
                refs = {(item.text or "").strip().partition(":")[2]
                        for item in grid.iter("DataItem") if item.get("Format") == "HDF"}
                if not all(r.startswith(f"/frames/{fr}/{sname}/") for r in refs):
                    bad.append(f"{xmf}: {sname} frame {k} refers to {sorted(refs)[:2]}..., "
                               f"not to /frames/{fr}/{sname}")
                topo = grid.find("Topology")
                kind = "3DRectMesh" if ndim == 1 else "Polyvertex"
                if topo is None or topo.get("TopologyType") != kind:
                    bad.append(f"{xmf}: {sname} frame {k} is not a {kind} grid")
        for item in root.iter("DataItem"):
            if item.get("Format") != "HDF":
                continue
            ref = (item.text or "").strip()
            fname, _, dset = ref.partition(":")
            if fname != os.path.basename(h5path):
                bad.append(f"{xmf}: refers to {fname}, not to {os.path.basename(h5path)}")
                break
            if dset not in f:
                bad.append(f"{xmf}: {dset} not in the file")
                continue
            dims = tuple(int(t) for t in item.get("Dimensions", "").split())
            shape = f[dset].shape
            # In 1D the attributes of the 1 x 1 x n grid are declared (1, 1) + shape.
            if dims != shape and not (ndim == 1 and dims == (1, 1) + shape):
                bad.append(f"{xmf}: {dset} declared {dims}, stored {shape}")


def run_contract(contract, path, bad):
    if not contract:
        return
    if not os.path.exists(contract):
        print(f"  external contract {contract} not found, skipped")
        return
    r = subprocess.run([sys.executable, contract, path], capture_output=True, text=True)
    print("  contract: " + (r.stdout.strip() or r.stderr.strip()))
    if r.returncode != 0:
        bad.append(f"external contract failed: {r.stdout.strip()} {r.stderr.strip()}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("files", nargs="+", help="dpmpm HDF5 output files")
    ap.add_argument("--contract", help="external layout checker to run as well, if it exists")
    args = ap.parse_args()
    status = 0
    for path in args.files:
        bad = []
        if not os.path.exists(path):
            bad.append("file missing")
        else:
            for check in (check_h5, check_xmf):
                try:
                    check(path, bad)
                except (OSError, KeyError, ValueError, RuntimeError) as e:
                    bad.append(f"{check.__name__[6:]}: cannot be read ({e})")
            run_contract(args.contract, path, bad)
        if bad:
            status = 1
            print(f"{path}: FAILED")
            for b in bad:
                print(f"  {b}")
        else:
            print(f"{path}: layout ok")
    return status


if __name__ == "__main__":
    sys.exit(main())

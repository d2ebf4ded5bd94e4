"""The XDMF sidecar of an output file, made from the file's content.

The same layout as the Fortran writer (src/io/dpmpm_xdmf.f90, write_xdmf): XDMF 2, one
temporal collection of frames, each frame a spatial collection holding, per set with
points in it (solid, fluid, then others), a spatial collection named after the set around
the set's grid. A grid is a Polyvertex cloud in 2D and 3D and a 1 x 1 x n rectilinear
grid on the x axis in 1D, with the datasets as node attributes and the (n, 6) stress as
one Matrix attribute. No hyperslab and no function item: ParaView's Xdmf3 readers skip
both, and this layout reads whole with each of its three XDMF readers.
"""
import os

import h5py

from .run import set_names


def _esc(text):
    return (text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
            .replace('"', "&quot;"))


def _time(t):
    """The time as the Fortran writer prints it (es24.16e3): 9.8233800000000000E-001."""
    mant, _, exp = f"{t:.16E}".partition("E")
    e = int(exp)
    return f"{mant}E{'-' if e < 0 else '+'}{abs(e):03d}"


def _item(dims, ntype, prec, ref):
    return (f'<DataItem Dimensions="{dims}" NumberType="{ntype}" Precision="{prec}" '
            f'Format="HDF">{ref}</DataItem>')


def _set_grid(lines, base, sname, g, ndim):
    n = g["id"].shape[0]
    vec = f"{n} {ndim}"
    lines.append(f'     <Grid Name="{_esc(sname)}" GridType="Uniform">')
    x = _item(vec, "Float", "8", base + "x")
    if ndim == 1:
        zero = '<DataItem Dimensions="1" NumberType="Float" Precision="8" Format="XML">0</DataItem>'
        lines.append(f'      <Topology TopologyType="3DRectMesh" Dimensions="1 1 {n}"/>')
        lines.append('      <Geometry GeometryType="VXVYVZ">')
        lines += ["       " + x, "       " + zero, "       " + zero]
    else:
        lines.append(f'      <Topology TopologyType="Polyvertex" NumberOfElements="{n}" '
                     f'NodesPerElement="1"/>')
        lines.append(f'      <Geometry GeometryType="{"XY" if ndim == 2 else "XYZ"}">')
        lines.append("       " + x)
    lines.append("      </Geometry>")

    def attribute(name, atype, dims, ntype, prec):
        # In 1D the XDMF Reader reads a node attribute of the 1 x 1 x n grid whole only
        # when its dimensions start with those of the grid (1 1 n).
        dims = f"1 1 {dims}" if ndim == 1 else dims
        lines.append(f'      <Attribute Name="{name}" AttributeType="{atype}" Center="Node">'
                     f'{_item(dims, ntype, prec, base + name)}</Attribute>')

    kind = "Scalar" if ndim == 1 else "Vector"
    for name in ("v", "displacement"):
        if name in g:
            attribute(name, kind, vec, "Float", "8")
    for name in ("mass", "volume"):
        if name in g:
            attribute(name, "Scalar", str(n), "Float", "8")
    if "stress" in g:
        # The columns in file order xx yy zz yz xz xy (doc/output.md, "Viewing in ParaView").
        attribute("stress", "Matrix", f"{n} 6", "Float", "8")
    if "material" in g:
        attribute("material", "Scalar", str(n), "Int", "4")
    for name in ("porosity", "pore_pressure"):
        if name in g:
            attribute(name, "Scalar", str(n), "Float", "8")
    # The state values of the constitutive models (plastic_strain, ...): every other
    # dataset, in name order as the writer lists them.
    for name in state_datasets(g):
        attribute(name, "Scalar", str(n), "Float", "8")
    attribute("id", "Scalar", str(n), "Int", "8")
    lines.append("     </Grid>")


#: The datasets of a point set that are not state values of the constitutive models.
FIXED_DATASETS = ("id", "x", "v", "displacement", "mass", "volume", "stress", "material",
                  "porosity", "pore_pressure")


def state_datasets(g):
    """The names of the state values of the models in point set group g (one (n,) float64
    dataset each, named by the model table of src/materials/dpmpm_model_table.f90), sorted."""
    return sorted(name for name in g if name not in FIXED_DATASETS)


def xdmf_text(h5path):
    """The sidecar text for the HDF5 file at h5path (refers to it by its base name)."""
    h5base = _esc(os.path.basename(h5path))
    lines = ['<?xml version="1.0" ?>', '<Xdmf Version="2.0">', " <Domain>"]
    with h5py.File(h5path, "r") as f:
        ndim = int(f.attrs["ndim"])
        frames = f["frames"] if "frames" in f else {}
        names = sorted(frames)
        sets = set()
        for fr in names:
            sets.update(frames[fr].keys())
        lines.append('  <Grid Name="frames" GridType="Collection" CollectionType="Temporal">')
        for fr in names:
            lines.append(f'   <Grid Name="frame {fr}" GridType="Collection" '
                         f'CollectionType="Spatial">')
            lines.append(f'    <Time Value="{_time(float(frames[fr].attrs["time"]))}"/>')
            for sname in set_names(sets):
                g = frames[fr].get(sname)
                if g is None or g["id"].shape[0] == 0:
                    continue
                lines.append(f'    <Grid Name="{_esc(sname)}" GridType="Collection" '
                             f'CollectionType="Spatial">')
                _set_grid(lines, f"{h5base}:/frames/{fr}/{_esc(sname)}/", sname, g, ndim)
                lines.append("    </Grid>")
            lines.append("   </Grid>")
        lines.append("  </Grid>")
    lines += [" </Domain>", "</Xdmf>"]
    return "\n".join(lines) + "\n"


def write_xdmf(h5path, out=None):
    """Write the sidecar of h5path to out (default: next to it, <name>.xmf), through a
    temporary file renamed at the end. Returns the path written."""
    out = out or os.path.splitext(h5path)[0] + ".xmf"
    tmp = out + ".tmp"
    with open(tmp, "w") as f:
        f.write(xdmf_text(h5path))
    os.replace(tmp, out)
    return out

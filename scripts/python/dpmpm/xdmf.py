"""The XDMF sidecar of an output file, made from the file's content.

The same layout as the Fortran writer (src/io/dpmpm_output.f90, write_xdmf): XDMF 2,
one temporal collection per point set named after the set (solid, fluid, then others),
a Polyvertex cloud per frame in which the set has points, the datasets as node
attributes, and the stress columns as stress_xx ... stress_xy through hyperslabs of the
(n, 6) stress dataset when the set has one. 1D coordinates get y = z = 0 through
function items (ParaView needs three coordinates).
"""
import os

import h5py

from .run import STRESS_COMPONENTS, set_names


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


def _set_grid(lines, base, sname, g, ndim, time):
    n = g["id"].shape[0]
    vec = f"{n} {ndim}"
    lines.append(f'   <Grid Name="{_esc(sname)}" GridType="Uniform">')
    lines.append(f'    <Time Value="{time}"/>')
    lines.append(f'    <Topology TopologyType="Polyvertex" NumberOfElements="{n}" '
                 f'NodesPerElement="1"/>')
    x = _item(vec, "Float", "8", base + "x")
    if ndim == 1:
        lines.append('    <Geometry GeometryType="X_Y_Z">')
        lines.append("     " + x)
        for _ in range(2):
            lines.append(f'     <DataItem ItemType="Function" Function="$0 - $0" '
                         f'Dimensions="{vec}">{x}</DataItem>')
    else:
        lines.append(f'    <Geometry GeometryType="{"XY" if ndim == 2 else "XYZ"}">')
        lines.append("     " + x)
    lines.append("    </Geometry>")

    def attribute(name, atype, dims, ntype, prec):
        lines.append(f'    <Attribute Name="{name}" AttributeType="{atype}" Center="Node">'
                     f'{_item(dims, ntype, prec, base + name)}</Attribute>')

    kind = "Scalar" if ndim == 1 else "Vector"
    for name in ("v", "displacement"):
        if name in g:
            attribute(name, kind, vec, "Float", "8")
    for name in ("mass", "volume"):
        if name in g:
            attribute(name, "Scalar", str(n), "Float", "8")
    if "stress" in g:
        for j, comp in enumerate(STRESS_COMPONENTS):
            lines.append(f'    <Attribute Name="stress_{comp}" AttributeType="Scalar" '
                         f'Center="Node"><DataItem ItemType="HyperSlab" Dimensions="{n} 1" '
                         f'Type="HyperSlab"><DataItem Dimensions="3 2" Format="XML">0 {j} 1 1 '
                         f'{n} 1</DataItem>{_item(f"{n} 6", "Float", "8", base + "stress")}'
                         f'</DataItem></Attribute>')
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
    lines.append("   </Grid>")


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
        for sname in set_names(sets):
            lines.append(f'  <Grid Name="{_esc(sname)}" GridType="Collection" '
                         f'CollectionType="Temporal">')
            for fr in names:
                g = frames[fr].get(sname)
                if g is None or g["id"].shape[0] == 0:
                    continue
                base = f"{h5base}:/frames/{fr}/{_esc(sname)}/"
                _set_grid(lines, base, sname, g, ndim, _time(float(frames[fr].attrs["time"])))
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

"""The groups of a namelist text (the input echoed in /input, a scene file) as plain
dicts, read by f90nml; ``dpmpm.Scene`` (dpmpm.scene) is the object to change scenes with.

``groups(text, name)`` gives each group as a dict of variable -> list of values (ints,
floats, strings, logicals): a scalar is a list of one, an element assignment such as
``ncells(2) = 4`` gives ``[None, 4]`` and repeat counts such as ``3*0.0`` are expanded.
A section of a higher-rank array (``stress_gradient(1:6, 2) = ...``) is kept as f90nml's
nested list.
"""
import io

import f90nml


def _as_lists(grp):
    out = {}
    for key, val in grp.items():
        vals = list(val) if isinstance(val, list) else [val]
        start = grp.start_index.get(key)
        if start and len(start) == 1 and start[0] and start[0] > 1:
            vals = [None] * (start[0] - 1) + vals
        out[key] = vals
    return out


def parse(text):
    """All groups of a namelist text as a list of (name, {variable: [values]})."""
    return [(name, _as_lists(grp)) for name, grp in f90nml.reads(text).items()]


def groups(text, name):
    """Every group called name (case insensitive), as a list of dicts."""
    name = name.lower()
    return [v for g, v in parse(text) if g == name]


def group(text, name):
    """The only group called name, or an empty dict when the text has none."""
    found = groups(text, name)
    if len(found) > 1:
        raise ValueError(f"&{name} occurs {len(found)} times")
    return found[0] if found else {}


def value(text):
    """One value given as namelist text (``"0.1"``, ``"'out'"``, ``".true."``)."""
    return f90nml.reads(f"&v x = {text} /\n")["v"]["x"]


def edit(text, values, drop=()):
    """The namelist text with variables replaced or added (f90nml's patch: the layout and
    the comments of the rest are kept) and whole groups removed.

    ``values`` maps ``"group.variable"`` (or ``"variable"``, taken from &run) to the value
    as namelist text (``"0.1"``, ``"'out'"``); a variable the group lacks is added to it,
    a group the text lacks is appended. The first group of that name is edited. ``drop``
    lists group names whose every occurrence is removed; the text is then written anew by
    f90nml (its comments are lost).
    """
    patch = {}
    for key, val in values.items():
        grp, _, var = key.rpartition(".")
        patch.setdefault((grp or "run").lower(), {})[var.lower()] = value(val)
    out = io.StringIO()
    f90nml.Parser().read(io.StringIO(text), patch, out)
    text = out.getvalue()
    if drop:
        from .scene import Scene
        scene = Scene.from_text(text)
        for name in drop:
            scene.remove(name)
        text = scene.text()
    return text

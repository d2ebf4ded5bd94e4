"""Scenes as Python objects: a dpmpm input file (doc/input.md) read, changed and written
with f90nml, and checked by ``dpmpm --check``.

    import dpmpm
    s = dpmpm.Scene.read("inputs/consolidation_2d.nml")
    s["run"]["t_end"] = 0.05                    # the only &run group, an f90nml Namelist
    s.set(run={"name": "short"}, output={"dir": "out/study"})
    s.find("material", id=1)[0]["youngs_modulus"] *= 2
    s.add("boundary", face="x-", condition="slip")   # one more of a repeated group
    s.replace("shape", "kernel = 'cubic', quadrature = 'gauss'")   # a group anew
    s.check()                                   # [] or the problems dpmpm reports
    s.write("out/study/short.nml")

Groups keep their order in the file and may repeat (``&material``, ``&region``,
``&boundary``, ``&load``); each is an ``f90nml.Namelist`` (variable names lower case,
arrays as lists, an element assignment such as ``ncells(2) = 4`` kept as such).
Comments are not kept: ``text()`` writes the groups in f90nml's layout.
"""
import copy as _copy
import os
import subprocess
import tempfile

import f90nml

from .errors import InputError
from .launch import MPI_ENV, find_binary

#: Groups a scene may hold several of; the others occur at most once.
REPEATED = ("material", "region", "boundary", "load")


def _group(values):
    g = f90nml.Namelist()
    for k, v in (values or {}).items():
        g[k.lower()] = v
    return g


class Scene:
    """The groups of a dpmpm input file in order, as ``(name, f90nml.Namelist)``."""

    def __init__(self, groups=(), path=None):
        self.groups_list = [(n.lower(), g if isinstance(g, f90nml.Namelist) else _group(g))
                            for n, g in groups]
        self.path = os.fspath(path) if path is not None else None

    # ---- reading and writing
    @classmethod
    def from_text(cls, text, path=None):
        """A scene from namelist text."""
        nml = f90nml.reads(text)
        return cls([(name, grp) for name, grp in nml.items()], path)

    @classmethod
    def read(cls, path):
        """A scene from a file."""
        with open(path) as f:
            return cls.from_text(f.read(), path)

    def text(self):
        """The scene as namelist text (f90nml's layout; comments are not kept)."""
        out = []
        for name, grp in self.groups_list:
            one = f90nml.Namelist({name: grp})
            one.indent = "  "
            out.append(str(one))
        return "\n".join(out) + "\n"

    def write(self, path):
        """Write the scene to path (folders made as needed); returns path."""
        d = os.path.dirname(os.fspath(path))
        if d:
            os.makedirs(d, exist_ok=True)
        with open(path, "w") as f:
            f.write(self.text())
        return os.fspath(path)

    def copy(self):
        """A deep copy, to vary without touching this one."""
        return Scene(_copy.deepcopy(self.groups_list), self.path)

    # ---- groups
    def names(self):
        """The group names in order, repeats included."""
        return [n for n, _ in self.groups_list]

    def groups(self, name):
        """Every group called name, in order (a list, empty when there is none)."""
        name = name.lower()
        return [g for n, g in self.groups_list if n == name]

    def group(self, name, create=False):
        """The only group called name; with create, an empty one is appended when the
        scene has none. KeyError when it is missing, ValueError when it repeats."""
        found = self.groups(name)
        if len(found) > 1:
            raise ValueError(f"&{name} occurs {len(found)} times: use groups() or find()")
        if not found:
            if not create:
                raise KeyError(f"the scene has no &{name} group")
            return self.add(name)
        return found[0]

    def __getitem__(self, name):
        return self.group(name)

    def __contains__(self, name):
        return bool(self.groups(name))

    def find(self, name, /, **match):
        """The groups called name whose variables equal every given value, e.g.
        ``find("material", id=2)``, ``find("boundary", face="y+")``,
        ``find("benchmark", name="terzaghi")`` (a variable may be called name)."""
        def same(a, b):
            if isinstance(a, str) and isinstance(b, str):
                return a.strip().lower() == b.strip().lower()
            return a == b
        return [g for g in self.groups(name)
                if all(k.lower() in g and same(g[k.lower()], v) for k, v in match.items())]

    def add(self, name, values=None, /, **kw):
        """Append a group (after the last of its name, else at the end) and return it."""
        name = name.lower()
        grp = _group(dict(values or {}, **kw))
        last = max((k for k, (n, _) in enumerate(self.groups_list) if n == name), default=None)
        at = len(self.groups_list) if last is None else last + 1
        self.groups_list.insert(at, (name, grp))
        return grp

    def replace(self, name, values=None, /, **kw):
        """Put a group called name holding exactly these variables in place of the only
        one of that name (appended when the scene has none) and return it. values: a dict,
        or the group's body as namelist text (``"kernel = 'cubic', field_radius = 2.0"``,
        as study scripts list their choices). ValueError when the group repeats."""
        name = name.lower()
        if isinstance(values, str):
            grp = f90nml.reads(f"&{name} {values} /\n").get(name, f90nml.Namelist())
        else:
            grp = _group(values)
        for k, v in kw.items():
            grp[k.lower()] = v
        at = [k for k, (n, _) in enumerate(self.groups_list) if n == name]
        if len(at) > 1:
            raise ValueError(f"&{name} occurs {len(at)} times: remove() and add() instead")
        if not at:
            return self.add(name, grp)
        self.groups_list[at[0]] = (name, grp)
        return grp

    def remove(self, name, /, **match):
        """Remove the groups called name that match (all of them without match); returns
        how many were removed."""
        gone = {id(g) for g in self.find(name, **match)}
        before = len(self.groups_list)
        self.groups_list = [(n, g) for n, g in self.groups_list if id(g) not in gone]
        return before - len(self.groups_list)

    def set(self, values=None, **groups):
        """Set variables: ``set(run={"t_end": 0.5}, output={"dir": "x"})`` or
        ``set({"run.t_end": 0.5})``. The group must occur once (created if absent);
        returns the scene."""
        for key, val in (values or {}).items():
            grp, _, var = key.rpartition(".")
            self.group(grp or "run", create=True)[var.lower()] = val
        for grp, vals in groups.items():
            g = self.group(grp, create=True)
            for var, val in vals.items():
                g[var.lower()] = val
        return self

    # ---- what the scene writes
    def _get(self, group, var, default):
        found = self.groups(group)
        return found[0].get(var, default) if found else default

    @property
    def name(self):
        """&run name (dpmpm's default 'dpmpm' when not given)."""
        return str(self._get("run", "name", "dpmpm")).strip()

    @property
    def output_dir(self):
        """&output dir (default 'out'), as written: relative to where dpmpm runs."""
        return str(self._get("output", "dir", "out")).strip()

    def output_file(self, cwd=None):
        """``<dir>/<name>.h5``, joined to cwd when the scene's dir is relative."""
        return os.path.join(cwd or "", self.output_dir, self.name + ".h5")

    def checkpoint_file(self, cwd=None):
        """``<dir>/<name>.ckpt.h5``, where the run keeps its checkpoint."""
        return os.path.join(cwd or "", self.output_dir, self.name + ".ckpt.h5")

    # ---- dpmpm --check
    def _check(self, binary, cwd):
        exe = find_binary(binary)
        with tempfile.TemporaryDirectory(prefix="dpmpm_check_") as tmp:
            nml = os.path.join(tmp, (self.name or "scene") + ".nml")
            self.write(nml)
            r = subprocess.run([exe, "--check", nml], capture_output=True, text=True,
                               cwd=cwd, env=dict(os.environ, **MPI_ENV))
        prefix = f"dpmpm: input error: {nml}: "
        problems = [line[len(prefix):] if line.startswith(prefix) else line
                    for line in r.stderr.splitlines() if "input error" in line]
        if r.returncode != 0 and not problems:
            problems = [line for line in r.stderr.splitlines() if line.strip()] or \
                [f"dpmpm --check exited with status {r.returncode}"]
        return problems, r.stdout

    def check(self, binary=None, cwd=None):
        """Validate the scene with ``dpmpm --check`` (the binary: ``find_binary``): the
        list of problems dpmpm reports, each as its message (group, value, rule and
        ``[line N]`` of the group in the written text); empty when the scene is valid."""
        return self._check(binary, cwd)[0]

    def resolved(self, binary=None, cwd=None):
        """The scene as dpmpm reads it, every default filled in (``dpmpm --check``'s
        output); InputError when dpmpm refuses it."""
        problems, out = self._check(binary, cwd)
        if problems:
            raise InputError(problems, where=self.path or self.name)
        return Scene.from_text(out)

    def __repr__(self):
        counts = {}
        for n in self.names():
            counts[n] = counts.get(n, 0) + 1
        body = ", ".join(n if c == 1 else f"{n}*{c}" for n, c in counts.items())
        return f"Scene({self.name!r}, groups=[{body}])"


def read_scene(path):
    """``Scene.read(path)``."""
    return Scene.read(path)


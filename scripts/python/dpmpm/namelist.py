"""A small reader for the namelist text echoed in /input.

Only what the analysis needs: the groups of a file, each as a dict of variable ->
list of values (ints, floats, strings, logicals), with element assignments such as
``ncells(2) = 4`` and repeat counts such as ``3*0.0``. Fortran namelist syntax that
dpmpm inputs do not use (derived types, complex numbers) is not supported.
"""
import re

_TOKEN = re.compile(r"""
    '(?:[^']|'')*'          # quoted string, '' inside
  | "(?:[^"]|"")*"
  | [A-Za-z_]\w*\([^)]*\)    # name(index), the index may hold commas and blanks
  | [^\s,='"]+              # a bare word or number
  | =
""", re.VERBOSE)


def _strip_comment(line):
    """The line without its ! comment (a ! inside quotes is kept)."""
    quote = None
    for k, c in enumerate(line):
        if quote:
            if c == quote:
                quote = None
        elif c in "'\"":
            quote = c
        elif c == "!":
            return line[:k]
    return line


def _value(tok):
    """One value token: string, logical, int or float."""
    if tok[0] in "'\"":
        q = tok[0]
        return tok[1:-1].replace(q + q, q)
    low = tok.lower()
    if low in (".true.", ".t.", "t", "true"):
        return True
    if low in (".false.", ".f.", "f", "false"):
        return False
    try:
        return int(tok)
    except ValueError:
        pass
    try:
        return float(low.replace("d", "e"))
    except ValueError:
        return tok


def _tokens(text):
    """(tokens of each group) for every &group ... / in the text, in order."""
    groups = []
    current = None
    for line in text.splitlines():
        line = _strip_comment(line)
        for tok in _TOKEN.findall(line):
            if current is None:
                if tok.startswith("&") and len(tok) > 1:
                    current = (tok[1:].lower(), [])
                continue
            if tok == "/" or tok == "&end":
                groups.append(current)
                current = None
            elif tok.endswith("/") and not tok.startswith(("'", '"')):
                current[1].append(tok[:-1])
                groups.append(current)
                current = None
            else:
                current[1].append(tok)
    if current is not None:
        groups.append(current)
    return groups


_NAME = re.compile(r"^([A-Za-z_]\w*)(?:\((.*)\))?$")


def _assign(values, name, index, items):
    """Store items into values[name], starting at the Fortran index (1-based) if given."""
    if index is None:
        values[name] = list(items)
        return
    # Only the first index matters here: ncells(2) = 4, stress_gradient(1:6, 2) = ...
    first = index.split(",")[0]
    start = int(first.split(":")[0]) if first.split(":")[0].strip() else 1
    if "," in index:
        # A section of a higher-rank array: kept under a key naming the section.
        values[f"{name}({index.replace(' ', '')})"] = list(items)
        return
    cur = values.setdefault(name, [])
    while len(cur) < start - 1 + len(items):
        cur.append(None)
    cur[start - 1:start - 1 + len(items)] = list(items)


def parse(text):
    """All groups of a namelist text as a list of (name, {variable: [values]})."""
    out = []
    for gname, toks in _tokens(text):
        values = {}
        k = 0
        while k < len(toks):
            # A variable name followed by '='.
            if k + 1 < len(toks) and toks[k + 1] == "=":
                m = _NAME.match(toks[k])
                if not m:
                    raise ValueError(f"&{gname}: cannot read {toks[k]!r}")
                name, index = m.group(1).lower(), m.group(2)
                k += 2
                items = []
                while k < len(toks) and not (k + 1 < len(toks) and toks[k + 1] == "="):
                    tok = toks[k]
                    rep = re.match(r"^(\d+)\*(.*)$", tok) if tok[0] not in "'\"" else None
                    if rep:
                        items.extend([_value(rep.group(2))] * int(rep.group(1)))
                    else:
                        items.append(_value(tok))
                    k += 1
                _assign(values, name, index, items)
            else:
                raise ValueError(f"&{gname}: unexpected {toks[k]!r}")
        out.append((gname, values))
    return out


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


def edit(text, values, drop=()):
    """The namelist text with variables replaced or added and whole groups removed.

    ``values`` maps ``"group.variable"`` (or ``"variable"``, taken from &run) to the
    value as namelist text (``"0.1"``, ``"'out'"``); a variable the group lacks is added
    as its first line. The first group of that name is edited. ``drop`` lists group
    names whose every occurrence is removed. Comments and layout elsewhere are kept.
    """
    for name in drop:
        text = re.sub(rf"(?ims)^\s*&{name}\b.*?^\s*/\s*$\n?", "", text)
    for key, val in values.items():
        grp, _, var = key.rpartition(".")
        grp = grp or "run"
        # The variable inside its group, up to the group's closing slash.
        pat = rf"(?ims)^(\s*&{grp}\b(?:(?!^\s*/).)*?^\s*{var}\s*=\s*)[^\n!]*"
        if re.search(pat, text):
            text = re.sub(pat, lambda m: m.group(1) + val, text, count=1)
        elif re.search(rf"(?im)^\s*&{grp}\s*$", text):
            text = re.sub(rf"(?im)^(\s*&{grp})\s*$", lambda m: f"{m.group(1)}\n  {var} = {val}",
                          text, count=1)
        else:
            text = text.rstrip("\n") + f"\n&{grp}\n  {var} = {val}\n/\n"
    return text

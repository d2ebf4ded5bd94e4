#!/usr/bin/env python3
"""Write the Fortran of one input group from its list of variables.

The list, src/config/dpmpm_vars_<group>.inc, has one line per variable
(doc/architecture.md, "Input variables"):

    VAR(group, type, name, component, shape, default)        !< meaning
    TEXT(group, name, component, length, default, 'group', 'name')
    LOCAL(group, type, name, shape, default)

and comment lines. This script writes five plain Fortran files next to each other,
which the config types and the readers take with a Fortran INCLUDE line:

    dpmpm_vars_<group>_component.inc  components of a config type, with defaults
    dpmpm_vars_<group>_local.inc      the reader's local variables, named as in the input
    dpmpm_vars_<group>_namelist.inc   the group's namelist, in the list's order
    dpmpm_vars_<group>_default.inc    the locals set to their defaults
    dpmpm_vars_<group>_kept.inc       the values read kept in dest (a TEXT string longer
                                      than its component is refused, not cut)

Usage: gen_input_vars.py OUTDIR LIST...
"""
import os
import re
import sys

KINDS = {'VAR': 6, 'TEXT': 7, 'LOCAL': 5}


def split_args(text, where):
    """Split the arguments of one line at the commas outside brackets and quotes."""
    args, depth, quote, cur = [], 0, None, ''
    for ch in text:
        if quote:
            cur += ch
            if ch == quote:
                quote = None
        elif ch in '\'"':
            quote = ch
            cur += ch
        elif ch in '([':
            depth += 1
            cur += ch
        elif ch in ')]':
            depth -= 1
            cur += ch
        elif ch == ',' and depth == 0:
            args.append(cur.strip())
            cur = ''
        else:
            cur += ch
    if quote or depth != 0:
        sys.exit(f'{where}: unbalanced quotes or brackets')
    args.append(cur.strip())
    return args


def parse_line(line, where):
    """(kind, args, doc) of a variable line, ('comment', text) of a comment line, or None."""
    s = line.strip()
    if not s:
        return None
    if s.startswith('!'):
        return ('comment', s)
    m = re.match(r'(VAR|TEXT|LOCAL)\(', s)
    if not m:
        sys.exit(f'{where}: neither a comment nor VAR/TEXT/LOCAL: {s}')
    # the closing parenthesis of the line: the first at depth 0 outside quotes
    depth, quote, end = 0, None, None
    for k in range(m.end() - 1, len(s)):
        ch = s[k]
        if quote:
            if ch == quote:
                quote = None
        elif ch in '\'"':
            quote = ch
        elif ch in '([':
            depth += 1
        elif ch in ')]':
            depth -= 1
            if depth == 0:
                end = k
                break
    if end is None:
        sys.exit(f'{where}: no closing parenthesis')
    kind = m.group(1)
    args = split_args(s[m.end():end], where)
    if len(args) != KINDS[kind]:
        sys.exit(f'{where}: {kind} takes {KINDS[kind]} arguments, not {len(args)}')
    rest = s[end + 1:].strip()
    if rest and not rest.startswith('!'):
        sys.exit(f'{where}: text after the line: {rest}')
    return (kind, args, rest)


def decl(ftype, name, shape, init=None, doc=''):
    text = f'{ftype} :: {name}{shape}'
    if init is not None:
        text += f' = {init}'
    if doc:
        text += f' {doc}'
    return text


def generate(path, outdir):
    base = os.path.basename(path)
    group = re.fullmatch(r'dpmpm_vars_(\w+)\.inc', base)
    if not group:
        sys.exit(f'{path}: not named dpmpm_vars_<group>.inc')
    group = group.group(1)
    out = {part: [] for part in ('component', 'local', 'namelist', 'default', 'kept')}
    with open(path) as f:
        lines = f.read().splitlines()
    for n, line in enumerate(lines, 1):
        item = parse_line(line, f'{path}:{n}')
        if item is None:
            continue
        if item[0] == 'comment':
            out['component'].append(item[1])
            continue
        kind, a, doc = item
        if a[0] != group:
            sys.exit(f'{path}:{n}: group {a[0]} in the list of {group}')
        if kind == 'VAR':
            _, ftype, name, comp, shape, default = a
            out['component'].append(decl(ftype, comp, shape, default, doc))
            out['local'].append(decl(ftype, name, shape))
            out['default'].append(f'{name} = {default}')
            out['kept'].append(f'dest%{comp} = {name}')
        elif kind == 'TEXT':
            _, name, comp, length, default, gs, ns = a
            if gs != f"'{group}'" or ns != f"'{name}'":
                sys.exit(f"{path}:{n}: TEXT ends in '{group}', '{name}', not {gs}, {ns}")
            out['component'].append(decl(f'character(len={length})', comp, '', default, doc))
            # a long buffer: a value longer than the component is seen and refused
            out['local'].append(decl('character(len=long_len)', name, ''))
            out['default'].append(f'{name} = {default}')
            out['kept'].append(f"call check_length(pb, '{group}', '{name}', {name}, len(dest%{comp}))")
            out['kept'].append(f'dest%{comp} = {name}(1:len(dest%{comp}))')
        else:
            _, ftype, name, shape, default = a
            out['local'].append(decl(ftype, name, shape))
            out['default'].append(f'{name} = {default}')
        # every kind is in the namelist, in the list's order (which the echo keeps)
        out['namelist'].append(f'namelist /{group}/ {name}')
    for part, body in out.items():
        target = os.path.join(outdir, f'dpmpm_vars_{group}_{part}.inc')
        text = f'! Generated by scripts/gen_input_vars.py from src/config/{base}: edit the list.\n'
        text += ''.join(line + '\n' for line in body)
        # written only when it changes, so that its users are not rebuilt for nothing
        if os.path.exists(target):
            with open(target) as f:
                if f.read() == text:
                    continue
        with open(target, 'w') as f:
            f.write(text)


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    outdir = sys.argv[1]
    os.makedirs(outdir, exist_ok=True)
    for path in sys.argv[2:]:
        generate(path, outdir)


if __name__ == '__main__':
    main()

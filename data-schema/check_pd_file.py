#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Validate a pd-file (pdgrain's HDF5 file) against data-schema/pd-file.schema.json.

Every entry of the JSON is checked: presence (when required), kind, dtype class and size, rank
and shape (symbols n, nb, B, np, nw, T, To, nmat, nmesh resolved from the file), the `unit`
attribute, fixed values and enumerations, value ranges, finiteness, CSR offsets, z = 0 in 2D
files, H5MD hard links and extendible first axes. A file of a newer MAJOR schema version is
refused. Normative text: data-schema/pd-file.md.

Command line:  check_pd_file.py FILE [FILE ...]   exit 0 valid, 1 invalid, 2 unreadable file.
As a module:   from check_pd_file import check;  check("case.h5") -> list of violations.
"""

import argparse
import json
import os
import re
import sys

import h5py
import numpy as np

SCHEMA_FILE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "pd-file.schema.json")
BLOCK = 1 << 22  # values read at once from a large dataset


class UnreadableFile(OSError):
    """The file is missing, not HDF5, or truncated."""


def load_schema(path=SCHEMA_FILE):
    with open(path, encoding="utf-8") as fh:
        return json.load(fh)


# ---------------------------------------------------------------------------------------------
# shape and range expressions: "*", 3, "n", "nb+1", "n-1", alternatives "nb|n"


def _eval_term(term, sym):
    """Value of one term, or None if a symbol is unresolved; "*" gives the string "*"."""
    if isinstance(term, (int, float)):
        return term
    term = term.strip()
    if term == "*":
        return "*"
    m = re.fullmatch(r"([A-Za-z_]\w*)?\s*(?:([+-])?\s*(\d+))?", term)
    if not m or (m.group(1) is None and m.group(3) is None):
        raise ValueError("bad expression %r in the schema" % term)
    name, sign, num = m.groups()
    value = 0
    if name is not None:
        if sym.get(name) is None:
            return None
        value = sym[name]
    if num is not None:
        value = value - int(num) if sign == "-" else value + int(num)
    return value


def _alternatives(expr, sym):
    """List of allowed values of a shape element (None if any symbol is unresolved)."""
    if isinstance(expr, (int, float)):
        return [expr]
    values = [_eval_term(t, sym) for t in expr.split("|")]
    if any(v is None for v in values):
        return None
    return values


def _shape_ok(shape, expected, sym):
    """(ok, resolved-expected-as-text) or (None, text) when unresolved."""
    if len(shape) != len(expected):
        return False, None
    resolved, ok = [], True
    for actual, expr in zip(shape, expected):
        alts = _alternatives(expr, sym)
        if alts is None:
            return None, None
        resolved.append("|".join(str(a) for a in alts))
        if "*" not in alts and actual not in alts:
            ok = False
    return ok, resolved


def _fmt_shape(items):
    items = list(items)
    return "(" + ", ".join(str(i) for i in items) + ("," if len(items) == 1 else "") + ")"


# ---------------------------------------------------------------------------------------------
# helpers over h5py


def _split(path):
    """'/a/b@c' -> ('/a/b', 'c'); '/a/b' -> ('/a/b', None)."""
    if "@" in path:
        obj, attr = path.split("@", 1)
        return obj or "/", attr
    return path, None


def _parent(obj):
    if obj == "/":
        return None
    p = obj.rsplit("/", 1)[0]
    return p or "/"


def _expand(f, pattern):
    """Concrete object paths matching `pattern` ('*' = any child group that exists)."""
    parts = [p for p in pattern.split("/") if p]
    paths = ["/"]
    for part in parts:
        nxt = []
        for base in paths:
            prefix = base.rstrip("/") + "/"
            if part == "*":
                g = f.get(base)
                if isinstance(g, h5py.Group):
                    nxt += [prefix + k for k in sorted(g.keys())
                            if isinstance(g.get(k), h5py.Group)]
            else:
                nxt.append(prefix + part)
        paths = nxt
    return paths


def _kind(f, path):
    obj = f.get(path)
    if obj is None:
        return None
    return "group" if isinstance(obj, h5py.Group) else "dataset"


def _dtype_class(dt):
    if h5py.check_string_dtype(dt) is not None or dt.kind in "SU":
        return "string"
    return {"f": "float", "i": "int", "u": "uint", "b": "uint"}.get(dt.kind, dt.kind)


def _as_text(v):
    if isinstance(v, bytes):
        return v.decode("utf-8", "replace")
    if isinstance(v, np.ndarray):
        return [_as_text(x) for x in v.tolist()]
    if isinstance(v, (list, tuple)):
        return [_as_text(x) for x in v]
    if isinstance(v, np.generic):
        return v.item()
    return v


def _value_text(v):
    return json.dumps(v) if not isinstance(v, str) else repr(v)


def _blocks(dset):
    """Yield the values of a dataset as numpy arrays of at most ~BLOCK elements."""
    if dset.shape == () or dset.size == 0:
        yield np.asarray(dset[()])
        return
    row = max(1, int(np.prod(dset.shape[1:])))
    step = max(1, BLOCK // row)
    for r in range(0, dset.shape[0], step):
        yield dset[r:r + step]


# ---------------------------------------------------------------------------------------------
# the checker


class _Checker:
    def __init__(self, f, schema):
        self.f = f
        self.schema = schema
        self.out = []
        self.sym = {}
        self.ran = {"pd-pack", "any"}  # tools whose output must be present
        self.dimension = None

    def report(self, path, msg):
        self.out.append("%s: %s" % (path, msg))

    # ---- version gate
    def version_ok(self):
        f, want = self.f, self.schema["version"]
        name = _as_text(f.attrs.get("schema"))
        if name is None:
            self.report("/@schema", "missing (not a pd-file)")
            return False
        if name != self.schema["schema"]:
            self.report("/@schema", "is %r, expected %r (not a pd-file)"
                        % (name, self.schema["schema"]))
            return False
        ver = _as_text(f.attrs.get("schema_version"))
        if not isinstance(ver, str) or not re.fullmatch(r"\d+\.\d+\.\d+", ver):
            self.report("/@schema_version", "is %r, expected MAJOR.MINOR.PATCH" % (ver,))
            return False
        major, want_major = int(ver.split(".")[0]), int(want.split(".")[0])
        if major > want_major:
            self.report("/@schema_version", "file is pd-file %s, a newer MAJOR version than this "
                        "checker reads (%s); refused, use a newer pdgrain" % (ver, want))
            return False
        if major < want_major:
            self.report("/@schema_version", "file is pd-file %s, an older MAJOR version than this "
                        "checker reads (%s); refused" % (ver, want))
            return False
        return True

    # ---- context: symbols, tools that ran, dimension
    def resolve(self):
        f = self.f
        for name, spec in self.schema["symbols"].items():
            value = None
            if "count" in spec:
                g = f.get(spec["count"])
                if isinstance(g, h5py.Group):
                    value = sum(1 for k in g.keys() if isinstance(g.get(k), h5py.Group))
            for src in spec.get("from", []):
                d = f.get(src)
                if isinstance(d, h5py.Dataset) and len(d.shape) >= 1:
                    value = int(d.shape[0])
                    break
            self.sym[name] = value
        prov = f.get("/provenance")
        if isinstance(prov, h5py.Group):
            for k in prov:
                g = prov.get(k)
                if not isinstance(g, h5py.Group):
                    continue
                try:
                    if int(g.attrs.get("exit_status", -1)) == 0:
                        self.ran.add(_as_text(g.attrs.get("tool")))
                except (TypeError, ValueError):
                    pass
        dim = f.attrs.get("dimension")
        try:
            self.dimension = int(dim)
        except (TypeError, ValueError):
            self.dimension = None

    def required(self, entry):
        return bool(entry.get("required")) and entry.get("written_by") in self.ran

    # ---- one entry
    def check_entry(self, e):
        obj_pattern, attr = _split(e["path"])
        if "*" in obj_pattern and e["kind"] == "group" and obj_pattern.endswith("*"):
            self.check_pattern_group(e, obj_pattern)
        for obj in _expand(self.f, obj_pattern):
            if attr is not None:
                self.check_attribute(e, obj, attr)
            else:
                self.check_object(e, obj)

    def check_pattern_group(self, e, pattern):
        parent = pattern[: -len("/*")] or "/"
        for base in _expand(self.f, parent):
            g = self.f.get(base)
            if not isinstance(g, h5py.Group):
                continue
            names = [k for k in g.keys() if isinstance(g.get(k), h5py.Group)]
            if self.required(e) and len(names) < e.get("min_count", 0):
                self.report(base, "holds %d groups, expected at least %d"
                            % (len(names), e["min_count"]))
            rx = e.get("name_pattern")
            for k in names:
                if rx and not re.search(rx, k):
                    self.report(base.rstrip("/") + "/" + k, "name does not match %s" % rx)

    def check_object(self, e, path):
        f = self.f
        kind = _kind(f, path)
        parent = _parent(path)
        if kind is None:
            if self.required(e) and (parent is None or _kind(f, parent) == "group"):
                self.report(path, "missing")
            return
        if kind != e["kind"]:
            self.report(path, "is a %s, expected a %s" % (kind, e["kind"]))
            return
        if kind == "group":
            return
        d = f[path]
        self.check_type(e, path, d.dtype)
        if "shape" in e:
            self.check_shape(e, path, d.shape)
        if e.get("unit") is not None:
            unit = _as_text(d.attrs.get("unit"))
            if unit is None:
                self.report(path, "missing unit attribute (expected %r)" % e["unit"])
            elif unit not in e["unit"].split("|"):
                self.report(path, "unit %r, expected %r" % (unit, e["unit"]))
        if e.get("extendible") and d.shape and (d.maxshape is None or d.maxshape[0] is not None):
            self.report(path, "first axis is not extendible (maxshape %s, expected (None, ...))"
                        % (d.maxshape,))
        if "hard_link" in e:
            target = f.get(e["hard_link"])
            addr = h5py.h5o.get_info(d.id).addr
            if target is not None and addr != h5py.h5o.get_info(target.id).addr:
                self.report(path, "is not a hard link to %s" % e["hard_link"])
        self.check_values(e, path, d)

    def check_type(self, e, path, dt):
        if "dtype" not in e:
            return
        cls = _dtype_class(dt)
        want = e["dtype"] + ("%d" % (8 * e["size"]) if "size" in e else "")
        found = cls if cls == "string" else "%s%d" % (cls, 8 * dt.itemsize)
        if cls != e["dtype"] or ("size" in e and cls != "string" and dt.itemsize != e["size"]):
            self.report(path, "dtype %s, expected %s" % (found, want))

    def check_shape(self, e, path, shape):
        expected = e["shape"]
        ok, resolved = _shape_ok(tuple(shape), expected, self.sym)
        if ok is False:
            exp = _fmt_shape(expected)
            if resolved is not None and resolved != [str(x) for x in expected]:
                exp += "=" + _fmt_shape(resolved)
            self.report(path, "shape %s expected %s" % (_fmt_shape(shape), exp))

    def check_attribute(self, e, obj, name):
        f = self.f
        shown = "%s@%s" % (obj, name)
        if _kind(f, obj) is None:
            return  # the object's own entry reports it
        o = f[obj]
        if name not in o.attrs:
            if self.required(e):
                self.report(shown, "missing")
            return
        aid = o.attrs.get_id(name)
        self.check_type(e, shown, aid.dtype)
        if "shape" in e:
            self.check_shape(e, shown, aid.shape)
        value = _as_text(o.attrs[name])
        self.check_scalar_values(e, shown, value)

    def check_scalar_values(self, e, shown, value):
        if "value" in e and value != e["value"]:
            self.report(shown, "is %s, expected %s" % (_value_text(value), _value_text(e["value"])))
        if "enum" in e and value not in e["enum"]:
            self.report(shown, "is %s, expected one of %s"
                        % (_value_text(value), json.dumps(e["enum"])))
        if "pattern" in e and not (isinstance(value, str) and re.search(e["pattern"], value)):
            self.report(shown, "is %s, does not match %s" % (_value_text(value), e["pattern"]))
        if "range" in e and isinstance(value, (int, float)):
            self.check_range(e, shown, value, value)

    def check_range(self, e, shown, lo_found, hi_found):
        lo, hi = e["range"]
        lo_v = None if lo is None else _eval_term(lo, self.sym)
        hi_v = None if hi is None else _eval_term(hi, self.sym)
        if (lo_v is not None and lo_found < lo_v) or (hi_v is not None and hi_found > hi_v):
            def show(expr, v):
                if expr is None:
                    return "inf"
                if isinstance(expr, (int, float)) or str(v) == str(expr):
                    return str(v)
                return "%s=%s" % (expr, v)
            self.report(shown, "values in [%s, %s], expected within [%s, %s]"
                        % (_num(lo_found), _num(hi_found), show(lo, lo_v), show(hi, hi_v)))

    def check_values(self, e, path, d):
        cls = _dtype_class(d.dtype)
        if cls == "string":
            if any(k in e for k in ("value", "enum", "pattern")):
                self.check_scalar_values(e, path, _as_text(d[()]))
            return
        if cls not in ("float", "int", "uint"):
            return
        finite = cls == "float" and e.get("finite", True)
        planar = e.get("planar_z") and self.dimension == 2 and d.shape and d.shape[-1] == 3
        want_range = "range" in e
        csr = e.get("csr")
        if not (finite or planar or want_range or csr or "value" in e or "enum" in e):
            return
        if d.size == 0:
            return
        lo = hi = None
        bad = 0
        zmax = 0.0
        for a in _blocks(d):
            a = np.asarray(a)
            if finite:
                ok = np.isfinite(a)
                bad += int(a.size - np.count_nonzero(ok))
                a_ok = a[ok]
            else:
                a_ok = a.ravel()
            if a_ok.size:
                lo = a_ok.min() if lo is None else min(lo, a_ok.min())
                hi = a_ok.max() if hi is None else max(hi, a_ok.max())
            if planar:
                z = np.abs(a[..., 2])
                z = z[np.isfinite(z)]
                if z.size:
                    zmax = max(zmax, float(z.max()))
        if bad:
            self.report(path, "%d non-finite values (NaN or inf)" % bad)
        if planar and zmax != 0.0:
            self.report(path, "z component is not 0 in a 2D file (max |z| = %g)" % zmax)
        if want_range and lo is not None:
            self.check_range(e, path, lo.item() if hasattr(lo, "item") else lo,
                             hi.item() if hasattr(hi, "item") else hi)
        if ("value" in e or "enum" in e) and d.shape == ():
            self.check_scalar_values(e, path, _as_text(d[()]))
        if csr:
            self.check_csr(path, d, csr)

    def check_csr(self, path, d, total_sym):
        off = np.asarray(d[()]).astype(np.int64).ravel()
        if off.size == 0:
            return
        if off[0] != 0:
            self.report(path, "first offset is %d, expected 0" % off[0])
        dec = np.nonzero(np.diff(off) < 0)[0]
        if dec.size:
            self.report(path, "offsets decrease at row %d (%d > %d)"
                        % (dec[0], off[dec[0]], off[dec[0] + 1]))
        total = self.sym.get(total_sym)
        if total is not None and off[-1] != total:
            self.report(path, "last offset is %d, expected %s=%d" % (off[-1], total_sym, total))

    def run(self):
        if not self.version_ok():
            return self.out
        self.resolve()
        for e in self.schema["entries"]:
            self.check_entry(e)
        return self.out


def _num(v):
    return "%d" % v if isinstance(v, (int, np.integer)) or float(v).is_integer() else "%.6g" % v


def check(path, schema=None):
    """Violations of `path` against the schema, one "<dataset path>: <problem>" string each;
    an empty list means valid. Raises UnreadableFile if the file cannot be opened as HDF5."""
    schema = schema if schema is not None else load_schema()
    try:
        f = h5py.File(path, "r")
    except (OSError, ValueError) as err:
        raise UnreadableFile("%s: cannot open as HDF5 (%s)" % (path, err)) from err
    with f:
        return _Checker(f, schema).run()


def main(argv=None):
    ap = argparse.ArgumentParser(description="Validate pd-files against the pd-file schema. "
                                 "Exit status: 0 valid, 1 invalid, 2 unreadable file.")
    ap.add_argument("files", nargs="+", metavar="FILE", help="pd HDF5 file(s)")
    ap.add_argument("--schema", default=SCHEMA_FILE, help="schema JSON (default: %(default)s)")
    ap.add_argument("-q", "--quiet", action="store_true", help="print violations only")
    args = ap.parse_args(argv)
    schema = load_schema(args.schema)
    status = 0
    for name in args.files:
        try:
            problems = check(name, schema)
        except UnreadableFile as err:
            print("check_pd_file: %s" % err, file=sys.stderr)
            status = 2
            continue
        for p in problems:
            print("%s: %s" % (name, p))
        if problems:
            status = max(status, 1)
            print("%s: INVALID, %d violation(s) of pd-file %s"
                  % (name, len(problems), schema["version"]), file=sys.stderr)
        elif not args.quiet:
            print("%s: valid pd-file (schema %s)" % (name, schema["version"]))
    return status


if __name__ == "__main__":
    sys.exit(main())

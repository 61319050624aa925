#!/usr/bin/python3
"""Independent dolfinx reference for liftoff: beams and circular arches on a tensionless
Winkler foundation, discretised with C0 interior-penalty (CIP) Lagrange elements.

Run with Debian's interpreter (dolfinx 0.5.2 lives there):

    /usr/bin/python3 verification/dolfinx/penalty_reference.py SCENE.toml \
        [--elements N | --refine] [--penalty-scale S] [--u-degree 3] --json OUT.json

It shares no code with liftoff: it reads the same TOML scene (tomllib) and builds its own model.

Model (the sign conventions of liftoff's README): w > 0 into the foundation; forces > 0 push
toward the foundation; moments > 0 are counterclockwise (x or theta to the right, foundation
below), rotation = -w' (beam), -(u + w')/R (arch).

Discretisation (deliberately different from liftoff's Hermite cubics + P1 reaction):
  * w: continuous P2 Lagrange; the fourth-order term by the symmetric C0 interior-penalty
    method (broken second derivatives, consistency terms on the interior vertices, a penalty
    alpha * EI / h_avg on the jump of w'); clamped ends impose w' = 0 by Nitsche's method with
    the same structure on the boundary.
  * u (arches only): continuous Lagrange of degree --u-degree (default 3: then u' can equal w
    exactly for every continuous P2 w, so inextensional bending is representable and the
    element does not lock; degree 2 locks, see README.md here, "The discretisation").
  * foundation: the residual integral of K max(w, 0) v, integrated EXACTLY on each cell: the
    P2 w is split at its roots and each positive piece is integrated by 3-point Gauss (exact
    for the quartic integrands). Its Jacobian is the integral of K v_i v_j over {w > 0} (the
    moving-boundary terms vanish because w = 0 there), so the discrete problem is C^1 and
    Newton converges quadratically. --foundation-integration quadrature instead uses UFL's
    conditional(w > 0) at the quadrature points (a semismooth alternative, as a cross-check).
  * Newton: dolfinx NonlinearProblem + NewtonSolver, started from the bilateral solution. The
    residual is assembled from the UFL form (never as K @ x) and the Newton system is solved by
    GMRES on the matrix-free action of the Jacobian form, preconditioned by the LU (MUMPS) of
    the assembled Jacobian. Reason: the P2-CIP matrix of this fourth-order problem has
    condition number ~N^4, and the rounding of its assembled entries alone moves a plain direct
    solution by ~eps*N^4 relative (1e-6 at N = 1600, 1e-3 at 6400: a smooth error that shifts
    the contact limits); the form evaluations do not lose those digits.
  * Contact limits: the roots of the P2 interpolant of w on the foundation cells (quadratic
    formula per cell), not snapped to vertices.

Exit codes: 0 solved, 2 bad scene or command line, 3 no converged equilibrium.
"""

import argparse
import json
import logging
import math
import os
import sys
import time
import tomllib

import numpy as np

DEG = math.pi / 180.0


class SceneError(Exception):
    pass


class SolveFailure(Exception):
    pass


# --------------------------------------------------------------------------------------------
# Scene
# --------------------------------------------------------------------------------------------

def _num(table, key, where, default=None, required=True):
    if key not in table:
        if required and default is None:
            raise SceneError(f"key '{where}.{key}': required")
        return default
    v = table[key]
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise SceneError(f"key '{where}.{key}': expected a finite number, got {v!r}")
    return float(v)


def _numbers(table, key, where, min_len=1):
    v = table.get(key)
    if (not isinstance(v, list) or len(v) < min_len
            or any(isinstance(e, bool) or not isinstance(e, (int, float)) or not math.isfinite(e) for e in v)):
        raise SceneError(f"key '{where}.{key}': expected an array of at least {min_len} finite numbers")
    return [float(e) for e in v]


def _string(table, key, where, allowed, default):
    v = table.get(key, default)
    if v not in allowed:
        raise SceneError(f"key '{where}.{key}': expected one of {', '.join(map(repr, allowed))}, got {v!r}")
    return v


def _case_factor(case, lam):
    """The factor on a load of this case at load factor lam: live loads scale, dead ones do not;
    a named case has no meaning under a load factor other than 1."""
    if case == "live":
        return lam
    if case == "dead" or lam == 1.0:
        return 1.0
    raise SceneError(f"load case {case!r}: only 'dead' and 'live' loads can take a load factor ({lam})")


def _known(table, keys, where):
    """A key this reference does not read would be ignored silently and change the problem:
    refuse it (the tables of numerics, [solve], [ritz], [trace], [compare], are not read)."""
    for key in table:
        if key not in keys:
            raise SceneError(f"key '{where}.{key}': unknown to the dolfinx reference (it reads "
                             f"{', '.join(keys)})")


def _table_positions(sc, at, where):
    """A table's positions (user coordinate) -> internal, non-decreasing, inside the member."""
    for a, b in zip(at[:-1], at[1:]):
        if b < a:
            raise SceneError(f"key '{where}': positions must be non-decreasing ({a} then {b})")
    return [sc_pos(sc, p, where) for p in at]


def _read_gap(sc, fd, scene_path):
    """g(x): (positions internal, values) or None. Constant beyond the table's ends."""
    if "gap" in fd and "gap_file" in fd:
        raise SceneError("key 'foundation.gap_file': not allowed together with 'foundation.gap'")
    if "gap" in fd:
        g = fd["gap"]
        if not isinstance(g, dict):
            raise SceneError("key 'foundation.gap': expected a table { at = [...], value = [...] }")
        at = _numbers(g, "at", "foundation.gap")
        val = _numbers(g, "value", "foundation.gap")
        if len(at) != len(val):
            raise SceneError("key 'foundation.gap.value': expected as many values as positions in 'at'")
        return _gap_positions(sc, at, "foundation.gap.at"), val
    if "gap_file" in fd:
        f = fd["gap_file"]
        if not isinstance(f, str):
            raise SceneError("key 'foundation.gap_file': expected a file name (string)")
        path = os.path.join(os.path.dirname(os.path.abspath(scene_path)), f)
        at, val = [], []
        try:
            with open(path) as fh:
                for line in fh:
                    parts = line.replace(",", " ").replace(";", " ").split()
                    try:
                        x, v = float(parts[0]), float(parts[1])
                    except (ValueError, IndexError):
                        continue      # a header or a blank line
                    at.append(x)
                    val.append(v)
        except OSError as e:
            raise SceneError(f"key 'foundation.gap_file': cannot read {path}: {e.strerror}")
        if not at:
            raise SceneError(f"key 'foundation.gap_file': no 'position, gap' rows in {path}")
        return _gap_positions(sc, at, "foundation.gap_file"), val
    return None


def _gap_positions(sc, at, where):
    """Gap positions may reach beyond the member (a survey); only the order is checked."""
    for a, b in zip(at[:-1], at[1:]):
        if b < a:
            raise SceneError(f"key '{where}': positions must be non-decreasing ({a} then {b})")
    return [p if sc["kind"] == "beam" else p * DEG for p in at]


# liftoff's scene keys nondimensional_k and tension_nondimensional_k (K l^4/EI) were k and tension_k;
# this reference reads the old names, so a scene's new ones are mapped onto them (a scene with both
# is refused by liftoff's reader).
def _old_names(table):
    renamed = {"nondimensional_k": "k", "tension_nondimensional_k": "tension_k"}
    return {renamed.get(key, key): value for key, value in table.items()}


def _read_foundation(sc, fd, scene_path):
    if fd is None:
        raise SceneError("table [foundation] is required")
    if not isinstance(fd, dict):
        raise SceneError("key 'foundation': expected a table")
    fd = _old_names(fd)
    if isinstance(fd.get("segments"), list):
        fd["segments"] = [_old_names(seg) if isinstance(seg, dict) else seg for seg in fd["segments"]]
    _known(fd, ("k", "modulus", "from", "to", "tensionless", "segments", "gap", "gap_file", "tension_modulus",
                "tension_k", "side"), "foundation")
    kscale = sc["EI"] / sc["ref_length"] ** 4          # K per unit of k
    segments = []                                        # (s_a, s_b, K_a, K_b, user_a, user_b)
    if "segments" in fd:
        for key in ("k", "modulus", "from", "to"):
            if key in fd:
                raise SceneError(f"key 'foundation.{key}': not allowed together with [[foundation.segments]]")
        if not isinstance(fd["segments"], list) or not fd["segments"]:
            raise SceneError("key 'foundation.segments': expected one or more [[foundation.segments]] tables")
        for i, seg in enumerate(fd["segments"]):
            where = f"foundation.segments[{i}]"
            if not isinstance(seg, dict):
                raise SceneError(f"key '{where}': expected a table")
            _known(seg, ("from", "to", "k", "modulus"), where)
            a_user = _num(seg, "from", where)
            b_user = _num(seg, "to", where)
            if not b_user > a_user:
                raise SceneError(f"key '{where}.to': expected > from ({a_user}), got {b_user}")
            if ("k" in seg) == ("modulus" in seg):
                raise SceneError(f"key '{where}': exactly one of 'k' and 'modulus'")
            key = "k" if "k" in seg else "modulus"
            v = seg[key]
            if isinstance(v, list):
                vals = _numbers(seg, key, where, 2)
                if len(vals) != 2:
                    raise SceneError(f"key '{where}.{key}': expected a number or two numbers [at from, at to]")
            else:
                vals = [_num(seg, key, where)] * 2
            if min(vals) < 0.0 or max(vals) <= 0.0:
                raise SceneError(f"key '{where}.{key}': expected values >= 0, not both 0, got {v!r}")
            fac = kscale if key == "k" else 1.0
            segments.append((sc_pos(sc, a_user, where + ".from"), sc_pos(sc, b_user, where + ".to"),
                             vals[0] * fac, vals[1] * fac, a_user, b_user))
        segments.sort()
        for p, q in zip(segments[:-1], segments[1:]):
            if q[0] < p[1] - 1e-12 * (sc["s1"] - sc["s0"]):
                raise SceneError(f"key 'foundation.segments': pieces [{p[4]}, {p[5]}] and [{q[4]}, {q[5]}] overlap")
    else:
        if ("k" in fd) == ("modulus" in fd):
            raise SceneError("key 'foundation': exactly one of 'k' and 'modulus' (or [[foundation.segments]])")
        K = _num(fd, "k", "foundation") * kscale if "k" in fd else _num(fd, "modulus", "foundation")
        if not K > 0.0:
            raise SceneError(f"key 'foundation.{'k' if 'k' in fd else 'modulus'}': expected > 0")
        a_user = _num(fd, "from", "foundation", default=user_of(sc, sc["s0"]))
        b_user = _num(fd, "to", "foundation", default=user_of(sc, sc["s1"]))
        if not b_user > a_user:
            raise SceneError(f"key 'foundation.to': expected > from ({a_user}), got {b_user}")
        segments.append((sc_pos(sc, a_user, "foundation.from"), sc_pos(sc, b_user, "foundation.to"), K, K,
                         a_user, b_user))
    sc["segments"] = segments
    # "the" modulus for the summary line: the largest
    sc["K"] = max(max(s[2], s[3]) for s in segments)
    sc["k"] = sc["K"] / kscale
    if "tensionless" in fd and not isinstance(fd["tensionless"], bool):
        raise SceneError("key 'foundation.tensionless': expected true or false")
    sc["tensionless"] = bool(fd.get("tensionless", True))
    if "tension_modulus" in fd and "tension_k" in fd:
        raise SceneError("key 'foundation.tension_k': not allowed together with 'foundation.tension_modulus'")
    Kt = 0.0
    if "tension_modulus" in fd or "tension_k" in fd:
        key = "tension_modulus" if "tension_modulus" in fd else "tension_k"
        Kt = _num(fd, key, "foundation") * (kscale if key == "tension_k" else 1.0)
        if not sc["tensionless"]:
            raise SceneError(f"key 'foundation.{key}': only meaningful with tensionless = true")
        if Kt < 0.0 or any(Kt > min(s[2], s[3]) * (1 + 1e-12) for s in segments):
            raise SceneError(f"key 'foundation.{key}': expected >= 0 and <= the compression modulus everywhere")
    sc["Kt"] = Kt
    sc["gap"] = _read_gap(sc, fd, scene_path)
    side = _string(fd, "side", "foundation", ("inside", "outside"), "inside")
    if sc["kind"] == "beam" and "side" in fd:
        raise SceneError("key 'foundation.side': only for arches")
    sc["side"] = side
    sc["sigma"] = -1.0 if side == "outside" else 1.0   # user w = sigma * (inward radial w)


def _read_support(sc, v, where, interior=False):
    """A support: a string (end supports) or a table. Returns a dict with kind, settlement,
    stiffness, rotational_stiffness and (interior) at."""
    arch = sc["kind"] == "arch"
    if interior:
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            v = {"at": v}
        if not isinstance(v, dict):
            raise SceneError(f"key '{where}': expected a position or a table {{ at = ..., kind = ... }}")
        allowed = ("pinned", "spring")
    else:
        allowed = ("pinned", "clamped", "free", "spring") + (("roller",) if arch else ())
        if isinstance(v, str):
            v = {"kind": v}
        if not isinstance(v, dict):
            raise SceneError(f"key '{where}': expected a string or a table {{ kind = ... }}")
    _known(v, ("kind", "settlement", "stiffness", "rotational_stiffness") + (("at",) if interior else ()), where)
    out = {"kind": _string(v, "kind", where, allowed, "pinned" if interior else None)}
    if out["kind"] is None:
        raise SceneError(f"key '{where}.kind': required")
    out["settlement"] = _num(v, "settlement", where, default=0.0)
    out["stiffness"] = _num(v, "stiffness", where, default=0.0)
    out["rotational_stiffness"] = _num(v, "rotational_stiffness", where, default=0.0)
    if out["kind"] == "free" and "settlement" in v:
        raise SceneError(f"key '{where}.settlement': not allowed on a free end")
    if out["kind"] == "spring":
        if out["stiffness"] < 0 or out["rotational_stiffness"] < 0 or \
                max(out["stiffness"], out["rotational_stiffness"]) <= 0:
            raise SceneError(f"key '{where}.stiffness': a spring needs stiffness and/or rotational_stiffness "
                             f">= 0, at least one > 0")
    else:
        for key in ("stiffness", "rotational_stiffness"):
            if key in v:
                raise SceneError(f"key '{where}.{key}': only for kind = \"spring\"")
    if interior:
        out["at"] = sc_pos(sc, _num(v, "at", where), where + ".at")
        if out["at"] in (sc["s0"], sc["s1"]):
            raise SceneError(f"key '{where}.at': expected strictly inside the member")
    return out


def _read_loads(sc, raw):
    arch = sc["kind"] == "arch"
    loads = []
    for i, ld in enumerate(raw.get("loads", [])):
        where = f"loads[{i}]"
        if not isinstance(ld, dict):
            raise SceneError(f"key '{where}': expected a table")
        _known(ld, ("kind", "value", "at", "from", "to", "case", "direction", "per"), where)
        lk = _string(ld, "kind", where, ("force", "moment", "uniform", "distributed", "curvature", "axial"), None)
        # "dead" and "live" (scaled by the load factor), or a named load case of liftoff's
        # [[combinations]]: applied once, as liftoff's solve does (with a load factor, refused).
        case = ld.get("case", "live")
        if not isinstance(case, str) or not case:
            raise SceneError(f"key '{where}.case': expected a non-empty string, got {case!r}")
        item = {"kind": lk, "case": case}
        if lk == "axial":
            # issue 15: a constant axial force along the beam, value > 0 compressive
            if arch:
                raise SceneError(f"key '{where}.kind': an axial load is for beams only")
            for key in ("at", "from", "to", "direction", "per"):
                if key in ld:
                    raise SceneError(f"key '{where}.{key}': not allowed on an axial load (constant along the member)")
            item["value"] = _num(ld, "value", where)
            loads.append(item)
            continue
        if not arch:
            for key in ("direction", "per"):
                if key in ld:
                    raise SceneError(f"key '{where}.{key}': not allowed on a beam (its loads are transverse)")
        if lk in ("uniform", "distributed"):
            item["direction"] = _string(ld, "direction", where, ("radial", "vertical"), "radial")
            if "per" in ld and item["direction"] != "vertical":
                raise SceneError(f"key '{where}.per': only with direction = \"vertical\"")
            item["per"] = _string(ld, "per", where, ("arc", "projection"), "arc")
        if lk == "uniform":
            v = _num(ld, "value", where)
            a = _num(ld, "from", where, default=user_of(sc, sc["s0"]))
            b = _num(ld, "to", where, default=user_of(sc, sc["s1"]))
            if not b > a:
                raise SceneError(f"key '{where}.to': expected > from")
            item.update(at=[sc_pos(sc, a, where + ".from"), sc_pos(sc, b, where + ".to")], values=[v, v])
        elif lk == "distributed":
            at = _numbers(ld, "at", where, 2)
            vals = _numbers(ld, "value", where, 2)
            if len(at) != len(vals):
                raise SceneError(f"key '{where}.value': expected as many values as positions in 'at'")
            item.update(at=_table_positions(sc, at, where + ".at"), values=vals)
        elif lk == "curvature":
            item["value"] = _num(ld, "value", where)
            a = _num(ld, "from", where, default=user_of(sc, sc["s0"]))
            b = _num(ld, "to", where, default=user_of(sc, sc["s1"]))
            if not b > a:
                raise SceneError(f"key '{where}.to': expected > from")
            item.update(range=(sc_pos(sc, a, where + ".from"), sc_pos(sc, b, where + ".to")))
        else:
            item["value"] = _num(ld, "value", where)
            item["at"] = sc_pos(sc, _num(ld, "at", where), where + ".at")
            if lk == "force":
                item["direction"] = _string(ld, "direction", where,
                                            ("radial", "tangential", "vertical", "horizontal"), "radial")
        loads.append(item)
    return loads


def read_scene(path):
    with open(path, "rb") as fh:
        raw = tomllib.load(fh)
    st = raw.get("structure")
    if not isinstance(st, dict):
        raise SceneError("table [structure] is required")
    kind = st.get("kind")
    if kind not in ("beam", "arch"):
        raise SceneError("key 'structure.kind': expected \"beam\" or \"arch\"")
    _known(st, ("kind", "length", "radius", "half_angle_deg", "EI", "EA"), "structure")
    sc = {"kind": kind, "name": path}
    sc["EI"] = _num(st, "EI", "structure")
    if kind == "beam":
        sc["L"] = _num(st, "length", "structure")
        sc["s0"], sc["s1"] = 0.0, sc["L"]
        sc["J"] = 1.0          # ds_physical = J ds (s = x)
        sc["ref_length"] = sc["L"]
        sc["user_span"] = sc["L"]
    else:
        sc["R"] = _num(st, "radius", "structure")
        gamma = _num(st, "half_angle_deg", "structure")
        sc["gamma_deg"] = gamma
        sc["EA"] = _num(st, "EA", "structure")
        sc["s0"], sc["s1"] = -gamma * DEG, gamma * DEG
        sc["J"] = sc["R"]      # ds_physical = R dtheta (s = theta)
        sc["ref_length"] = sc["R"]
        sc["user_span"] = 2.0 * gamma   # degrees
    sc["user_keys"] = {}

    sup = raw.get("supports", {})
    if not isinstance(sup, dict):
        raise SceneError("key 'supports': expected a table")
    _known(sup, ("left", "right", "interior"), "supports")
    for end in ("left", "right"):
        sc[end] = _read_support(sc, sup.get(end, "free"), f"supports.{end}")
    interior = sup.get("interior", [])
    if not isinstance(interior, list):
        raise SceneError("key 'supports.interior': expected an array")
    sc["interior"] = [_read_support(sc, v, f"supports.interior[{i}]", interior=True) for i, v in enumerate(interior)]

    _read_foundation(sc, raw.get("foundation"), path)
    sc["loads"] = _read_loads(sc, raw)
    sc["w0"] = _read_initial_shape(sc, raw.get("geometry"))
    sc["scene_elements"] = int(raw.get("solve", {}).get("elements", 200))
    sc["plain"] = (len(sc["segments"]) == 1 and sc["segments"][0][2] == sc["segments"][0][3] and sc["gap"] is None
                   and sc["Kt"] == 0.0 and sc["side"] == "inside")
    return sc


def _read_initial_shape(sc, geo):
    """[geometry] initial_shape = { at, value } (issue 15): the stress-free initial shape w0,
    piecewise linear through the points (constant beyond them), beams only. The named shapes
    (half-sine, bump) are not read here: a one-line error."""
    if geo is None:
        return None
    if not isinstance(geo, dict):
        raise SceneError("key 'geometry': expected a table")
    _known(geo, ("initial_shape",), "geometry")
    if "initial_shape" not in geo:
        return None
    where = "geometry.initial_shape"
    if sc["kind"] != "beam":
        raise SceneError(f"key '{where}': read for beams only")
    shape = geo["initial_shape"]
    if not isinstance(shape, dict) or set(shape) != {"at", "value"}:
        raise SceneError(f"key '{where}': only a table {{ at = [...], value = [...] }} is read here")
    at = _numbers(shape, "at", where, 2)
    vals = _numbers(shape, "value", where, 2)
    if len(at) != len(vals):
        raise SceneError(f"key '{where}.value': expected as many values as positions in 'at'")
    if any(b <= a for a, b in zip(at, at[1:])):
        raise SceneError(f"key '{where}.at': expected increasing positions")
    return (_table_positions(sc, at, where + ".at"), vals)


def axial_force(sc, lam):
    """The beam's axial force (compression positive) at load factor lam."""
    return sum(_case_factor(ld["case"], lam) * ld["value"] for ld in sc["loads"] if ld["kind"] == "axial")


def sc_pos(sc, user, where="position"):
    """User position (x, or theta in degrees) -> internal coordinate s (x, or theta in rad)."""
    s = user if sc["kind"] == "beam" else user * DEG
    span = sc["s1"] - sc["s0"]
    if abs(s - sc["s0"]) <= 1e-12 * span:
        s = sc["s0"]
    if abs(s - sc["s1"]) <= 1e-12 * span:
        s = sc["s1"]
    if s < sc["s0"] or s > sc["s1"]:
        raise SceneError(f"key '{where}': position {user} outside the member")
    if "user_keys" in sc:
        sc["user_keys"][s] = user      # a limit here is reported as the scene's own number
    return s


def user_of(sc, s):
    return s if sc["kind"] == "beam" else s / DEG


def table_value(at, values, x, outside):
    """Piecewise-linear table at x (not at a step: callers sample inside cells); outside the
    table: 'const' (its end values) or 'zero'."""
    at = np.asarray(at, dtype=float)
    values = np.asarray(values, dtype=float)
    if outside == "zero":
        return np.interp(x, at, values, left=0.0, right=0.0)
    return np.interp(x, at, values)


def cell_linear(fun, xa, xb):
    """End values (at xa, xb) of a function that is linear on each cell, sampled at the quarter
    points (never at a breakpoint or step, which are mesh vertices) and extrapolated."""
    q1 = fun(0.75 * xa + 0.25 * xb)
    q3 = fun(0.25 * xa + 0.75 * xb)
    return 1.5 * q1 - 0.5 * q3, 1.5 * q3 - 0.5 * q1


# --------------------------------------------------------------------------------------------
# Mesh
# --------------------------------------------------------------------------------------------

def key_points(sc):
    """Mesh vertices that every mesh has: the ends, supports, foundation piece ends, gap
    breakpoints and steps (inside the member), load points and table breakpoints."""
    pts = [sc["s0"], sc["s1"]] + [s["at"] for s in sc["interior"]]
    for seg in sc["segments"]:
        pts += [seg[0], seg[1]]
    if sc["gap"] is not None:
        pts += [p for p in sc["gap"][0] if sc["s0"] < p < sc["s1"]]
    if sc.get("w0") is not None:
        pts += [p for p in sc["w0"][0] if sc["s0"] < p < sc["s1"]]
    for ld in sc["loads"]:
        if ld["kind"] == "axial":
            continue
        if ld["kind"] in ("uniform", "distributed"):
            pts += list(ld["at"])
        elif ld["kind"] == "curvature":
            pts += list(ld["range"])
        else:
            pts.append(ld["at"])
    pts = sorted(pts)
    span = sc["s1"] - sc["s0"]
    out = [pts[0]]
    for p in pts[1:]:
        if p - out[-1] > 1e-12 * span:
            out.append(p)
    return np.array(out)


def base_allocation(kp, n_target):
    lengths = np.diff(kp)
    n = np.maximum(1, np.rint(n_target * lengths / lengths.sum()).astype(int))
    return n


def vertices(kp, alloc):
    xs = [kp[0]]
    for a, b, n in zip(kp[:-1], kp[1:], alloc):
        xs.extend(list(np.linspace(a, b, n + 1)[1:]))
    return np.array(xs)


# --------------------------------------------------------------------------------------------
# The finite-element model for one mesh
# --------------------------------------------------------------------------------------------

def _Problem(model, F, u, bcs, J, extra):
    """dolfinx NonlinearProblem plus the point loads and (optionally) the exact-cut
    foundation term, added to the assembled residual and Jacobian."""
    from dolfinx.fem.petsc import NonlinearProblem
    from petsc4py import PETSc

    class Problem(NonlinearProblem):
        def F(self, x, b):
            super().F(x, b)
            add = -model.f_point
            if extra is not None:
                r, _ = extra(x.array_r.copy(), want_jac=False)
                add = add + r
            add = add.copy()
            add[model.bc_dofs] = 0.0
            b.array[:] += add

        def J(self, x, A):
            super().J(x, A)
            if extra is not None:
                _, Jf = extra(x.array_r.copy(), want_jac=True)
                Jf = Jf.tocsr()
                Jf.sort_indices()
                A.setValuesCSR(Jf.indptr.astype(PETSc.IntType), Jf.indices.astype(PETSc.IntType), Jf.data,
                               addv=PETSc.InsertMode.ADD_VALUES)
                A.assemble()

    prob = Problem(F, u, bcs=bcs, J=J)
    prob.J_ufl = J
    prob.extra = extra
    return prob


class _Action:
    """Matrix-free Jacobian: y = J x by assembling the action of the Jacobian form (plus the
    exact-cut foundation term), the same structure-preserving evaluation as the residual.
    Used as the Krylov operator, with the LU of the assembled Jacobian as preconditioner."""

    def __init__(self, model, problem):
        import ufl
        from dolfinx import fem
        self.model = model
        self.extra = problem.extra
        self.dxf = fem.Function(model.W)
        self.form = fem.form(ufl.action(problem.J_ufl, self.dxf))
        self.Jf = None
        self.mask = np.ones(model.ndofs)
        self.mask[model.bc_dofs] = 0.0

    def update(self, x, A):       # NewtonSolver's "J" callback: remember the state
        if self.extra is not None:
            _, self.Jf = self.extra(x.array_r.copy(), want_jac=True)

    def mult(self, mat, x, y):
        from dolfinx.fem.petsc import assemble_vector
        xa = x.array_r
        xx = xa * self.mask
        self.dxf.x.array[:] = xx
        b = assemble_vector(self.form)
        ya = b.array.copy()
        if self.Jf is not None:
            ya += self.Jf @ xx
        ya = ya * self.mask + xa * (1.0 - self.mask)
        y.array[:] = ya


class Model:
    def __init__(self, sc, xs, opts):
        import ufl
        from mpi4py import MPI
        from petsc4py import PETSc
        from dolfinx import fem, mesh as dmesh
        import dolfinx.fem.petsc as fpetsc
        self.sc, self.opts = sc, opts
        arch = sc["kind"] == "arch"
        self.arch = arch
        t_build0 = time.perf_counter()

        n = len(xs) - 1
        self.n_elements = n
        domain = ufl.Mesh(ufl.VectorElement("Lagrange", ufl.interval, 1))
        cells = np.stack([np.arange(n), np.arange(1, n + 1)], axis=1).astype(np.int64)
        msh = dmesh.create_mesh(MPI.COMM_SELF, cells, xs.reshape(-1, 1), domain)
        self.msh = msh
        tdim = 1
        msh.topology.create_connectivity(0, 1)
        msh.topology.create_connectivity(1, 0)
        nc = msh.topology.index_map(tdim).size_local
        mid = dmesh.compute_midpoints(msh, tdim, np.arange(nc, dtype=np.int32))[:, 0]
        span = sc["s1"] - sc["s0"]
        tol = 1e-10 * span

        # spaces
        Pw = ufl.FiniteElement("Lagrange", msh.ufl_cell(), 2)
        if arch:
            Pu = ufl.FiniteElement("Lagrange", msh.ufl_cell(), opts.u_degree)
            W = fem.FunctionSpace(msh, ufl.MixedElement([Pu, Pw]))
            Wu, Ww = W.sub(0), W.sub(1)
        else:
            W = fem.FunctionSpace(msh, Pw)
            Wu, Ww = None, W
        self.W, self.Ww, self.Wu = W, Ww, Wu
        ndofs = W.dofmap.index_map.size_local * W.dofmap.index_map_bs
        self.ndofs = ndofs

        # parent-dof coordinates
        coord = np.full(ndofs, np.nan)
        self.is_w = np.zeros(ndofs, dtype=bool)
        if arch:
            for sub, flag in ((Wu, False), (Ww, True)):
                Vc, cmap = sub.collapse()
                cmap = np.asarray(cmap)
                coord[cmap] = Vc.tabulate_dof_coordinates()[:, 0]
                if flag:
                    self.is_w[cmap] = True
        else:
            coord[:] = W.tabulate_dof_coordinates()[:, 0]
            self.is_w[:] = True
        self.coord = coord

        # w dofs per cell, ordered left, middle, right
        cw = np.array([Ww.dofmap.cell_dofs(c) for c in range(nc)], dtype=np.int64)
        order = np.argsort(coord[cw], axis=1)
        cw = np.take_along_axis(cw, order, axis=1)
        self.cw = cw
        self.cx = coord[cw]          # (nc, 3)
        self.cell_mid = mid
        sigma = sc["sigma"]
        self.sigma = sigma

        # ---- per-cell foundation data: compression modulus at the cell ends (linear within a
        # piece, 0 in a void), tension modulus, gap at the cell ends (linear on every cell: its
        # breakpoints and steps are vertices) ----
        xa, xb = self.cx[:, 0], self.cx[:, 2]

        def modulus_at(x):
            out = np.zeros_like(x)
            for a, b, Ka, Kb, _, _ in sc["segments"]:
                sel = (x > a) & (x < b)
                out[sel] = Ka + (Kb - Ka) * (x[sel] - a) / (b - a)
            return out
        Kc_a, Kc_b = cell_linear(modulus_at, xa, xb)
        on_piece = np.zeros(nc, dtype=bool)
        for a, b, _, _, _, _ in sc["segments"]:
            on_piece |= (mid > a) & (mid < b)
        self.found_cells = np.nonzero(on_piece)[0]
        self.Kc_ab = np.stack([Kc_a, Kc_b], axis=1)[self.found_cells]
        self.Kt_cell = np.full(len(self.found_cells), sc["Kt"])
        if sc["gap"] is not None:
            g_a, g_b = cell_linear(lambda x: table_value(sc["gap"][0], sc["gap"][1], x, "const"), xa, xb)
        else:
            g_a, g_b = np.zeros(nc), np.zeros(nc)
        self.g_ab = np.stack([g_a, g_b], axis=1)

        # ---- boundary conditions: w (and u) held, with the settlements as values ----
        def vertex_at(s):
            v = dmesh.locate_entities(msh, 0, lambda x: np.abs(x[0] - s) < tol)
            if len(v) != 1:
                raise RuntimeError(f"no unique mesh vertex at s = {s}")
            return v

        bc_dofs, bc_vals = [], []

        def hold(dofs, value):
            bc_dofs.append(np.asarray(dofs))
            bc_vals.append(np.full(len(dofs), value))
        gauge = None
        self.springs = []        # (vertex s, kind dict, cells side) for the spring terms
        for end, s in (("left", sc["s0"]), ("right", sc["s1"])):
            sup = sc[end]
            kind = sup["kind"]
            v = vertex_at(s)
            if kind in ("pinned", "clamped", "roller"):
                hold(fem.locate_dofs_topological(Ww, 0, v), sigma * sup["settlement"])
            if arch and kind in ("pinned", "clamped"):
                hold(fem.locate_dofs_topological(Wu, 0, v), 0.0)
            if kind == "spring":
                self.springs.append((s, sup))
        for sup in sc["interior"]:
            if sup["kind"] == "pinned":
                hold(fem.locate_dofs_topological(Ww, 0, vertex_at(sup["at"])), sigma * sup["settlement"])
            else:
                self.springs.append((sup["at"], sup))
        ends = [sc["left"]["kind"], sc["right"]["kind"]]
        u_held = any(k in ("pinned", "clamped") for k in ends) or any(
            k == "spring" and sc[e]["stiffness"] > 0 for e, k in zip(("left", "right"), ends)) or any(
            s["kind"] == "spring" and s["stiffness"] > 0 for s in sc["interior"])
        if arch and not u_held:
            # rigid rotation about the centre (u = const, w = 0) is resisted by nothing:
            # fix u at the vertex nearest the crown (a gauge; changes no deflection or force)
            xv = msh.geometry.x[:, 0]
            vc = int(np.argmin(np.abs(xv - 0.5 * (sc["s0"] + sc["s1"]))))
            xg = xv[vc]
            hold(fem.locate_dofs_topological(Wu, 0, vertex_at(xg)), 0.0)
            gauge = f"u = 0 at theta = {xg / DEG:.6g} deg (rigid rotation of the arch about its centre)"
        self.gauge = gauge
        if bc_dofs:
            allb = np.concatenate(bc_dofs).astype(np.int32)
            allv = np.concatenate(bc_vals)
            self.bc_dofs, first = np.unique(allb, return_index=True)
            self.bc_values = allv[first]
        else:
            self.bc_dofs, self.bc_values = np.zeros(0, dtype=np.int32), np.zeros(0)
        self.bc_dofs = self.bc_dofs.astype(np.int32)
        held = fem.Function(W)
        held.x.array[self.bc_dofs] = self.bc_values
        self.held = held
        bcs = [fem.dirichletbc(held, self.bc_dofs)] if len(self.bc_dofs) else []
        self.bcs = bcs

        # ---- clamped-end facet tags for Nitsche ----
        facet_idx, facet_val = [], []
        for tag, (end, s) in enumerate((("left", sc["s0"]), ("right", sc["s1"])), start=1):
            if sc[end]["kind"] == "clamped":
                facet_idx.append(int(vertex_at(s)[0]))
                facet_val.append(tag)
        order_f = np.argsort(facet_idx)
        ft = dmesh.meshtags(msh, 0, np.array(facet_idx, dtype=np.int32)[order_f],
                            np.array(facet_val, dtype=np.int32)[order_f])

        # ---- cell data: line loads (DG1: piecewise linear, steps at vertices), imposed
        # curvature (DG0), and the DG0 modulus of the quadrature cross-check ----
        V0 = fem.FunctionSpace(msh, ("DG", 0))
        c0 = np.array([V0.dofmap.cell_dofs(c)[0] for c in range(nc)])
        kf = fem.Function(V0)
        kf.x.array[c0[self.found_cells]] = sc["K"]
        self.kf = kf
        V1 = fem.FunctionSpace(msh, ("DG", 1))
        c1 = np.array([V1.dofmap.cell_dofs(c) for c in range(nc)])
        x1 = V1.tabulate_dof_coordinates()[:, 0]
        lam = opts.load_factor
        q_line = {key: np.zeros((nc, 2)) for key in ("radial", "arc", "projection")}
        kT = fem.Function(V0)
        for ld in sc["loads"]:
            fac = _case_factor(ld["case"], lam)
            if ld["kind"] in ("uniform", "distributed"):
                qa, qb = cell_linear(lambda x: table_value(ld["at"], ld["values"], x, "zero"), xa, xb)
                key = "radial" if ld["direction"] == "radial" else ld["per"]
                q_line[key] += fac * np.stack([qa, qb], axis=1)
            elif ld["kind"] == "curvature":
                a, b = ld["range"]
                sel = (mid > a) & (mid < b)
                # kap is the curvature change in the solver's variable (theta for arches:
                # physical curvature kap / R^2) and of the inward w (sigma)
                scale = sigma * (sc["R"] ** 2 if arch else 1.0)
                kT.x.array[c0[sel]] += fac * ld["value"] * scale
        self.has_curvature = bool(np.any(kT.x.array != 0.0))

        def dg1(vals):
            f = fem.Function(V1)
            for c in range(nc):
                d = c1[c]
                left = x1[d] <= 0.5 * (xa[c] + xb[c])
                f.x.array[d] = np.where(left, vals[c, 0], vals[c, 1])
            return f
        q_rad, q_arc, q_proj = (dg1(q_line[k]) for k in ("radial", "arc", "projection"))

        # ---- forms ----
        EI, J = sc["EI"], sc["J"]
        if arch:
            R = sc["R"]
            cb = EI / R ** 3          # EI * ((u' + w'')/R^2)^2 * R dtheta
            cm = sc["EA"] / R         # EA * ((u' - w)/R)^2 * R dtheta
        else:
            cb = EI
        alpha = opts.alpha * opts.penalty_scale
        nrm = ufl.FacetNormal(msh)
        h = ufl.CellDiameter(msh)
        h_avg = (h("+") + h("-")) / 2.0
        trial = ufl.TrialFunction(W)
        test = ufl.TestFunction(W)
        if arch:
            u, w = ufl.split(trial)
            uh, wh = ufl.split(test)
            kap = u.dx(0) + ufl.div(ufl.grad(w))
            kaph = uh.dx(0) + ufl.div(ufl.grad(wh))
        else:
            w, wh = trial, test
            kap = ufl.div(ufl.grad(w))
            kaph = ufl.div(ufl.grad(wh))
        ds = ufl.Measure("ds", domain=msh, subdomain_data=ft)
        dx = ufl.dx(domain=msh)
        dS = ufl.dS(domain=msh)
        a = cb * kap * kaph * dx
        a += (- cb * ufl.avg(kap) * ufl.jump(ufl.grad(wh), nrm)
              - cb * ufl.jump(ufl.grad(w), nrm) * ufl.avg(kaph)
              + alpha * cb / h_avg * ufl.jump(ufl.grad(w), nrm) * ufl.jump(ufl.grad(wh), nrm)) * dS
        if facet_idx:
            dn = ufl.dot(ufl.grad(w), nrm)
            dnh = ufl.dot(ufl.grad(wh), nrm)
            nit = -cb * kap * dnh - cb * dn * kaph + alpha * cb / h * dn * dnh
            a += nit * ds(1) + nit * ds(2)
        if arch:
            a += cm * (u.dx(0) - w) * (uh.dx(0) - wh) * dx
        # issue 15, beams: the axial force P (compression positive) adds -P/2 int w'^2 to the
        # energy, i.e. -P int w' v' to the bilinear form. With a stress-free initial shape w0 the
        # unknown is the deflection from it (bending and foundation act on it; the foundation
        # follows the initial shape) while P acts on the total slope w0' + w': the load gains
        # +P int w0' v'.
        self.axial_force = 0.0 if arch else axial_force(sc, opts.load_factor)
        if self.axial_force != 0.0:
            a += -self.axial_force * w.dx(0) * wh.dx(0) * dx
        # line loads: radial ones (> 0 toward the foundation, i.e. along sigma * inward);
        # vertical ones (> 0 downward) have the inward component cos(theta) and the
        # tangential one sin(theta); per projection they carry |cos(theta)| more (dx = R cos dtheta)
        if arch:
            th = ufl.SpatialCoordinate(msh)[0]
            qv = q_arc + q_proj * abs(ufl.cos(th))
            dxq = ufl.dx(domain=msh, metadata={"quadrature_degree": 10})
            Lq = J * (sigma * q_rad + qv * ufl.cos(th)) * wh * dxq + J * qv * ufl.sin(th) * uh * dxq
        else:
            Lq = J * q_rad * wh * dx
        # imposed curvature: the bending energy is 1/2 EI (kap + kT)^2, so the residual gains
        # int EI kT kap(v) and kT enters the moment of every consistency term
        if self.has_curvature:
            Lq = Lq - cb * kT * kaph * dx + cb * ufl.avg(kT) * ufl.jump(ufl.grad(wh), nrm) * dS
            if facet_idx:
                Lq = Lq + cb * kT * ufl.dot(ufl.grad(wh), nrm) * (ds(1) + ds(2))
        if self.axial_force != 0.0 and sc.get("w0") is not None:
            # w0 is linear on every cell (its breakpoints are vertices): a DG0 slope
            w0a, w0b = cell_linear(lambda x: table_value(sc["w0"][0], sc["w0"][1], x, "const"), xa, xb)
            w0_slope = fem.Function(V0)
            w0_slope.x.array[c0] = (w0b - w0a) / (xb - xa)
            Lq = Lq + self.axial_force * w0_slope * wh.dx(0) * dx
        self.L_form = fem.form(Lq)

        # residual forms F(uh; v) and their Jacobians, for dolfinx's NonlinearProblem. The
        # residual is assembled from the form (not as K @ x): see solve() for why. The
        # foundation (and springs) are added by foundation_exact, bilateral or tensionless.
        self.uh = fem.Function(W)
        uh = self.uh
        F_lin = ufl.action(a, uh) - Lq
        self.prob_bil = _Problem(self, F_lin, uh, bcs, a, lambda x, want_jac: self.foundation_exact(x, want_jac, True))
        if sc["tensionless"]:
            if opts.foundation_integration == "exact":
                self.prob_t = _Problem(self, F_lin, uh, bcs, a, self.foundation_exact)
            else:
                wcur = ufl.split(uh)[1] if arch else uh
                dxq = ufl.dx(domain=msh, metadata={"quadrature_degree": opts.quadrature_degree})
                Fq = kf * J * ufl.conditional(ufl.gt(wcur, 0.0), wcur, 0.0) * wh * dxq
                self.prob_t = _Problem(self, F_lin + Fq, uh, bcs, a + ufl.derivative(Fq, uh, trial),
                                       lambda x, want_jac: self.springs_only(x, want_jac))
        if opts.krylov:      # compile the matrix-free Jacobian actions here, not in the solve
            for prob in [self.prob_bil] + ([self.prob_t] if sc["tensionless"] else []):
                prob.action = _Action(self, prob)
        self.time_build = time.perf_counter() - t_build0

        # point loads need mesh connectivity: keep what is needed
        self._fem, self._fpetsc, self._PETSc, self._dmesh = fem, fpetsc, PETSc, dmesh
        self._vertex_at = vertex_at
        self._spring_matrix()

    # ------------------------------------------------------------------
    def assemble_point_loads(self):
        """Vector of the point forces and moments (line loads and curvature are in the UFL form)."""
        sc, opts = self.sc, self.opts
        f = np.zeros(self.ndofs)
        msh = self.msh
        lam = opts.load_factor
        for ld in sc["loads"]:
            if ld["kind"] not in ("force", "moment"):
                continue
            fac = _case_factor(ld["case"], lam)
            P = fac * ld["value"]
            v = self._vertex_at(ld["at"])
            if ld["kind"] == "force":
                dw = self._fem.locate_dofs_topological(self.Ww, 0, v)
                direction = ld.get("direction", "radial")
                if not self.arch or direction == "radial":
                    f[dw] += self.sigma * P            # toward the foundation
                else:
                    du = self._fem.locate_dofs_topological(self.Wu, 0, v)
                    th = ld["at"]
                    # unit vectors at theta (crown up): inward (-sin, -cos), tangential
                    # (cos, -sin); vertical > 0 is (0, -1), horizontal > 0 is (1, 0)
                    cw, cu = {"tangential": (0.0, 1.0),
                              "vertical": (math.cos(th), math.sin(th)),
                              "horizontal": (-math.sin(th), math.cos(th))}[direction]
                    f[dw] += P * cw
                    f[du] += P * cu
            else:
                # point moment: work = M * rotation
                f += P * self._rotation_vector(ld["at"])
        f[self.bc_dofs] = 0.0
        self.f_point = f
        b = self._fpetsc.assemble_vector(self.L_form)
        self.load_norm = float(np.linalg.norm(b.array + f))

    def _rotation_vector(self, s):
        """g with rotation(s) = g . x: -w' (beam), -(u + w')/R (arch, w inward). The C0 P2
        test function's derivative jumps at a vertex; take it from the adjacent cell (at an
        end there is only one), averaging the two one-sided values at an interior vertex."""
        v = self._vertex_at(s)
        cells = self.msh.topology.connectivity(0, 1).links(int(v[0]))
        g = np.zeros(self.ndofs)
        for c in cells:
            dofs = np.asarray(self.Ww.dofmap.cell_dofs(int(c)))
            g[dofs] += lagrange_derivatives(self.coord[dofs], s) / len(cells)
        if self.arch:
            du = self._fem.locate_dofs_topological(self.Wu, 0, v)
            g[du] += 1.0
            g /= self.sc["R"]
        return -g

    def _spring_matrix(self):
        """Springs: energy 1/2 k (w - sigma s)^2 (+ 1/2 k u^2 on arches) + 1/2 k_r rotation^2,
        as a constant matrix S and vector fs: residual S x - fs."""
        import scipy.sparse as sp
        S = sp.lil_matrix((self.ndofs, self.ndofs))
        fs = np.zeros(self.ndofs)
        for s, sup in self.springs:
            v = self._vertex_at(s)
            k, kr = sup["stiffness"], sup["rotational_stiffness"]
            if k > 0:
                dw = int(self._fem.locate_dofs_topological(self.Ww, 0, v)[0])
                S[dw, dw] += k
                fs[dw] += k * self.sigma * sup["settlement"]
                if self.arch:
                    du = int(self._fem.locate_dofs_topological(self.Wu, 0, v)[0])
                    S[du, du] += k
            if kr > 0:
                g = self._rotation_vector(s)
                nz = np.nonzero(g)[0]
                for i in nz:
                    for j in nz:
                        S[i, j] += kr * g[i] * g[j]
        keep = np.ones(self.ndofs)
        keep[self.bc_dofs] = 0.0
        D = sp.diags(keep)
        self.S = (D @ S.tocsr() @ D).tocsr()
        fs[self.bc_dofs] = 0.0
        self.fs = fs

    def springs_only(self, x, want_jac=True):
        return self.S @ x - self.fs, (self.S if want_jac else None)

    # ------------------------------------------------------------------
    def foundation_exact(self, x, want_jac=True, bilateral=False):
        """Residual and Jacobian of the foundation, int [K_c max(d, 0) + K_t min(d, 0)] v with
        d = w - g (w in the user's sign: sigma * the inward w), exact per cell: d is quadratic
        on a cell (P2 w, g linear: its breakpoints are vertices), split at its roots, each piece
        integrated by 3-point Gauss (exact to degree 5: K linear x d quadratic x v quadratic).
        bilateral: K_t = K_c (the bonded foundation, and the linear start). Springs added."""
        import scipy.sparse as sp
        cells = self.found_cells
        sig = self.sigma
        dofs = self.cw[cells]            # (m, 3)
        xl = self.cx[cells, 0]
        hh = self.cx[cells, 2] - xl
        ga, gb = self.g_ab[cells, 0], self.g_ab[cells, 1]
        wv = sig * x[dofs]               # user w at t = 0, 1/2, 1
        dv = wv - np.stack([ga, 0.5 * (ga + gb), gb], axis=1)
        d0, dm, d1 = dv[:, 0], dv[:, 1], dv[:, 2]
        # d(t) = A t^2 + B t + C
        A = 2.0 * d1 - 4.0 * dm + 2.0 * d0
        B = 4.0 * dm - d1 - 3.0 * d0
        C = d0
        r1, r2 = quad_roots(A, B, C)
        r1 = np.where(np.isfinite(r1), np.clip(r1, 0.0, 1.0), 1.0)
        r2 = np.where(np.isfinite(r2), np.clip(r2, 0.0, 1.0), 1.0)
        br = np.stack([np.zeros_like(A), r1, r2, np.ones_like(A)], axis=1)
        br = np.sort(br, axis=1)                      # pieces [br0,br1],[br1,br2],[br2,br3]
        gp = np.array([-math.sqrt(0.6), 0.0, math.sqrt(0.6)])
        gw = np.array([5.0, 8.0, 5.0]) / 9.0
        J = self.sc["J"]
        Ka, Kb = self.Kc_ab[:, 0], self.Kc_ab[:, 1]
        Kt = self.Kt_cell
        Rloc = np.zeros((len(cells), 3))
        Jloc = np.zeros((len(cells), 3, 3)) if want_jac else None
        for p in range(3):
            ta, tb = br[:, p], br[:, p + 1]
            L = tb - ta
            tm = 0.5 * (ta + tb)
            dmid = (A * tm + B) * tm + C
            compressed = dmid > 0.0
            for q in range(3):
                t = tm + 0.5 * L * gp[q]
                phi = np.stack([2.0 * (t - 0.5) * (t - 1.0), 4.0 * t * (1.0 - t), 2.0 * t * (t - 0.5)], axis=1)
                dt = (A * t + B) * t + C
                Kc = Ka + (Kb - Ka) * t
                K = Kc if bilateral else np.where(compressed, Kc, Kt)
                fac = np.where(L > 0.0, K * J * hh * 0.5 * L * gw[q], 0.0)
                Rloc += (sig * fac * dt)[:, None] * phi
                if want_jac:
                    Jloc += fac[:, None, None] * phi[:, :, None] * phi[:, None, :]
        r = np.zeros(self.ndofs)
        np.add.at(r, dofs.ravel(), Rloc.ravel())
        r[self.bc_dofs] = 0.0
        r += self.S @ x - self.fs
        if not want_jac:
            return r, None
        rows = np.repeat(dofs, 3, axis=1).ravel()
        cols = np.tile(dofs, (1, 3)).ravel()
        Jm = sp.csr_matrix((Jloc.ravel(), (rows, cols)), shape=(self.ndofs, self.ndofs))
        keep = np.ones(self.ndofs)
        keep[self.bc_dofs] = 0.0
        D = sp.diags(keep)
        Jm = (D @ Jm @ D).tocsr() + self.S
        return r, Jm

    def _newton(self, problem, atol):
        """dolfinx NewtonSolver (incremental criterion) on `problem`, starting from self.uh."""
        from dolfinx.nls.petsc import NewtonSolver
        PETSc = self._PETSc
        solver = NewtonSolver(self.msh.comm, problem)
        solver.convergence_criterion = "incremental"
        solver.rtol = self.opts.step_tolerance
        solver.atol = atol
        solver.max_it = self.opts.max_newton
        solver.report = False
        solver.error_on_nonconvergence = False
        ksp = solver.krylov_solver
        if self.opts.krylov:
            # operator: matrix-free action (accurate); preconditioner: LU of the assembled
            # Jacobian (accurate only to ~eps*cond, which is all a preconditioner needs)
            from dolfinx.fem.petsc import create_matrix
            act = problem.action
            shell = PETSc.Mat().createPython([self.ndofs, self.ndofs], comm=PETSc.COMM_SELF)
            shell.setPythonContext(act)
            shell.setUp()
            Pmat = create_matrix(problem.a)
            solver.setJ(act.update, shell)
            solver.setP(problem.J, Pmat)
            ksp.setType("gmres")
            ksp.setTolerances(rtol=1e-12, atol=1e-300, max_it=60)
            ksp.setGMRESRestart(60)
            self._keep = (act, shell, Pmat)
        else:
            ksp.setType("preonly")
        ksp.getPC().setType("lu")
        ksp.getPC().setFactorSolverType(self.opts.lu)
        steps = []

        def update(slv, dx, x):
            steps.append(dx.norm())
            x.axpy(-1.0, dx)
        solver.set_update(update)
        n, converged = solver.solve(self.uh)
        if self.opts.verbose:
            xn = np.linalg.norm(self.uh.x.array)
            print("    newton |dx|/|x|: " + " ".join(f"{d / max(xn, 1e-300):.2e}" for d in steps), file=sys.stderr)
        if not converged:
            raise RuntimeError(f"Newton did not converge in {n} iterations")
        return n, steps

    def solve(self):
        """Bilateral (linear) solve, then, if tensionless, Newton from there. Returns x, info.

        Why the residual is assembled from the UFL form: the P2-CIP matrix of a fourth-order
        operator has condition number ~ N^4, and the rounding of its assembled entries alone
        perturbs a direct solution by ~ eps N^4 (about 1e-6 relative at N = 1600, 1e-3 at 6400,
        as a smooth, lowest-mode error that moves the contact limits). The form-assembled
        residual (FFCx kernels: exact-integer difference stencils times 1/h^k) does not have
        that loss, so Newton in correction form, x -= J^-1 F(x), with J's LU used only as an
        approximate inverse, converges to the discrete solution to ~1e-11 (iterative
        refinement). A plain direct solve is used nowhere."""
        self.uh.x.array[:] = 0.0
        self.uh.x.array[self.bc_dofs] = self.bc_values     # the settlements
        n_bil, steps_bil = self._newton(self.prob_bil, atol=1e-300)
        xnorm = float(np.linalg.norm(self.uh.x.array))
        info = {"bilateral_iterations": n_bil}
        prob = self.prob_bil
        if self.sc["tensionless"]:
            n, steps = self._newton(self.prob_t, atol=self.opts.step_tolerance * max(xnorm, 1e-300))
            rel = [d / max(np.linalg.norm(self.uh.x.array), 1e-300) for d in steps]
            info.update(newton_iterations=n, newton_steps=rel, newton_last_step=rel[-1] if rel else 0.0)
            prob = self.prob_t
        else:
            info.update(newton_iterations=0)
        x = self.uh.x.array.copy()
        # final residual, from the same assembly
        from dolfinx.fem.petsc import create_vector
        b = create_vector(prob.L)
        prob.F(self.uh.vector, b)
        info["residual"] = float(b.norm() / max(self.load_norm, 1e-300))
        info["residual_note"] = ("l2 norm of the form-assembled residual over that of the loads; its floor is the "
                                 "rounding of the fourth-order operator (~eps |K| |x|), mostly high-frequency and "
                                 "harmless; newton_last_step is the better measure of convergence")
        return x, info

    # ------------------------------------------------------------------
    def postprocess(self, x):
        sc = self.sc
        cx, cw = self.cx, self.cw
        wv = self.sigma * x[cw]          # the user's w (> 0 into the foundation)
        w0, wm, w1 = wv[:, 0], wv[:, 1], wv[:, 2]
        A = 2.0 * w1 - 4.0 * wm + 2.0 * w0
        B = 4.0 * wm - w1 - 3.0 * w0
        C = w0
        h = cx[:, 2] - cx[:, 0]
        # extremes: vertices, midpoints and stationary points of the cell parabolas
        cand_s = [cx[:, 0], cx[:, 2]]
        cand_w = [w0, w1]
        with np.errstate(divide="ignore", invalid="ignore"):
            ts = np.where(A != 0.0, -B / (2.0 * A), -1.0)
        inside = (ts > 0.0) & (ts < 1.0)
        cand_s.append(np.where(inside, cx[:, 0] + ts * h, cx[:, 0]))
        cand_w.append(np.where(inside, (A * ts + B) * ts + C, w0))
        cs = np.concatenate(cand_s)
        cwv = np.concatenate(cand_w)
        imax, imin = int(np.argmax(cwv)), int(np.argmin(cwv))
        # contact regions: where d = w - g > 0 on the foundation's pieces
        fc = self.found_cells
        ga, gb = self.g_ab[fc, 0], self.g_ab[fc, 1]
        dv = wv[fc] - np.stack([ga, 0.5 * (ga + gb), gb], axis=1)
        dA = 2.0 * dv[:, 2] - 4.0 * dv[:, 1] + 2.0 * dv[:, 0]
        dB = 4.0 * dv[:, 1] - dv[:, 2] - 3.0 * dv[:, 0]
        dC = dv[:, 0]
        r1, r2 = quad_roots(dA, dB, dC)
        scale = max(np.max(np.abs(wv)), np.max(np.abs(self.g_ab)), 1e-300)
        pieces = []
        for j, c in enumerate(fc):
            ts_ = sorted([0.0, 1.0] + [t for t in (r1[j], r2[j]) if 0.0 < t < 1.0])
            for ta, tb in zip(ts_[:-1], ts_[1:]):
                if tb <= ta:
                    continue
                tm = 0.5 * (ta + tb)
                dmid = (dA[j] * tm + dB[j]) * tm + dC[j]
                sa = cx[c, 0] + ta * h[c] if ta > 0.0 else cx[c, 0]
                sb = cx[c, 0] + tb * h[c] if tb < 1.0 else cx[c, 2]
                pieces.append((sa, sb, dmid > 1e-13 * scale))
        pieces.sort()
        regions = []
        for a, b, pos in pieces:
            if not pos:
                continue
            if regions and abs(a - regions[-1][1]) <= 1e-12 * (sc["s1"] - sc["s0"]):
                regions[-1][1] = b
            else:
                regions.append([a, b])
        # reaction K_c max(d, 0) + K_t min(d, 0), sampled at 9 points per foundation cell
        tt = np.linspace(0.0, 1.0, 9)
        dt = (dA[:, None] * tt + dB[:, None]) * tt + dC[:, None]
        Kc = self.Kc_ab[:, :1] + (self.Kc_ab[:, 1:] - self.Kc_ab[:, :1]) * tt
        if sc["tensionless"]:
            react = Kc * np.maximum(dt, 0.0) + self.Kt_cell[:, None] * np.minimum(dt, 0.0)
        else:
            react = Kc * dt
        max_reaction = float(max(0.0, react.max())) if len(fc) else 0.0

        def to_user(v):      # a limit at a key point (piece end, void edge): the scene's own number
            return sc["user_keys"].get(v, user_of(sc, v))
        positive = [[to_user(a), to_user(b)] for a, b in regions]
        if not sc["tensionless"]:
            # a bilateral foundation is bonded: it is in contact over its whole extent (its
            # pieces, merged where they touch), as liftoff reports it; where d > 0 is given separately
            contact = []
            for a, b, *_ in sc["segments"]:
                if contact and abs(a - contact[-1][1]) <= 1e-12 * (sc["s1"] - sc["s0"]):
                    contact[-1][1] = b
                else:
                    contact.append([a, b])
            contact = [[to_user(a), to_user(b)] for a, b in contact]
        else:
            contact = positive
        # w at every vertex and cell midpoint, in order along the member (for figures)
        order = np.argsort(np.concatenate([cx[:, 0], cx[:, 1]]))
        field_s = np.concatenate([cx[:, 0], cx[:, 1]])[order]
        field_w = np.concatenate([w0, wm])[order]
        last = int(np.argmax(cx[:, 2]))
        field_s, field_w = np.append(field_s, cx[last, 2]), np.append(field_w, w1[last])
        field_r = np.zeros_like(field_w)
        rf = np.zeros((len(cx), 2))
        rf[fc, 0], rf[fc, 1] = react[:, 0], react[:, 4]
        field_rc = np.concatenate([rf[:, 0], rf[:, 1]])[order]
        field_r[:-1] = field_rc
        field_r[-1] = react[list(fc).index(last), 8] if last in set(fc) else 0.0
        return {
            "fields": {"coordinate": [user_of(sc, float(v)) for v in field_s], "w": field_w.tolist(),
                       "reaction": field_r.tolist()},
            "contact_regions": contact,
            "w_positive_regions": positive,
            "w_max": float(cwv[imax]), "at_w_max": user_of(sc, float(cs[imax])),
            "w_min": float(cwv[imin]), "at_w_min": user_of(sc, float(cs[imin])),
            "max_reaction": max_reaction,
        }


def quad_roots(A, B, C):
    """Real roots of A t^2 + B t + C (arrays), NaN where none; stable formulas."""
    A = np.asarray(A, dtype=float)
    B = np.asarray(B, dtype=float)
    C = np.asarray(C, dtype=float)
    scale = np.maximum(np.maximum(np.abs(A), np.abs(B)), np.abs(C))
    lin = np.abs(A) <= 1e-14 * scale
    disc = B * B - 4.0 * A * C
    with np.errstate(divide="ignore", invalid="ignore"):
        sq = np.sqrt(np.where(disc >= 0.0, disc, np.nan))
        qq = -0.5 * (B + np.copysign(sq, B))
        ra = qq / A
        rb = C / qq
        rl = -C / B
    r1 = np.where(lin, rl, ra)
    r2 = np.where(lin, np.nan, rb)
    return r1, r2


def lagrange_derivatives(nodes, x0):
    nodes = np.asarray(nodes, dtype=float)
    m = len(nodes)
    d = np.zeros(m)
    for i in range(m):
        denom = np.prod([nodes[i] - nodes[j] for j in range(m) if j != i])
        s = 0.0
        for k in range(m):
            if k == i:
                continue
            s += np.prod([x0 - nodes[j] for j in range(m) if j not in (i, k)])
        d[i] = s / denom
    return d


# --------------------------------------------------------------------------------------------
# Driver
# --------------------------------------------------------------------------------------------

def solve_mesh(sc, xs, opts):
    t0 = time.perf_counter()
    model = Model(sc, xs, opts)           # mesh, spaces, form compilation (JIT, cached)
    t1 = time.perf_counter()
    model.assemble_point_loads()
    try:
        x, info = model.solve()
    except Exception as e:      # Newton or LU failure
        raise SolveFailure(f"{len(xs) - 1} elements: {e} (if the loads have no equilibrium on this "
                           f"foundation, e.g. they lift a member that only the foundation holds, none can be found)")
    t2 = time.perf_counter()
    out = model.postprocess(x)
    out.update(elements=model.n_elements, dofs=model.ndofs, time_s=t2 - t1, setup_s=t1 - t0, **info)
    if model.gauge:
        out["gauge"] = model.gauge
    return out


def flatten_limits(regions):
    return np.array([v for r in regions for v in r], dtype=float)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene")
    g = ap.add_mutually_exclusive_group()
    g.add_argument("--elements", type=int, help="number of elements (default: the scene's)")
    g.add_argument("--refine", action="store_true", help="uniform refinement until the contact limits settle")
    ap.add_argument("--start-elements", type=int, default=50, help="first mesh of --refine (default 50)")
    ap.add_argument("--max-elements", type=int, default=25600, help="last mesh of --refine at most (default 25600)")
    ap.add_argument("--tolerance", type=float, default=1e-6,
                    help="--refine stops when the limits change by less than this times the member length")
    ap.add_argument("--penalty-scale", type=float, default=1.0, help="multiplies the CIP/Nitsche penalty alpha")
    ap.add_argument("--alpha", type=float, default=8.0, help="base CIP/Nitsche penalty (default 8)")
    ap.add_argument("--u-degree", type=int, default=3, help="Lagrange degree of u for arches (default 3)")
    ap.add_argument("--foundation-integration", choices=("exact", "quadrature"), default="exact")
    ap.add_argument("--quadrature-degree", type=int, default=8, help="for --foundation-integration quadrature")
    ap.add_argument("--no-krylov", dest="krylov", action="store_false",
                    help="Newton steps by the LU of the assembled Jacobian alone (no matrix-free GMRES)")
    ap.add_argument("--lu", default="mumps", choices=("mumps", "superlu", "umfpack", "petsc"),
                    help="PETSc LU package for the Newton steps (default mumps)")
    ap.add_argument("--max-newton", type=int, default=50)
    ap.add_argument("--step-tolerance", type=float, default=1e-10,
                    help="Newton stops when |dx| <= this * |x| (default 1e-10)")
    ap.add_argument("--verbose", action="store_true", help="print the Newton history")
    ap.add_argument("--load-factor", type=float, default=1.0, help="lambda multiplying the live loads")
    ap.add_argument("--json", metavar="OUT.json", help="write the result here ('-' = stdout)")
    ap.add_argument("--repeat", type=int, default=1,
                    help="with --elements: solve the mesh this many times and report the median time_s "
                         "(each run's in time_s_runs); for benchmarks (verification/bench)")
    opts = ap.parse_args(argv)
    logging.disable(logging.INFO)
    import dolfinx.log
    dolfinx.log.set_log_level(dolfinx.log.LogLevel.ERROR)     # our own messages say it

    t_start = time.perf_counter()
    try:
        sc = read_scene(opts.scene)
    except (SceneError, tomllib.TOMLDecodeError, OSError) as e:
        print(f"{opts.scene}: {e}", file=sys.stderr)
        return 2
    if opts.foundation_integration == "quadrature" and not sc["plain"]:
        print(f"{opts.scene}: --foundation-integration quadrature covers one constant foundation piece "
              f"without gap, tension modulus or side (use the default, exact)", file=sys.stderr)
        return 2
    kp = key_points(sc)

    # warm-up: compile all forms once on the coarsest mesh so that time_s excludes the JIT
    t_w = time.perf_counter()
    Model(sc, vertices(kp, base_allocation(kp, len(kp) - 1)), opts)
    compile_s = time.perf_counter() - t_w

    result = {
        "method": "dolfinx-penalty",
        "scene": opts.scene,
        "structure": sc["kind"],
        "coordinate": "x" if sc["kind"] == "beam" else "theta_deg",
        "tensionless": sc["tensionless"],
        "k": sc["k"],
        "load_factor": opts.load_factor,
        "axial_force": axial_force(sc, opts.load_factor) if sc["kind"] == "beam" else None,
        "initial_shape": sc["w0"] is not None,
        "discretisation": {
            "w": "P2 Lagrange, C0 interior penalty (symmetric), Nitsche for clamped w'",
            "u": f"P{opts.u_degree} Lagrange" if sc["kind"] == "arch" else None,
            "alpha": opts.alpha * opts.penalty_scale,
            "penalty_scale": opts.penalty_scale,
            "foundation_integration": opts.foundation_integration
            + ("" if opts.foundation_integration == "exact" else f" (degree {opts.quadrature_degree})"),
            "newton": ("dolfinx NewtonSolver (incremental criterion), form-assembled residual, "
                       + (f"GMRES on the matrix-free Jacobian action, preconditioned by PETSc LU ({opts.lu})"
                          if opts.krylov else f"PETSc LU ({opts.lu}) of the assembled Jacobian")),
        },
        "sign_convention": "w > 0 into the foundation",
        "compile_s": compile_s,
    }
    if opts.refine:
        alloc0 = base_allocation(kp, opts.start_elements)
        levels = []
        level = 0
        tol_abs = opts.tolerance * sc["user_span"]
        converged = False
        while True:
            alloc = alloc0 * 2 ** level
            if alloc.sum() > opts.max_elements:
                break
            try:
                res = solve_mesh(sc, vertices(kp, alloc), opts)
            except SolveFailure as e:
                if not levels:
                    print(f"{opts.scene}: {e}", file=sys.stderr)
                    return 3
                result["refinement_stopped"] = str(e)
                print(f"  stopped: {e}", file=sys.stderr)
                break
            levels.append(res)
            print(f"  {res['elements']:7d} elements  limits {res['contact_regions']}  "
                  f"newton {res['newton_iterations']}  {res['time_s']:.3f} s", file=sys.stderr)
            if len(levels) >= 2:
                a = flatten_limits(levels[-1]["contact_regions"])
                b = flatten_limits(levels[-2]["contact_regions"])
                if a.shape == b.shape and np.max(np.abs(a - b), initial=0.0) < tol_abs and len(levels) >= 3:
                    converged = True
                    break
            level += 1
        final = levels[-1]
        result.update({k: final[k] for k in final})
        result["refinement"] = [{"elements": r["elements"], "contact_regions": r["contact_regions"],
                                 "w_max": r["w_max"], "w_min": r["w_min"], "max_reaction": r["max_reaction"],
                                 "newton_iterations": r["newton_iterations"], "time_s": r["time_s"]}
                                for r in levels]
        result["refinement_converged"] = converged
        result["refinement_tolerance"] = tol_abs
        order, err, extrap, per_limit = richardson(levels)
        if err is None and flatten_limits(final["contact_regions"]).size:
            # no Richardson estimate (fewer than three meshes, or the number of limits changed
            # among the last three): fall back to the last change if comparable, else the
            # member length, and say so
            a = flatten_limits(levels[-1]["contact_regions"])
            b = flatten_limits(levels[-2]["contact_regions"]) if len(levels) >= 2 else np.zeros(0)
            err = float(np.max(np.abs(a - b))) if a.shape == b.shape else float(sc["user_span"])
            result["estimate_note"] = "no Richardson estimate: " + (
                "last change used" if a.shape == b.shape else "contact topology still changing; member length used")
        result["observed_order"] = order
        result["estimated_limit_error"] = err
        result["extrapolated_contact_regions"] = extrap
        result["per_limit_order"] = per_limit
        result["last_change"] = (float(np.max(np.abs(flatten_limits(levels[-1]["contact_regions"])
                                                      - flatten_limits(levels[-2]["contact_regions"])), initial=0.0))
                                 if len(levels) >= 2 and len(levels[-1]["contact_regions"]) == len(levels[-2]["contact_regions"])
                                 else None)
    else:
        n = opts.elements or sc["scene_elements"]
        runs = []
        try:
            for _ in range(max(1, opts.repeat)):
                res = solve_mesh(sc, vertices(kp, base_allocation(kp, n)), opts)
                runs.append(res["time_s"])
        except SolveFailure as e:
            print(f"{opts.scene}: {e}", file=sys.stderr)
            return 3
        if len(runs) > 1:
            res["time_s"] = float(np.median(runs))
            res["time_s_runs"] = runs
        result.update(res)
        result["refinement"] = [{"elements": res["elements"], "contact_regions": res["contact_regions"]}]
        result["observed_order"] = None
        result["estimated_limit_error"] = None
    result["wall_s"] = time.perf_counter() - t_start

    text = json.dumps(result, indent=2)
    if opts.json == "-":
        print(text)
    elif opts.json:
        with open(opts.json, "w") as fh:
            fh.write(text + "\n")
    if opts.json != "-":
        print(summary(result))
    return 0


def richardson(levels):
    """Observed order and error estimate of the contact limits from the last three meshes."""
    if len(levels) < 3:
        return None, None, None, None
    q = [flatten_limits(r["contact_regions"]) for r in levels[-3:]]
    if not (q[0].shape == q[1].shape == q[2].shape) or q[0].size == 0:
        return None, None, None, None
    d1 = np.abs(q[1] - q[0])
    d2 = np.abs(q[2] - q[1])
    D1, D2 = float(d1.max()), float(d2.max())
    per = []
    for a, b in zip(d1, d2):
        per.append(float(math.log2(a / b)) if a > 0 and b > 0 else None)
    if D1 <= 0.0 or D2 <= 0.0:
        return None, D2, [list(map(float, q[2].reshape(-1, 2)[i])) for i in range(q[2].size // 2)], per
    p = math.log2(D1 / D2)
    ratio = 2.0 ** p
    err = D2 / (ratio - 1.0) if ratio > 1.0 else D2
    # per-limit Richardson extrapolation with the observed global order
    ext = q[2] + (q[2] - q[1]) / (ratio - 1.0) if ratio > 1.0 else q[2]
    ext = ext.reshape(-1, 2)
    return p, err, [[float(a), float(b)] for a, b in ext], per


def summary(r):
    lines = [f"dolfinx-penalty: {r['scene']} ({r['structure']}), k = {r['k']:g}, tensionless = {r['tensionless']}"]
    unit = "" if r["structure"] == "beam" else " deg"
    regs = ", ".join(f"[{a:.9g}, {b:.9g}]{unit}" for a, b in r["contact_regions"]) or "none"
    lines.append(f"  contact       {regs}")
    lines.append(f"  w max         {r['w_max']:.9e} at {r['at_w_max']:.9g}{unit}")
    lines.append(f"  w min         {r['w_min']:.9e} at {r['at_w_min']:.9g}{unit}")
    lines.append(f"  max reaction  {r['max_reaction']:.9e}")
    lines.append(f"  mesh          {r['elements']} elements, {r.get('dofs')} dofs, Newton {r.get('newton_iterations')} it, "
                 f"residual {r.get('residual', float('nan')):.2e}, solve {r['time_s']:.3f} s")
    if r.get("observed_order") is not None or r.get("estimated_limit_error") is not None:
        lines.append(f"  refinement    order {r['observed_order']}, estimated limit error {r['estimated_limit_error']}")
    if r.get("gauge"):
        lines.append(f"  gauge         {r['gauge']}")
    return "\n".join(lines)


if __name__ == "__main__":
    sys.exit(main())

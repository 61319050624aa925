#!/usr/bin/python3
"""Independent dolfinx reference for issue 16: von Karman beams and shallow arches (a beam with a
stress-free initial shape w0) on a Winkler foundation, bilateral or tensionless, traced through limit
points by displacement control of the crown.

    /usr/bin/python3 verification/dolfinx/von_karman_reference.py SCENE.toml \
        [--elements 128] [--crown-max D] [--steps 60] [--json OUT.json | --json -]

It shares no code with liftoff (only `quad_roots` of penalty_reference.py, the stable quadratic
formula). The tests of this model against closed forms are in check_issue16.py.

Model (liftoff's signs: w > 0 into the foundation, q > 0 toward it, N > 0 in tension). Energy

    Pi = int EI/2 w''^2 + EA/2 eps^2 dx + foundation - lambda int q w dx,
    eps = u' + w0' w' + w'^2/2,

w the deflection from the stress-free initial shape w0 (positive toward the foundation; the shallow
arch rising away from its bedding is w0 = -a sin(pi x/L), scene key `initial_shape = { shape =
"half_sine", amplitude = -a }`), u the axial displacement. The foundation reacts to w: k w
(bilateral) or k max(w, 0) (tensionless), i.e. the ground follows the initial shape.

Discretisation (not liftoff's Hermite cubics + LCP):
  * w: continuous P2 with the symmetric C0 interior penalty (alpha = 8, as penalty_reference.py):
    broken w'' in the cells, -{EI w''}[[w']] consistency and alpha EI/h [[w']]^2 on interior vertices.
  * u: continuous P3. The membrane strain of a P2 w is discontinuous P2 (w0' w' and w'^2/2), and u'
    of a continuous P3 spans every discontinuous P2 function, so inextensional deformations
    (eps = 0) are representable and the element does not lock. P2 u (u' discontinuous P1) cannot
    follow w'^2/2: membrane locking with the factor EA L^2/EI (h/L)^2 in the stiffness.
  * w0 enters as the exact UFL expression (sines), integrated with degree 8.
  * foundation: int K max(w, 0) v integrated exactly per cell (the quadratic w split at its roots,
    3-point Gauss per piece); its Jacobian is int K v_i v_j over w > 0, so the discrete problem is
    C^1 and Newton converges quadratically. Bilateral: the same code with K on both sides.
  * ends: pinned (w = 0 strong, M = 0 natural) with axial = "restrained" (u = 0) or "free" (N = 0);
    with both ends free axially u is held at the left end as a gauge.
  * continuation: displacement control of the crown (x = L/2, a vertex): the crown deflection delta
    is prescribed and lambda is an unknown (bordered Newton: [[J, -f], [e_c^T, 0]], sparse LU),
    predictor the secant through the last two points, so limit points in lambda are passed.
    A Newton failure, or a corrector larger than the last step (Newton left the branch), halves the
    step (6 times at most); where the crown deflection itself turns back
    along the path, crown control cannot follow and the script says so (exit 3). `--control
    arclength` then: after a first crown-controlled step, steps of that step's length in
    (x_free, s lambda) (s equalising both parts of the first step) along the secant, with the
    linear constraint t . (x, s lambda) = t . previous + h (same bordered Newton), halved on a
    failure; it stops at crown_max or after 8 * steps steps.
  * limit points: the extrema of lambda along the path, located by bisection within a step on the
    sign of the exact slope d lambda/d parameter (the bordered tangent); stability: the number of negative eigenvalues of the
    tangent stiffness on the free dofs (dense, up to 2000 dofs) at every step; a change is located
    by bisection and called `limit_point` if it falls in the step of an extremum of lambda,
    `contact_change` if it falls on a contact event (a tensionless tangent jumps there), else
    `bifurcation` (next to a bifurcation the bordered matrix is singular as well, so the bisection
    stops when Newton fails there and reports the bracket reached).
  * contact events: a change of the contact set's topology (number of regions w > 0, ends in
    contact) between two steps, located by bisection in delta (30 halvings of the step).
Exit codes: 0 solved, 2 bad scene or command line, 3 Newton failed.
"""

import argparse
import json
import logging
import math
import os
import sys
import time
import tomllib
from dataclasses import dataclass, field

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from penalty_reference import quad_roots  # noqa: E402  (the stable quadratic formula only)

logging.disable(logging.INFO)  # the JIT compiler's build log
ALPHA = 8.0
QDEG = 8
GAUSS_T = np.array([0.5 - math.sqrt(15.0) / 10.0, 0.5, 0.5 + math.sqrt(15.0) / 10.0])
GAUSS_W = np.array([5.0, 8.0, 5.0]) / 18.0


class SceneError(Exception):
    pass


class SolveFailure(Exception):
    pass


@dataclass
class Problem:
    """A von Karman beam: w0 = sum of amp * sin(n pi x/L) plus optional bumps; load q(x) * lambda."""
    L: float
    EI: float
    EA: float
    k: float = 0.0
    tensionless: bool = False
    sines: list = field(default_factory=list)     # initial shape [(n, amplitude)]
    bumps: list = field(default_factory=list)     # initial shape [(amplitude, centre, length)]
    load_sines: list = field(default_factory=list)  # line load [(n, q_n)]: q_n sin(n pi x/L)
    uniform: list = field(default_factory=list)   # line load [(value, from, to)]
    forces: list = field(default_factory=list)    # point forces [(at, value)] (at a vertex)
    axial_left: str = "restrained"
    axial_right: str = "restrained"


# ---------------------------------------------------------------------------------------------
# scene reading (the keys of liftoff's src/scene/README.md; only what this model needs, the rest refused)

def _number(table, key, where, required=True, default=None):
    v = table.get(key, default)
    if v is None:
        if required:
            raise SceneError(f"key '{where}.{key}': required")
        return None
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise SceneError(f"key '{where}.{key}': expected a finite number")
    return float(v)


def _known(table, keys, where):
    for key in table:
        if key not in keys:
            raise SceneError(f"key '{where}.{key}': not read by the von Karman reference")


# The scene's top-level tables this reference reads; any other is refused by read_scene.
TABLES = ("structure", "supports", "foundation", "geometry", "loads", "solve", "output")


def read_scene(path):
    try:
        with open(path, "rb") as fh:
            raw = tomllib.load(fh)
    except (OSError, tomllib.TOMLDecodeError) as e:
        raise SceneError(f"cannot read: {e}")
    _known(raw, TABLES, "scene")
    st = raw.get("structure", {})
    _known(st, ("kind", "length", "EI", "EA", "theory"), "structure")
    if st.get("kind", "beam") != "beam":
        raise SceneError("key 'structure.kind': expected \"beam\" (the von Karman reference reads beams)")
    if st.get("theory", "von_karman") != "von_karman":
        raise SceneError("key 'structure.theory': expected \"von_karman\" (linear scenes: penalty_reference.py)")
    p = Problem(L=_number(st, "length", "structure"), EI=_number(st, "EI", "structure"),
                EA=_number(st, "EA", "structure"))
    if min(p.L, p.EI, p.EA) <= 0:
        raise SceneError("key 'structure': expected positive length, EI and EA")
    sup = raw.get("supports", {})
    _known(sup, ("left", "right"), "supports")
    for end in ("left", "right"):
        v = sup.get(end, "pinned")
        v = {"kind": v} if isinstance(v, str) else v
        if not isinstance(v, dict):
            raise SceneError(f"key 'supports.{end}': expected a string or a table {{ kind, axial }}")
        _known(v, ("kind", "axial"), f"supports.{end}")
        if v.get("kind") != "pinned":
            raise SceneError(f"key 'supports.{end}.kind': expected \"pinned\" (the only end read here)")
        axial = v.get("axial", "restrained")
        if axial not in ("restrained", "free"):
            raise SceneError(f"key 'supports.{end}.axial': expected \"restrained\" or \"free\"")
        setattr(p, "axial_" + end, axial)
    fd = raw.get("foundation")
    if fd is not None:
        _known(fd, ("modulus", "k", "tensionless"), "foundation")
        p.k = _number(fd, "modulus" if "modulus" in fd else "k", "foundation")
        if p.k < 0:
            raise SceneError("key 'foundation.modulus': expected >= 0")
        t = fd.get("tensionless", True)
        if not isinstance(t, bool):
            raise SceneError("key 'foundation.tensionless': expected true or false")
        p.tensionless = t
    geo = raw.get("geometry", {})
    _known(geo, ("initial_shape",), "geometry")
    shape = geo.get("initial_shape")
    if shape is not None:
        where = "geometry.initial_shape"
        if not isinstance(shape, dict) or shape.get("shape") not in ("half_sine", "bump"):
            raise SceneError(f"key '{where}': expected {{ shape = \"half_sine\" | \"bump\", amplitude, ... }}")
        if shape["shape"] == "half_sine":
            _known(shape, ("shape", "amplitude"), where)
            p.sines.append((1, _number(shape, "amplitude", where)))
        else:
            _known(shape, ("shape", "amplitude", "at", "length"), where)
            a, x0, l = (_number(shape, key, where) for key in ("amplitude", "at", "length"))
            if l <= 0 or x0 - l / 2 < 0 or x0 + l / 2 > p.L:
                raise SceneError(f"key '{where}': expected a bump of positive length within the member")
            p.bumps.append((a, x0, l))
    loads = raw.get("loads", [])
    if not isinstance(loads, list):
        raise SceneError("key 'loads': expected an array of tables")
    for i, ld in enumerate(loads):
        where = f"loads[{i}]"
        kind = ld.get("kind")
        if kind == "uniform":
            _known(ld, ("kind", "value", "from", "to", "case"), where)
            p.uniform.append((_number(ld, "value", where), _number(ld, "from", where, False, 0.0),
                              _number(ld, "to", where, False, p.L)))
        elif kind == "force":
            _known(ld, ("kind", "value", "at", "case"), where)
            p.forces.append((_number(ld, "at", where), _number(ld, "value", where)))
        elif kind == "sine":
            # q_n sin(n pi x / L): this script's own load kind (the closed forms' load)
            _known(ld, ("kind", "value", "n", "case"), where)
            p.load_sines.append((int(_number(ld, "n", where, False, 1)), _number(ld, "value", where)))
        else:
            raise SceneError(f"key '{where}.kind': expected \"uniform\", \"force\" or \"sine\"")
    return p, raw.get("solve", {})


# ---------------------------------------------------------------------------------------------
# the discrete model

class Model:
    def __init__(self, p: Problem, n: int, u_degree=3):
        import ufl
        from mpi4py import MPI
        from dolfinx import fem, mesh as dmesh
        if n % 2:
            raise ValueError("an even number of elements (the crown is a vertex)")
        self.p, self.n = p, n
        self.fem = fem
        xs = np.linspace(0.0, p.L, n + 1)
        cells = np.stack([np.arange(n), np.arange(1, n + 1)], axis=1).astype(np.int64)
        domain = ufl.Mesh(ufl.VectorElement("Lagrange", ufl.interval, 1))
        msh = dmesh.create_mesh(MPI.COMM_SELF, cells, xs.reshape(-1, 1), domain)
        Pu = ufl.FiniteElement("Lagrange", msh.ufl_cell(), u_degree)
        Pw = ufl.FiniteElement("Lagrange", msh.ufl_cell(), 2)
        W = fem.FunctionSpace(msh, ufl.MixedElement([Pu, Pw]))
        self.ndofs = W.dofmap.index_map.size_local * W.dofmap.index_map_bs
        coord = np.full(self.ndofs, np.nan)
        is_w = np.zeros(self.ndofs, dtype=bool)
        for i, flag in ((0, False), (1, True)):
            Vc, cmap = W.sub(i).collapse()
            coord[np.asarray(cmap)] = Vc.tabulate_dof_coordinates()[:, 0]
            is_w[np.asarray(cmap)] = flag
        nc = msh.topology.index_map(1).size_local
        cw = np.array([W.sub(1).dofmap.cell_dofs(c) for c in range(nc)], dtype=np.int64)
        cw = np.take_along_axis(cw, np.argsort(coord[cw], axis=1), axis=1)
        self.cw, self.cx = cw, coord[cw]
        tol = 1e-9 * p.L

        def dofs_at(x, w):
            return np.nonzero((np.abs(coord - x) < tol) & (is_w == w))[0]
        held = [dofs_at(0.0, True), dofs_at(p.L, True)]
        if p.axial_left == "restrained":
            held.append(dofs_at(0.0, False))
        if p.axial_right == "restrained":
            held.append(dofs_at(p.L, False))
        if p.axial_left == "free" and p.axial_right == "free":
            held.append(dofs_at(0.0, False))     # gauge: rigid axial motion
        held = np.unique(np.concatenate(held))
        self.free = np.setdiff1d(np.arange(self.ndofs), held)
        self.crown = dofs_at(p.L / 2, True)
        assert len(self.crown) == 1
        self.crown = int(self.crown[0])
        self.coord, self.is_w = coord, is_w

        U = fem.Function(W)
        self.U = U
        u, w = ufl.split(U)
        V = ufl.TestFunction(W)
        dU = ufl.TrialFunction(W)
        x = ufl.SpatialCoordinate(msh)[0]
        # w0' (the initial shape enters the strain only through its slope), exact
        w0p = fem.Constant(msh, 0.0)
        for m, a in p.sines:
            w0p = w0p + a * m * math.pi / p.L * ufl.cos(m * math.pi * x / p.L)
        for a, x0, l in p.bumps:
            inside = ufl.And(ufl.gt(x, x0 - l / 2), ufl.lt(x, x0 + l / 2))
            w0p = w0p + ufl.conditional(inside, -a * math.pi / l * ufl.sin(math.pi * (x - x0) / l), 0.0)
        dxq = ufl.dx(metadata={"quadrature_degree": QDEG})
        h = ufl.CellDiameter(msh)
        h_avg = (h("+") + h("-")) / 2
        nrm = ufl.FacetNormal(msh)
        EI, EA = fem.Constant(msh, p.EI), fem.Constant(msh, p.EA)
        wxx = w.dx(0).dx(0)
        jump_w1 = ufl.jump(ufl.grad(w), nrm)
        eps = u.dx(0) + w0p * w.dx(0) + w.dx(0) ** 2 / 2
        energy = (EI / 2 * wxx ** 2 * ufl.dx - EI * ufl.avg(wxx) * jump_w1 * ufl.dS
                  + ALPHA * EI / (2 * h_avg) * jump_w1 ** 2 * ufl.dS + EA / 2 * eps ** 2 * dxq)
        F = ufl.derivative(energy, U, V)
        self.F = fem.form(F)
        self.J = fem.form(ufl.derivative(F, U, dU))
        self.N_form = fem.form(EA * eps / p.L * dxq)
        self.A2_form = fem.form(2.0 / p.L * w * ufl.sin(2 * math.pi * x / p.L) * dxq)
        # the reference load (lambda = 1)
        v_w = ufl.split(V)[1]
        q = fem.Constant(msh, 0.0)
        for m, qn in p.load_sines:
            q = q + qn * ufl.sin(m * math.pi * x / p.L)
        for val, a, b in p.uniform:
            q = q + ufl.conditional(ufl.And(ufl.ge(x, a), ufl.le(x, b)), val, 0.0)
        self.f = self._vector(fem.form(q * v_w * dxq))
        for at, val in p.forces:
            d = dofs_at(at, True)
            if len(d) != 1:
                raise SceneError(f"a point force at x = {at} is not at a vertex of the {n}-element mesh")
            self.f[d] += val
        self.x = np.zeros(self.ndofs)

    def _vector(self, form):
        import dolfinx.fem.petsc as fpetsc
        b = fpetsc.assemble_vector(form)
        out = b.array.copy()
        b.destroy()
        return out

    def _matrix(self, form):
        import dolfinx.fem.petsc as fpetsc
        import scipy.sparse as sp
        A = fpetsc.assemble_matrix(form)
        A.assemble()
        indptr, indices, data = A.getValuesCSR()
        out = sp.csr_matrix((data.copy(), indices.copy(), indptr.copy()), shape=(self.ndofs, self.ndofs))
        A.destroy()
        return out

    def _set(self, x):
        self.U.x.array[:] = x

    def foundation(self, x):
        """int K max(w,0) v (K on both sides if bilateral), exact per cell, and its Jacobian."""
        import scipy.sparse as sp
        p = self.p
        if p.k == 0.0:
            return np.zeros(self.ndofs), sp.csr_matrix((self.ndofs, self.ndofs))
        wl, wm, wr = (x[self.cw[:, i]] for i in range(3))
        hc = self.cx[:, 2] - self.cx[:, 0]
        A, B, C = 2 * wl - 4 * wm + 2 * wr, -3 * wl + 4 * wm - wr, wl
        r1, r2 = quad_roots(A, B, C)
        cuts = [np.where((r > 0) & (r < 1), r, 1.0) for r in (r1, r2)]
        bp = np.sort(np.stack([np.zeros_like(wl), cuts[0], cuts[1], np.ones_like(wl)], axis=1), axis=1)
        res = np.zeros((len(wl), 3))
        jac = np.zeros((len(wl), 3, 3))
        for j in range(3):
            ta, tb = bp[:, j], bp[:, j + 1]
            tm = (ta + tb) / 2
            wmid = A * tm ** 2 + B * tm + C
            Kpiece = np.full_like(wl, p.k) if not p.tensionless else np.where(wmid > 0, p.k, 0.0)
            for tg, wg in zip(GAUSS_T, GAUSS_W):
                t = ta + (tb - ta) * tg
                N = np.stack([2 * t * t - 3 * t + 1, 4 * t * (1 - t), 2 * t * t - t], axis=1)
                wt = (Kpiece * (tb - ta) * hc * wg)[:, None]
                wval = (A * t * t + B * t + C)[:, None]
                res += wt * wval * N
                jac += wt[:, :, None] * N[:, :, None] * N[:, None, :]
        r = np.zeros(self.ndofs)
        np.add.at(r, self.cw, res)
        rows = np.repeat(self.cw, 3, axis=1).ravel()
        cols = np.tile(self.cw, (1, 3)).ravel()
        Jf = sp.csr_matrix((jac.ravel(), (rows, cols)), shape=(self.ndofs, self.ndofs))
        return r, Jf

    def residual(self, x, lam, want_jac=True):
        self._set(x)
        rf, Jf = self.foundation(x)
        R = self._vector(self.F) + rf - lam * self.f
        return R, (self._matrix(self.J) + Jf) if want_jac else None

    def _bordered(self, J, row):
        """[[J_ff, -f], [row]] with row = (vector over the free dofs, coefficient of lambda)."""
        import scipy.sparse as sp
        fr = self.free
        col = sp.csr_matrix(-self.f[fr].reshape(-1, 1))
        r = sp.csr_matrix(np.asarray(row[0], dtype=float).reshape(1, -1))
        corner = sp.csr_matrix([[float(row[1])]])
        return sp.bmat([[J[fr][:, fr], col], [r, corner]]).tocsc()

    def crown_row(self):
        e = np.zeros(len(self.free))
        e[int(np.searchsorted(self.free, self.crown))] = 1.0
        return e, 0.0

    def solve(self, x, lam, delta=None, tol=1e-10, max_it=30, constraint=None):
        """Newton from (x, lam): load control (delta and constraint None), crown displacement control
        (x_crown = delta), or a linear constraint (vector over the free dofs, coefficient of
        lambda, value): row . x_free + coefficient * lambda = value (the arc-length step)."""
        import scipy.sparse.linalg as spla
        fr = self.free
        fscale = max(np.abs(self.f).max(), 1e-300)
        if delta is not None:
            constraint = self.crown_row() + (delta,)
        x = x.copy()
        for it in range(max_it):
            R, J = self.residual(x, lam)
            if constraint is None:
                step = spla.spsolve(J[fr][:, fr].tocsc(), -R[fr])
                dlam = 0.0
            else:
                K = self._bordered(J, constraint[:2])
                gap = constraint[2] - (constraint[0] @ x[fr] + constraint[1] * lam)
                sol = spla.spsolve(K, np.concatenate([-R[fr], [gap]]))
                step, dlam = sol[:-1], sol[-1]
            x[fr] += step
            lam += dlam
            size = max(np.abs(x).max(), 1e-300)
            if np.abs(step).max() <= tol * size and abs(dlam) <= tol * max(abs(lam), 1.0):
                R, _ = self.residual(x, lam, want_jac=False)
                return x, lam, it + 1, float(np.abs(R[fr]).max() / fscale)
            if not np.all(np.isfinite(step)):
                break
        raise SolveFailure(f"Newton did not converge in {max_it} iterations (lambda {lam:.6g})")

    def slope(self, x, lam, row=None):
        """d lambda / d parameter along the path whose parameter is row . (x_free, lambda) (default:
        the crown deflection), at a converged (x, lam): the bordered tangent."""
        import scipy.sparse.linalg as spla
        _, J = self.residual(x, lam)
        rhs = np.zeros(len(self.free) + 1)
        rhs[-1] = 1.0
        return float(spla.spsolve(self._bordered(J, row or self.crown_row()), rhs)[-1])

    # ---- output quantities ----
    def crown_deflection(self, x):
        return float(x[self.crown])

    def thrust(self, x):
        self._set(x)
        return float(self.fem.assemble_scalar(self.N_form))

    def second_mode(self, x):
        self._set(x)
        return float(self.fem.assemble_scalar(self.A2_form))

    def contact(self, x, rel=1e-12):
        """Regions where w > 0 (in x), from the roots of the P2 w on each cell."""
        wl, wm, wr = (x[self.cw[:, i]] for i in range(3))
        A, B, C = 2 * wl - 4 * wm + 2 * wr, -3 * wl + 4 * wm - wr, wl
        r1, r2 = quad_roots(A, B, C)
        scale = max(np.abs(x[self.is_w]).max(), 1e-300)
        pieces = []
        for c in range(len(wl)):
            ts = sorted([0.0, 1.0] + [float(r) for r in (r1[c], r2[c]) if 0 < r < 1])
            xa, xb = self.cx[c, 0], self.cx[c, 2]
            for ta, tb in zip(ts, ts[1:]):
                tm = (ta + tb) / 2
                pos = A[c] * tm * tm + B[c] * tm + C[c] > rel * scale
                a, b = xa + ta * (xb - xa), xa + tb * (xb - xa)
                if pieces and pieces[-1][2] == pos:
                    pieces[-1][1] = b
                else:
                    pieces.append([a, b, pos])
        return [(float(a), float(b)) for a, b, pos in pieces if pos]

    def index(self, x, lam, max_dofs=2000):
        """Negative eigenvalues of the tangent stiffness on the free dofs (dense; None beyond max_dofs)."""
        if len(self.free) > max_dofs:
            return None
        _, J = self.residual(x, lam)
        Jff = J[self.free][:, self.free].toarray()
        return int(np.sum(np.linalg.eigvalsh((Jff + Jff.T) / 2) < 0.0))

    def signature(self, x, lam=None):
        """The contact set's topology: number of regions and whether the ends are in contact."""
        reg = self.contact(x)
        tol = 1e-9 * self.p.L
        return (len(reg), bool(reg and reg[0][0] < tol), bool(reg and reg[-1][1] > self.p.L - tol))


# ---------------------------------------------------------------------------------------------
# continuation

def trace(model, crown_max, steps, locate_events=True, refine_limits=True, stability=True, control="crown"):
    """Path from zero load to crown deflection crown_max: `crown` control in `steps` equal steps of
    the crown deflection, or `arclength` (the first step by crown control, then steps of the same
    length in (x, s lambda), s making both parts of that first step equal; at most 8 * steps).
    Returns the path (crown, lambda, N, A2, contact regions, negative eigenvalues of the tangent
    stiffness per point), the limit points (extrema of lambda, refined), the contact events and the
    stability events (a change of the number of negative eigenvalues, located by bisection:
    `limit_point` where it falls in the step of an extremum of lambda, else `bifurcation`; skipped
    with stability=False or beyond 2000 free dofs, since the eigenvalues are dense)."""
    index = (lambda xx, ll: model.index(xx, ll)) if stability else (lambda xx, ll: None)
    fr = model.free
    ds = crown_max / steps
    x = np.zeros(model.ndofs)
    path = [(0.0, 0.0, x.copy())]   # (crown, lambda, state)
    steps_taken = []                 # per step: (row, parameter at its start, at its end)
    if control == "crown":
        row = model.crown_row()
        for i in range(1, steps + 1):
            x, lam = _advance(model, path, i * ds)
            path.append((i * ds, lam, x.copy()))
            steps_taken.append((row, (i - 1) * ds, i * ds))
    elif control == "arclength":
        x, lam, _, _ = model.solve(x, 0.0, ds)
        scale = np.linalg.norm(x[fr]) / abs(lam)
        vec = lambda xx, ll: np.concatenate([xx[fr], [scale * ll]])  # noqa: E731
        arc = np.linalg.norm(vec(x, lam))
        path.append((ds, lam, x.copy()))
        steps_taken.append((model.crown_row(), 0.0, ds))
        while path[-1][0] < crown_max and len(path) <= 8 * steps:
            (_, la, xa), (_, lb, xb) = path[-2], path[-1]
            t = vec(xb, lb) - vec(xa, la)
            t /= np.linalg.norm(t)
            row = (t[:-1], t[-1] * scale)
            p0 = float(t @ vec(xb, lb))
            h = arc
            for _ in range(7):
                pred = vec(xb, lb) + h * t
                xg = xb.copy()
                xg[fr] = pred[:-1]
                try:
                    x, lam, _, _ = model.solve(xg, pred[-1] / scale, constraint=row + (p0 + h,))
                    if np.linalg.norm(vec(x, lam) - pred) > h:   # left the branch
                        raise SolveFailure("the corrector left the branch")
                    break
                except SolveFailure:
                    h /= 2
            else:
                raise SolveFailure(f"arc-length step failed at crown deflection {path[-1][0]:.6g} even with "
                                   "the step halved 6 times")
            path.append((model.crown_deflection(x), lam, x.copy()))
            steps_taken.append((row, p0, p0 + h))
    else:
        raise ValueError(control)

    def solver(row):
        return lambda xx, ll, p: model.solve(xx, ll, constraint=row + (p,))[:2]
    events, index_changes, limits = [], [], []
    sigs = [model.signature(xx) if model.p.k > 0 else None for _, _, xx in path]
    idxs = [index(xx, ll) for _, ll, xx in path]
    for j, (row, pa, pb) in enumerate(steps_taken):
        a, b = path[j], path[j + 1]
        if not locate_events:
            break
        if j > 0 and sigs[j] != sigs[j + 1]:
            events.append(_locate(model, pa, pb, a, b, lambda xx, ll: model.signature(xx), "contact", solver(row)))
        if idxs[j] is not None and idxs[j + 1] is not None and idxs[j] != idxs[j + 1]:
            index_changes.append(_locate(model, pa, pb, a, b, lambda xx, ll: model.index(xx, ll), "stability",
                                         solver(row)))
        sa, sb = model.slope(a[2], a[1], row), model.slope(b[2], b[1], row)
        if j > 0 and sa * sb < 0:
            kind = "max" if sa > 0 else "min"
            if refine_limits:
                lp = _locate(model, pa, pb, a, b, lambda xx, ll: model.slope(xx, ll, row) > 0, "limit", solver(row))
            else:
                lp = {"crown": b[0], "lambda": b[1]}
            lp["kind"] = kind
            limits.append(lp)
    out = [{"crown": d, "lambda": l, "N": model.thrust(xx), "A2": model.second_mode(xx),
            "contact": model.contact(xx) if model.p.k > 0 else [], "negative_eigenvalues": i}
           for (d, l, xx), i in zip(path, idxs)]
    for ev in index_changes:
        # a limit point within the same step (a bifurcation that close to a limit point would be
        # called a limit point: refine the steps to separate them)
        near = [lp for lp in limits if abs(lp["crown"] - ev["crown"]) <= ds and abs(lp["lambda"] - ev["lambda"])
                <= 1e-6 * max(abs(lp["lambda"]), 1.0)]
        same = [ce for ce in events if abs(ce["crown"] - ev["crown"]) <= ds and abs(ce["lambda"] - ev["lambda"])
                <= 1e-6 * max(abs(ce["lambda"]), 1.0)]
        # a tensionless foundation's tangent jumps where the contact set changes: a count that
        # changes there is a contact event, not a singular point
        ev["kind"] = "limit_point" if near else ("contact_change" if same else "bifurcation")
    return out, limits, events, index_changes


def _predict(path, delta):
    """Secant predictor through the last two points (the first step starts from the last point)."""
    (d1, l1, x1) = path[-1]
    if len(path) < 2:
        return x1, l1
    (d0, l0, x0) = path[-2]
    s = (delta - d1) / (d1 - d0)
    return x1 + s * (x1 - x0), l1 + s * (l1 - l0)


def _advance(model, path, delta, depth=0):
    """Solve at crown deflection delta from the path's end; on a Newton failure, halve the step
    (intermediate points are not kept), at most 6 times."""
    try:
        xg, lg = _predict(path, delta)
        x, lam, _, _ = model.solve(xg, lg, delta)
        # a corrector as large as the last step means Newton left the branch (the crown deflection
        # folds back nearby and another branch has the same crown deflection): not accepted
        if len(path) >= 2 and np.abs(x - xg).max() > np.abs(path[-1][2] - path[-2][2]).max():
            raise SolveFailure("the corrector left the branch")
        return x, lam
    except SolveFailure:
        if depth >= 6:
            raise SolveFailure(f"Newton failed at crown deflection {delta:.6g} even with the step halved 6 times "
                               "(the crown deflection may turn back along the path: crown control cannot follow; "
                               "try --control arclength)")
    mid = (path[-1][0] + delta) / 2
    xm, lm = _advance(model, path, mid, depth + 1)
    return _advance(model, path[-1:] + [(mid, lm, xm)], delta, depth + 1)


def _locate(model, pa, pb, before, after, signature, what, solve_at, iters=30):
    """Bisection in the step's parameter (pa at `before`, pb at `after`) for the change of
    signature(x, lambda)."""
    (_, la, xa), (_, lb, xb) = before, after
    sig_before = signature(xa, la)
    sig_after = signature(xb, lb)
    bracketed = True
    for _ in range(iters):
        pm = (pa + pb) / 2
        try:
            xm, lm = solve_at(xa, la, pm)
        except SolveFailure:
            # next to a bifurcation point the bordered matrix is singular too (the crown does not
            # move in the antisymmetric mode): keep the bracket reached
            bracketed = False
            break
        if signature(xm, lm) == sig_before:
            pa, la, xa = pm, lm, xm
        else:
            pb, lb, xb = pm, lm, xm
    pick = (max if sig_before else min) if what == "limit" else (lambda u, v: (u + v) / 2)
    out = {"crown": (model.crown_deflection(xa) + model.crown_deflection(xb)) / 2, "lambda": pick(la, lb),
           "N": model.thrust(xb), "A2": model.second_mode(xb), "bracket": pb - pa, "bisection_converged": bracketed}
    if what == "contact":
        out.update({"from": list(sig_before), "to": list(sig_after), "contact_after": model.contact(xb)})
    elif what == "stability":
        out.update({"negative_eigenvalues_from": sig_before, "negative_eigenvalues_to": sig_after})
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene")
    ap.add_argument("--elements", type=int, default=None, help="even; default [solve] elements or 128")
    ap.add_argument("--crown-max", type=float, default=None,
                    help="final crown deflection (default: 2.5 times the rise of a half-sine initial shape, or L/50)")
    ap.add_argument("--steps", type=int, default=60)
    ap.add_argument("--control", choices=("crown", "arclength"), default="crown",
                    help="crown displacement control (default) or arc-length (where the crown turns back)")
    ap.add_argument("--u-degree", type=int, default=3, choices=(2, 3, 4))
    ap.add_argument("--json", default=None)
    opts = ap.parse_args(argv)
    try:
        p, solve = read_scene(opts.scene)
        n = opts.elements or int(solve.get("elements", 128))
        if n < 2 or n % 2:
            raise SceneError(f"expected an even number of elements, got {n}")
        if not (p.load_sines or p.uniform or p.forces):
            raise SceneError("key 'loads': expected at least one load (the path is lambda times it)")
        rise = max([abs(a) for m, a in p.sines if m == 1] + [abs(a) for a, _, _ in p.bumps] + [0.0])
        crown_max = opts.crown_max or (2.5 * rise if rise > 0 else p.L / 50)
        t0 = time.perf_counter()
        model = Model(p, n, opts.u_degree)
        path, limits, events, stability = trace(model, crown_max, opts.steps, control=opts.control)
    except SceneError as e:
        print(f"{opts.scene}: {e}", file=sys.stderr)
        return 2
    except SolveFailure as e:
        print(f"{opts.scene}: {e}", file=sys.stderr)
        return 3
    result = {"method": "dolfinx-von-karman", "scene": opts.scene, "elements": n, "u_degree": opts.u_degree, "control": opts.control,
              "path": path, "limit_points": limits, "contact_events": events, "stability_events": stability,
              "time_s": time.perf_counter() - t0}
    if opts.json == "-":
        json.dump(result, sys.stdout, indent=1)
    elif opts.json:
        with open(opts.json, "w") as fh:
            json.dump(result, fh, indent=1)
    if opts.json != "-":
        print(f"{n} elements, {len(path) - 1} steps ({opts.control} control) to crown deflection {path[-1]['crown']:.6g}, "
              f"lambda {path[-1]['lambda']:.6g} (asked: crown {crown_max:g}; {result['time_s']:.1f} s)")
        for lp in limits:
            print(f"  limit point ({lp['kind']} of lambda): lambda {lp['lambda']:.10g} at crown deflection {lp['crown']:.8g}")
        for ev in stability:
            print(f"  {ev['kind']}: lambda {ev['lambda']:.10g} at crown deflection {ev['crown']:.8g}, N {ev['N']:.8g}, "
                  f"negative eigenvalues {ev['negative_eigenvalues_from']} -> {ev['negative_eigenvalues_to']}")
        for ev in events:
            print(f"  contact event: lambda {ev['lambda']:.10g} at crown deflection {ev['crown']:.8g}, "
                  f"regions {['[%.6g, %.6g]' % r for r in ev['contact_after']]}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

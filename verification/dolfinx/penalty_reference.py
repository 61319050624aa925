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
    element does not lock; degree 2 locks, see README.md).
  * foundation: the residual integral of K max(w, 0) v, integrated EXACTLY on each cell: the
    P2 w is split at its roots and each positive piece is integrated by 3-point Gauss (exact
    for the quartic integrands). Its Jacobian is the integral of K v_i v_j over {w > 0} (the
    moving-boundary terms vanish because w = 0 there), so the discrete problem is C^1 and
    Newton converges quadratically. --foundation-integration quadrature instead uses UFL's
    conditional(w > 0) at the quadrature points (a semismooth alternative, as a cross-check).
  * Newton: PETSc SNES (newtonls) with our residual/Jacobian callbacks, direct LU, started
    from the bilateral (linear) solution.
"""

import argparse
import json
import logging
import math
import sys
import time
import tomllib

import numpy as np

DEG = math.pi / 180.0


class SceneError(Exception):
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


def read_scene(path):
    with open(path, "rb") as fh:
        raw = tomllib.load(fh)
    st = raw.get("structure")
    if st is None:
        raise SceneError("table [structure] is required")
    kind = st.get("kind")
    if kind not in ("beam", "arch"):
        raise SceneError("key 'structure.kind': expected \"beam\" or \"arch\"")
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

    sup = raw.get("supports", {})
    sc["left"] = sup.get("left", "free")
    sc["right"] = sup.get("right", "free")
    allowed = ("pinned", "clamped", "free") if kind == "beam" else ("pinned", "roller", "clamped", "free")
    for end in ("left", "right"):
        if sc[end] not in allowed:
            raise SceneError(f"key 'supports.{end}': expected one of {allowed}, got {sc[end]!r}")
    sc["interior"] = [sc_pos(sc, float(p)) for p in sup.get("interior", [])]

    fd = raw.get("foundation")
    if fd is None:
        raise SceneError("table [foundation] is required")
    if ("k" in fd) == ("modulus" in fd):
        raise SceneError("[foundation]: exactly one of 'k' and 'modulus'")
    if "k" in fd:
        sc["k"] = _num(fd, "k", "foundation")
        sc["K"] = sc["k"] * sc["EI"] / sc["ref_length"] ** 4
    else:
        sc["K"] = _num(fd, "modulus", "foundation")
        sc["k"] = sc["K"] * sc["ref_length"] ** 4 / sc["EI"]
    sc["tensionless"] = bool(fd.get("tensionless", True))
    sc["f_from"] = sc_pos(sc, _num(fd, "from", "foundation", default=user_of(sc, sc["s0"])))
    sc["f_to"] = sc_pos(sc, _num(fd, "to", "foundation", default=user_of(sc, sc["s1"])))

    loads = []
    for i, ld in enumerate(raw.get("loads", [])):
        lk = ld.get("kind")
        if lk not in ("force", "moment", "uniform"):
            raise SceneError(f"key 'loads[{i}].kind': expected force, moment or uniform")
        item = {"kind": lk, "value": _num(ld, "value", f"loads[{i}]"), "case": ld.get("case", "live")}
        if lk == "uniform":
            item["from"] = sc_pos(sc, _num(ld, "from", f"loads[{i}]", default=user_of(sc, sc["s0"])))
            item["to"] = sc_pos(sc, _num(ld, "to", f"loads[{i}]", default=user_of(sc, sc["s1"])))
        else:
            item["at"] = sc_pos(sc, _num(ld, "at", f"loads[{i}]"))
        loads.append(item)
    sc["loads"] = loads
    sc["scene_elements"] = int(raw.get("solve", {}).get("elements", 200))
    return sc


def sc_pos(sc, user):
    """User position (x, or theta in degrees) -> internal coordinate s (x, or theta in rad)."""
    s = user if sc["kind"] == "beam" else user * DEG
    span = sc["s1"] - sc["s0"]
    if abs(s - sc["s0"]) <= 1e-12 * span:
        s = sc["s0"]
    if abs(s - sc["s1"]) <= 1e-12 * span:
        s = sc["s1"]
    if s < sc["s0"] or s > sc["s1"]:
        raise SceneError(f"position {user} outside the member")
    return s


def user_of(sc, s):
    return s if sc["kind"] == "beam" else s / DEG


# --------------------------------------------------------------------------------------------
# Mesh
# --------------------------------------------------------------------------------------------

def key_points(sc):
    pts = [sc["s0"], sc["s1"], sc["f_from"], sc["f_to"]] + list(sc["interior"])
    for ld in sc["loads"]:
        pts += [ld["from"], ld["to"]] if ld["kind"] == "uniform" else [ld["at"]]
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
        in_found = (mid > sc["f_from"]) & (mid < sc["f_to"])
        self.found_cells = np.nonzero(in_found)[0]

        # ---- boundary conditions (all homogeneous) ----
        def vertex_at(s):
            v = dmesh.locate_entities(msh, 0, lambda x: np.abs(x[0] - s) < tol)
            if len(v) != 1:
                raise RuntimeError(f"no unique mesh vertex at s = {s}")
            return v

        bc_dofs = []
        gauge = None
        for end, s in (("left", sc["s0"]), ("right", sc["s1"])):
            kind = sc[end]
            v = vertex_at(s)
            if kind in ("pinned", "clamped", "roller"):
                bc_dofs.append(fem.locate_dofs_topological(Ww, 0, v))
            if arch and kind in ("pinned", "clamped"):
                bc_dofs.append(fem.locate_dofs_topological(Wu, 0, v))
        for s in sc["interior"]:
            bc_dofs.append(fem.locate_dofs_topological(Ww, 0, vertex_at(s)))
        if arch and sc["left"] in ("roller", "free") and sc["right"] in ("roller", "free"):
            # rigid rotation about the centre (u = const, w = 0) is resisted by nothing:
            # fix u at the vertex nearest the crown (a gauge; changes no deflection or force)
            xv = msh.geometry.x[:, 0]
            vc = int(np.argmin(np.abs(xv - 0.5 * (sc["s0"] + sc["s1"]))))
            xg = xv[vc]
            bc_dofs.append(fem.locate_dofs_topological(Wu, 0, vertex_at(xg)))
            gauge = f"u = 0 at theta = {xg / DEG:.6g} deg (rigid rotation of the arch about its centre)"
        self.gauge = gauge
        bc_dofs = np.unique(np.concatenate(bc_dofs)) if bc_dofs else np.zeros(0, dtype=np.int32)
        self.bc_dofs = bc_dofs.astype(np.int32)
        zero = PETSc.ScalarType(0.0)
        if arch:
            bcs = [fem.dirichletbc(zero, self.bc_dofs, W)] if len(self.bc_dofs) else []
        else:
            bcs = [fem.dirichletbc(zero, self.bc_dofs, W)] if len(self.bc_dofs) else []
        self.bcs = bcs

        # ---- clamped-end facet tags for Nitsche ----
        facet_idx, facet_val = [], []
        for tag, (end, s) in enumerate((("left", sc["s0"]), ("right", sc["s1"])), start=1):
            if sc[end] == "clamped":
                facet_idx.append(int(vertex_at(s)[0]))
                facet_val.append(tag)
        order_f = np.argsort(facet_idx)
        ft = dmesh.meshtags(msh, 0, np.array(facet_idx, dtype=np.int32)[order_f],
                            np.array(facet_val, dtype=np.int32)[order_f])

        # ---- DG0 cell data: foundation modulus and uniform load ----
        V0 = fem.FunctionSpace(msh, ("DG", 0))
        c0 = np.array([V0.dofmap.cell_dofs(c)[0] for c in range(nc)])
        kf = fem.Function(V0)
        kf.x.array[c0[in_found]] = sc["K"]
        qf = fem.Function(V0)
        lam = opts.load_factor
        for ld in sc["loads"]:
            if ld["kind"] == "uniform":
                fac = lam if ld["case"] == "live" else 1.0
                sel = (mid > ld["from"]) & (mid < ld["to"])
                qf.x.array[c0[sel]] += fac * ld["value"]
        self.kf = kf

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
        a_bil = kf * J * w * wh * dx          # bilateral foundation (linear)
        Lq = qf * J * wh * dx                  # uniform loads
        self.a_form_ufl, self.abil_form_ufl = a, a_bil
        self.a_form = fem.form(a)
        self.abil_form = fem.form(a_bil)
        self.L_form = fem.form(Lq)

        if opts.foundation_integration == "quadrature":
            self.xfun = fem.Function(W)
            wcur = ufl.split(self.xfun)[1] if arch else self.xfun
            md = {"quadrature_degree": opts.quadrature_degree}
            dxq = ufl.dx(domain=msh, metadata=md)
            pos = ufl.conditional(ufl.gt(wcur, 0.0), wcur, 0.0)
            Fq = kf * J * pos * wh * dxq
            Jq = ufl.derivative(Fq, self.xfun, trial)
            self.Fq_form = fem.form(Fq)
            self.Jq_form = fem.form(Jq)
        self.time_build = time.perf_counter() - t_build0

        # point loads need mesh connectivity: keep what is needed
        self._fem, self._fpetsc, self._PETSc, self._dmesh = fem, fpetsc, PETSc, dmesh
        self._vertex_at = vertex_at

    # ------------------------------------------------------------------
    def assemble_linear(self):
        """Stiffness K (with BC rows/cols), bilateral foundation matrix, load vector f."""
        import scipy.sparse as sp
        fpetsc = self._fpetsc
        sc, opts = self.sc, self.opts
        A = fpetsc.assemble_matrix(self.a_form, bcs=self.bcs)
        A.assemble()
        ip, ix, dv = A.getValuesCSR()
        K = sp.csr_matrix((dv, ix, ip), shape=(self.ndofs, self.ndofs))
        B = fpetsc.assemble_matrix(self.abil_form, bcs=self.bcs, diagonal=0.0)
        B.assemble()
        ip, ix, dv = B.getValuesCSR()
        Kb = sp.csr_matrix((dv, ix, ip), shape=(self.ndofs, self.ndofs))
        b = fpetsc.assemble_vector(self.L_form)
        b.ghostUpdate(addv=self._PETSc.InsertMode.ADD, mode=self._PETSc.ScatterMode.REVERSE)
        f = b.array.copy()

        msh = self.msh
        v2c = msh.topology.connectivity(0, 1)
        lam = opts.load_factor
        for ld in sc["loads"]:
            if ld["kind"] == "uniform":
                continue
            fac = lam if ld["case"] == "live" else 1.0
            P = fac * ld["value"]
            v = self._vertex_at(ld["at"])
            if ld["kind"] == "force":
                d = self._fem.locate_dofs_topological(self.Ww, 0, v)
                f[d] += P
            else:
                # point moment: work = M * rotation. The C0 P2 test function's derivative
                # jumps at a vertex; take it from the adjacent cell (at an end there is only
                # one), averaging the two one-sided values at an interior vertex.
                cells = v2c.links(int(v[0]))
                g = np.zeros(self.ndofs)
                for c in cells:
                    dofs = np.asarray(self.Ww.dofmap.cell_dofs(int(c)))
                    g[dofs] += lagrange_derivatives(self.coord[dofs], ld["at"]) / len(cells)
                if self.arch:
                    du = self._fem.locate_dofs_topological(self.Wu, 0, v)
                    g[du] += 1.0
                    g /= sc["R"]          # rotation = -(u + w')/R
                f += -P * g               # rotation = -w' (beam)
        f[self.bc_dofs] = 0.0
        self.K, self.Kb, self.f = K, Kb, f

    # ------------------------------------------------------------------
    def foundation_exact(self, x, want_jac=True):
        """Residual and Jacobian of int K max(w,0) v over the foundation, exact per cell."""
        import scipy.sparse as sp
        cells = self.found_cells
        dofs = self.cw[cells]            # (m, 3)
        xl = self.cx[cells, 0]
        hh = self.cx[cells, 2] - xl
        wv = x[dofs]                     # values at t = 0, 1/2, 1
        w0, wm, w1 = wv[:, 0], wv[:, 1], wv[:, 2]
        # w(t) = A t^2 + B t + C
        A = 2.0 * w1 - 4.0 * wm + 2.0 * w0
        B = 4.0 * wm - w1 - 3.0 * w0
        C = w0
        r1, r2 = quad_roots(A, B, C)
        r1 = np.where(np.isfinite(r1), np.clip(r1, 0.0, 1.0), 1.0)
        r2 = np.where(np.isfinite(r2), np.clip(r2, 0.0, 1.0), 1.0)
        br = np.stack([np.zeros_like(A), r1, r2, np.ones_like(A)], axis=1)
        br = np.sort(br, axis=1)                      # pieces [br0,br1],[br1,br2],[br2,br3]
        gp = np.array([-math.sqrt(0.6), 0.0, math.sqrt(0.6)])
        gw = np.array([5.0, 8.0, 5.0]) / 9.0
        coef = self.sc["K"] * self.sc["J"]
        Rloc = np.zeros((len(cells), 3))
        Jloc = np.zeros((len(cells), 3, 3)) if want_jac else None
        for p in range(3):
            ta, tb = br[:, p], br[:, p + 1]
            L = tb - ta
            tm = 0.5 * (ta + tb)
            wmid = (A * tm + B) * tm + C
            active = (wmid > 0.0) & (L > 0.0)
            for q in range(3):
                t = tm + 0.5 * L * gp[q]
                phi = np.stack([2.0 * (t - 0.5) * (t - 1.0), 4.0 * t * (1.0 - t), 2.0 * t * (t - 0.5)], axis=1)
                wt = (A * t + B) * t + C
                fac = np.where(active, coef * hh * 0.5 * L * gw[q], 0.0)
                Rloc += (fac * wt)[:, None] * phi
                if want_jac:
                    Jloc += fac[:, None, None] * phi[:, :, None] * phi[:, None, :]
        r = np.zeros(self.ndofs)
        np.add.at(r, dofs.ravel(), Rloc.ravel())
        r[self.bc_dofs] = 0.0
        if not want_jac:
            return r, None
        rows = np.repeat(dofs, 3, axis=1).ravel()
        cols = np.tile(dofs, (1, 3)).ravel()
        Jm = sp.csr_matrix((Jloc.ravel(), (rows, cols)), shape=(self.ndofs, self.ndofs))
        keep = np.ones(self.ndofs)
        keep[self.bc_dofs] = 0.0
        D = sp.diags(keep)
        Jm = (D @ Jm @ D).tocsr()
        return r, Jm

    def foundation_quadrature(self, x, want_jac=True):
        import scipy.sparse as sp
        fpetsc = self._fpetsc
        self.xfun.x.array[:] = x
        b = fpetsc.assemble_vector(self.Fq_form)
        r = b.array.copy()
        r[self.bc_dofs] = 0.0
        if not want_jac:
            return r, None
        A = fpetsc.assemble_matrix(self.Jq_form, bcs=self.bcs, diagonal=0.0)
        A.assemble()
        ip, ix, dv = A.getValuesCSR()
        return r, sp.csr_matrix((dv, ix, ip), shape=(self.ndofs, self.ndofs))

    # ------------------------------------------------------------------
    def linsolve(self, M, b):
        """Direct solve of the sparse system M x = b: SuperLU (scipy, partial pivoting, COLAMD)
        by default, or a PETSc LU package (--lu mumps|petsc)."""
        if self.opts.lu in ("superlu", "superlu-natural"):
            import scipy.sparse.linalg as spla
            spec = "NATURAL" if self.opts.lu == "superlu-natural" else "COLAMD"
            return spla.splu(M.tocsc(), permc_spec=spec).solve(np.asarray(b, dtype=float))
        PETSc = self._PETSc
        M = M.tocsr()
        M.sort_indices()
        n = M.shape[0]
        P = PETSc.Mat().createAIJ(size=(n, n), csr=(M.indptr.astype(PETSc.IntType),
                                                  M.indices.astype(PETSc.IntType), M.data),
                                  comm=PETSc.COMM_SELF)
        P.assemble()
        ksp = PETSc.KSP().create(PETSc.COMM_SELF)
        ksp.setOperators(P)
        ksp.setType("preonly")
        pc = ksp.getPC()
        pc.setType("lu")
        if self.opts.lu != "petsc":
            pc.setFactorSolverType(self.opts.lu)
        bv = PETSc.Vec().createWithArray(np.array(b, dtype=float), comm=PETSc.COMM_SELF)
        xv = P.createVecLeft()
        ksp.solve(bv, xv)
        if ksp.getConvergedReason() < 0:
            raise RuntimeError(f"LU solve failed: reason {ksp.getConvergedReason()}")
        x = xv.getArray().copy()
        ksp.destroy()
        P.destroy()
        return x

    def solve(self):
        """Bilateral solve, then (if tensionless) Newton. Returns x and info.

        The foundation residual r(x) = int K max(w,0) v is positively homogeneous of degree 1,
        so r(x) = Jf(x) x exactly, and the Newton step x+ = x - (K + Jf)^-1 (K x - f + r(x))
        is the same as solving (K + Jf(x)) x+ = f directly. We iterate in that form ("direct"):
        it never forms the residual K x - f, whose cancellation (K ~ EI/h^3 rows summing to
        nearly zero) would put a roundoff floor eps*|K||x| ~ N^3 on every Newton correction.
        --newton snes runs the same iteration in correction form through PETSc SNES."""
        import scipy.sparse as sp
        PETSc = self._PETSc
        K, Kb, f = self.K, self.Kb, self.f
        Kbil = (K + Kb).tocsr()
        x0 = self.linsolve(Kbil, f)
        # roundoff level of this discretisation: the 4th-order P2-CIP matrix has cond ~ N^4, and
        # the rounding of its entries alone perturbs the solution by ~ eps*cond. Estimate it
        # by solving the bilateral system once more with a different elimination order.
        import scipy.sparse.linalg as spla
        x0b = spla.splu(Kbil.tocsc(), permc_spec="NATURAL").solve(f)
        noise = float(np.linalg.norm(x0b - x0) / max(np.linalg.norm(x0), 1e-300))
        self.noise = noise
        info = {"newton_iterations": 0, "roundoff_estimate": noise}
        fnorm_f = np.linalg.norm(f)
        if not self.sc["tensionless"]:
            res = Kbil @ x0 - f
            info["residual"] = float(np.linalg.norm(res) / max(fnorm_f, 1e-300))
            return x0, info

        fnd = self.foundation_exact if self.opts.foundation_integration == "exact" else self.foundation_quadrature
        if self.opts.newton == "direct":
            x = x0
            prev = None
            steps = []
            converged = False
            for it in range(1, self.opts.max_newton + 1):
                _, Jf = fnd(x, want_jac=True)
                xn = self.linsolve(K + Jf, f)
                step = float(np.linalg.norm(xn - x))
                x = xn
                xnorm = float(np.linalg.norm(x))
                steps.append(step / max(xnorm, 1e-300))
                if self.opts.verbose:
                    print(f"    newton {it}: |dx|/|x| = {steps[-1]:.3e}", file=sys.stderr)
                if step <= self.opts.step_tolerance * xnorm:
                    converged = True
                    break
                if step <= 10.0 * noise * xnorm and (prev is None or step >= 0.1 * prev or step <= noise * xnorm):
                    converged = True     # down to the roundoff level of the linear solves
                    break
                prev = step
            if not converged:
                raise RuntimeError(f"Newton did not converge in {self.opts.max_newton} iterations")
            r, _ = fnd(x, want_jac=False)
            res = K @ x - f + r
            info.update(newton_iterations=it, newton_steps=steps,
                        residual=float(np.linalg.norm(res) / max(fnorm_f, 1e-300)),
                        residual_scaled=float(np.linalg.norm(res) / (abs(K).sum(axis=1).max() * np.linalg.norm(x) + fnorm_f)))
            return x, info

        # ---- SNES (correction form) ----
        info["snes_reason"] = None
        # Jacobian pattern: K's pattern plus all w-w couplings of the foundation cells
        dofs = self.cw[self.found_cells]
        rows = np.repeat(dofs, 3, axis=1).ravel()
        cols = np.tile(dofs, (1, 3)).ravel()
        S = sp.csr_matrix((np.zeros(len(rows)), (rows, cols)), shape=K.shape)
        Kpat = (K + S + Kb * 0.0).tocsr()
        Kpat.sort_indices()
        pattern = Kpat.copy()
        pattern.data[:] = 1.0     # structural ones to fix the pattern
        n = self.ndofs
        Pmat = PETSc.Mat().createAIJ(size=(n, n), csr=(pattern.indptr.astype(PETSc.IntType),
                                                     pattern.indices.astype(PETSc.IntType),
                                                     np.zeros(pattern.nnz)), comm=PETSc.COMM_SELF)
        Pmat.setOption(PETSc.Mat.Option.NEW_NONZERO_ALLOCATION_ERR, True)
        Pmat.assemble()
        fnorm_f = np.linalg.norm(f)
        Knorm = abs(K).sum(axis=1).max()
        counter = {"F": 0, "J": 0}

        def F_cb(snes, X, Fv):
            xa = X.getArray(readonly=True)
            r, _ = fnd(xa, want_jac=False)
            Fv.setArray(K @ xa - f + r)
            counter["F"] += 1

        def J_cb(snes, X, Jm, Pm):
            xa = X.getArray(readonly=True)
            _, Jf = fnd(xa, want_jac=True)
            M = (pattern * 0.0 + K + Jf).tocsr()
            M.sort_indices()
            Pm.zeroEntries()
            Pm.setValuesCSR(M.indptr.astype(PETSc.IntType), M.indices.astype(PETSc.IntType), M.data)
            Pm.assemble()
            counter["J"] += 1

        maxit = self.opts.max_newton

        def conv_cb(snes, it, norms):
            xnorm, ynorm, fn = norms
            if self.opts.verbose:
                print(f"    newton {it}: |F| = {fn:.3e}  |dx| = {ynorm:.3e}  |x| = {xnorm:.3e}", file=sys.stderr)
            if fn <= 1e-14 * fnorm_f:
                return PETSc.SNES.ConvergedReason.CONVERGED_FNORM_ABS
            if it > 0 and ynorm <= self.opts.step_tolerance * xnorm:
                return PETSc.SNES.ConvergedReason.CONVERGED_SNORM_RELATIVE
            if it >= maxit:
                return PETSc.SNES.ConvergedReason.DIVERGED_MAX_IT
            return PETSc.SNES.ConvergedReason.ITERATING

        snes = PETSc.SNES().create(PETSc.COMM_SELF)
        snes.setOptionsPrefix("penref_")
        popts = PETSc.Options()
        popts["penref_snes_linesearch_type"] = self.opts.line_search
        snes.setType("newtonls")
        snes.setFromOptions()
        Fvec = PETSc.Vec().createSeq(n)
        snes.setFunction(F_cb, Fvec)
        snes.setJacobian(J_cb, Pmat, Pmat)
        snes.setConvergenceTest(conv_cb)
        snes.setTolerances(max_it=maxit + 1)
        ksp = snes.getKSP()
        ksp.setType("preonly")
        ksp.getPC().setType("lu")
        X = PETSc.Vec().createSeq(n)
        X.setArray(x0)
        snes.solve(None, X)
        reason = snes.getConvergedReason()
        x = X.getArray().copy()
        r, _ = fnd(x, want_jac=False)
        res = K @ x - f + r
        info.update(newton_iterations=int(snes.getIterationNumber()), snes_reason=int(reason),
                    residual=float(np.linalg.norm(res) / max(fnorm_f, 1e-300)),
                    residual_floor=float(1e3 * np.finfo(float).eps * Knorm * np.linalg.norm(x) / max(fnorm_f, 1e-300)))
        snes.destroy()
        Pmat.destroy()
        if reason <= 0:
            raise RuntimeError(f"Newton (SNES) did not converge: reason {reason}")
        return x, info

    # ------------------------------------------------------------------
    def postprocess(self, x):
        sc = self.sc
        cx, cw = self.cx, self.cw
        wv = x[cw]
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
        # contact regions inside the foundation extent
        fc = self.found_cells
        r1, r2 = quad_roots(A[fc], B[fc], C[fc])
        scale = max(np.max(np.abs(wv)), 1e-300)
        pieces = []
        for j, c in enumerate(fc):
            ts_ = sorted([0.0, 1.0] + [t for t in (r1[j], r2[j]) if 0.0 < t < 1.0])
            for ta, tb in zip(ts_[:-1], ts_[1:]):
                if tb <= ta:
                    continue
                tm = 0.5 * (ta + tb)
                wmid = (A[c] * tm + B[c]) * tm + C[c]
                pieces.append((cx[c, 0] + ta * h[c], cx[c, 0] + tb * h[c], wmid > 1e-13 * scale))
        pieces.sort()
        regions = []
        for a, b, pos in pieces:
            if not pos:
                continue
            if regions and abs(a - regions[-1][1]) <= 1e-12 * (sc["s1"] - sc["s0"]):
                regions[-1][1] = b
            else:
                regions.append([a, b])
        wfound = np.concatenate([wv[fc].ravel(), np.where(inside[fc], (A[fc] * ts[fc] + B[fc]) * ts[fc] + C[fc], 0.0)])
        max_reaction = float(sc["K"] * max(0.0, wfound.max())) if len(fc) else 0.0
        return {
            "contact_regions": [[user_of(sc, a), user_of(sc, b)] for a, b in regions],
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
    model.assemble_linear()
    x, info = model.solve()
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
    ap.add_argument("--newton", choices=("direct", "snes"), default="direct",
                    help="direct: solve (K + Jf(x_k)) x_k+1 = f (default); snes: PETSc SNES, correction form")
    ap.add_argument("--lu", default="superlu", choices=("superlu", "superlu-natural", "mumps", "petsc"),
                    help="linear solver: superlu (scipy, default), superlu-natural, or PETSc LU with mumps/petsc")
    ap.add_argument("--line-search", default="basic", help="SNES line search: basic, bt, l2, cp")
    ap.add_argument("--max-newton", type=int, default=50)
    ap.add_argument("--step-tolerance", type=float, default=1e-11,
                    help="Newton stops when |dx| <= this * |x| (default 1e-11)")
    ap.add_argument("--verbose", action="store_true", help="print the Newton history")
    ap.add_argument("--load-factor", type=float, default=1.0, help="lambda multiplying the live loads")
    ap.add_argument("--json", metavar="OUT.json", help="write the result here ('-' = stdout)")
    opts = ap.parse_args(argv)
    logging.disable(logging.INFO)

    t_start = time.perf_counter()
    try:
        sc = read_scene(opts.scene)
    except (SceneError, tomllib.TOMLDecodeError, OSError) as e:
        print(f"{opts.scene}: {e}", file=sys.stderr)
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
        "discretisation": {
            "w": "P2 Lagrange, C0 interior penalty (symmetric), Nitsche for clamped w'",
            "u": f"P{opts.u_degree} Lagrange" if sc["kind"] == "arch" else None,
            "alpha": opts.alpha * opts.penalty_scale,
            "penalty_scale": opts.penalty_scale,
            "foundation_integration": opts.foundation_integration
            + ("" if opts.foundation_integration == "exact" else f" (degree {opts.quadrature_degree})"),
            "newton": (f"Newton in direct form (K + Jf(x_k)) x_k+1 = f, LU ({opts.lu})"
                       if opts.newton == "direct" else f"PETSc SNES newtonls, line search {opts.line_search}, LU"),
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
            res = solve_mesh(sc, vertices(kp, alloc), opts)
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
        result["observed_order"] = order
        result["estimated_limit_error"] = err
        result["extrapolated_contact_regions"] = extrap
        result["per_limit_order"] = per_limit
        result["last_change"] = (float(np.max(np.abs(flatten_limits(levels[-1]["contact_regions"])
                                                      - flatten_limits(levels[-2]["contact_regions"]))))
                                 if len(levels) >= 2 and len(levels[-1]["contact_regions"]) == len(levels[-2]["contact_regions"])
                                 else None)
    else:
        n = opts.elements or sc["scene_elements"]
        res = solve_mesh(sc, vertices(kp, base_allocation(kp, n)), opts)
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

"""The finite-element soil: statics, explicit time stepping over a macro
step, footprint and receiver outputs, save/restore.

Time integration: central differences in velocity-Verlet form with the
lumped mass (one matrix-vector product per step, no solve). The diagonal
damping (mass-proportional Rayleigh part, Lysmer-Kuhlemeyer dashpots) is
taken at the end of the step, which keeps the step explicit; the
stiffness-proportional part uses the half-step velocity, low-pass filtered
at [soil] damping_cutoff (an exact exponential update of the filter over
each step; params.damping_law), or the velocity itself with the cutoff 0.
The step is the largest stable one (from the highest eigenfrequency of
M^-1 K by power iteration) times a safety factor; a macro step H is cut into
ceil(H/dt) equal steps, the footprint forces varying linearly over it.
"""
from __future__ import annotations

import math

import numpy as np
from dolfinx import fem
import dolfinx.fem.petsc  # noqa: F401  (registers fem.petsc)
from mpi4py import MPI
from petsc4py import PETSc

from . import damping, far_field, footprints, forms, ground_shapes, near_field
from .mesh import SYMMETRY, block_mesh, facet_tags, layer_fields
from .params import SoilParams, stable_step


def _cat(arrays, dtype):
    return np.concatenate(arrays).astype(dtype) if arrays else np.zeros(0, dtype)


class FESoil:
    def __init__(self, params: SoilParams, comm=MPI.COMM_WORLD):
        self.p = params
        self.comm = comm
        self.mesh, self.nodes = block_mesh(params, comm)
        mesh = self.mesh
        self.V = fem.VectorFunctionSpace(mesh, ("Lagrange", 1))
        tags = facet_tags(mesh, self.nodes)
        ds = forms.boundary_measures(mesh, tags)
        self.fields = f = layer_fields(mesh, params)
        # Numbers of the block and the damping fit enter the forms as
        # constants, not literals: the compiled forms (FFCx, cached) are then
        # the same for every block, and a new scene compiles nothing.
        centre = fem.Constant(mesh, np.array([0.5 * (self.nodes[0][0] + self.nodes[0][-1]), 0.0, 0.0]))
        self._setup_operators(f, ds, tags, centre)
        self._setup_footprints()
        self.fp_compliance = (near_field.compliances(params, self.nodes, comm)  # m/N; None: off
                              if params.footprint_compliance else None)
        self._setup_receivers()
        self.dt = self._stable_step()
        self._inv = None  # (dt, the update's diagonal) of the last run
        self.ksp, self._extension = None, None  # the block's static solver, the far field
        # (forces, block solution, solution, held force) of the last static
        # solves; (forces, block solution) of another block's to start from
        self._static_basis, self._static_start = [], []
        self.reset()

    # ---- set-up -------------------------------------------------------
    def _setup_operators(self, f, ds, tags, centre):
        V, p = self.V, self.p
        K = forms.assembled(forms.stiffness_form(V, f, ds, centre, p.spring_alpha))
        n_owned = V.dofmap.index_map.size_local * V.dofmap.index_map_bs
        self.n_owned = n_owned
        self.mask = np.ones(n_owned)
        self.m = forms.lumped_mass(V, f)
        # The nodes inside an open trench touch no soil (no mass, no
        # stiffness): held at zero like the symmetry plane's u_y, their mass
        # set to 1 so that the update divides by none (path_measures.py).
        held = np.flatnonzero(self.m <= 0.0)
        self.mask[held] = 0.0
        self.m[held] = 1.0
        if p.symmetric:
            Vy, _ = V.sub(1).collapse()
            dofs = fem.locate_dofs_topological((V.sub(1), Vy), 2, tags.find(SYMMETRY))[0]
            dofs = dofs[dofs < n_owned]
            self.mask[dofs] = 0.0
            held = np.union1d(held, dofs)
        rows = (held + K.getOwnershipRange()[0]).astype(np.int32)
        # Statics: u_y = 0 on the symmetry plane, K's rows and columns there
        # replaced by the identity (the same operator as dolfinx's BCs).
        # GAMG needs AIJ: a copy (convert() without a target converts in place).
        self.K_static = K.convert("aij", PETSc.Mat())
        self.K_static.zeroRowsColumns(rows, 1.0)
        self.K = K
        self.c, self.tau, self.a1_max, parts = damping.operators(
            self, f, ds, lambda cells: forms.assembled(
                forms.stiffness_form(V, f, ds, centre, p.spring_alpha, cells)))
        self.parts = [(a1, K if A is None else A) for a1, A in parts]
        self.U, self.W = self.K.createVecs()
        self.KU = self.U.duplicate()

    def _setup_footprints(self):
        # The track's ground: an embankment's crest is the top node plane, a
        # cutting's base the plane at -depth (fe_soil/ground_shapes.py).
        g = self.p.ground
        z = None if g is None or g.shape != "cutting" else g.surface
        index = footprints.surface_node_index(self.V, self.nodes, z)
        self._surface_index = index
        idx, val, of, self.fp_area, self.fp_share = [], [], [], [], []
        for k, fp in enumerate(self.p.footprints):
            i, v, area = footprints.footprint_vector(fp, self.nodes, index)
            if area <= 0.0:
                raise ValueError(
                    f"soil: footprint at x = {fp.x} m, y = {fp.y} m lies outside the mesh surface"
                )
            idx.append(i)
            val.append(v)
            of.append(np.full(len(i), k))
            self.fp_area.append(area)
            # On the symmetry plane the half block carries half the force.
            on_axis = self.p.symmetric and abs(fp.y) < 1e-12
            self.fp_share.append(0.5 if on_axis else 1.0)
        # All footprints' (DOF, value) pairs in flat arrays: a load vector and
        # the footprint averages are then one bincount each, not a loop.
        self.fp_idx, self.fp_val, self.fp_of = _cat(idx, np.int64), _cat(val, float), _cat(of, np.int64)
        self.fp_area = np.array(self.fp_area)
        self.fp_share = np.array(self.fp_share)

    def _setup_receivers(self):
        """A receiver's velocity is the Q1 field at a surface point: on the
        tensor grid's surface the bilinear interpolation of the four nodes
        around it (products of 1D hats). Each rank sums its owned nodes'
        share, and one reduction adds them up (no ghost update)."""
        g = self.p.ground
        pts = np.array([[x, y, 0.0 if g is None else ground_shapes.surface_z(g, self.nodes, y)]
                        for x, y in self.p.receivers], dtype=float).reshape(-1, 3)
        self.rec_points = pts
        self.vfun = fem.Function(self.V)
        xs, ys, _ = self.nodes
        planes = {}  # the surface's node index of each receiver's height
        idx, w, of = [], [], []
        for k, (x, y, z) in enumerate(pts):
            if g is None:
                i, j = self._surface_index
            else:
                if z not in planes:
                    planes[z] = footprints.surface_node_index(self.V, self.nodes, z)
                i, j = planes[z]
            on = np.flatnonzero(i >= 0)
            wx = footprints.hat_values(xs, x)
            wy = footprints.hat_values(ys, y)
            vals = wx[i[on]] * wy[j[on]]
            keep = vals > 0.0
            for c in range(3):
                idx.append(3 * on[keep] + c)
                w.append(vals[keep])
                of.append(np.full(int(keep.sum()), 3 * k + c))
        self.rec_idx, self.rec_w, self.rec_of = _cat(idx, np.int64), _cat(w, float), _cat(of, np.int64)

    def _stable_step(self, iterations=40):
        """dt = safety * 2/w_max * (sqrt(1 + xi^2) - xi), w_max by power
        iteration on M^-1/2 K M^-1/2 (converges from below; the safety
        factor covers the gap); stable_step has the damping's share."""
        x, y = self.K.createVecs()
        # A start vector from the DOFs' coordinates: the same on any number
        # of ranks, so dt does not depend on the partition.
        c = self.dof_coordinates()
        comp = np.arange(self.n_owned) % 3
        x.array[:] = np.sin(12.9898 * c[:, 0] + 78.233 * c[:, 1] + 37.719 * c[:, 2] + 1.7 * comp) * self.mask
        s = 1.0 / np.sqrt(self.m)
        lam = 0.0
        for _ in range(iterations):
            x.array[:] *= 1.0 / math.sqrt(self.comm.allreduce(float(x.array @ x.array)))
            z = x.array.copy()
            x.array[:] = z * s
            self.K.mult(x, y)
            x.array[:] = y.array * s * self.mask
            lam = self.comm.allreduce(float(z @ x.array))
        self.w_max = math.sqrt(lam)
        return self.p.cfl_safety * stable_step(self.w_max, self.a1_max, self.tau)

    # ---- state --------------------------------------------------------
    def reset(self):
        self.t = 0.0
        self.u = self.U.array  # a view: K.mult reads it in place
        self.u[:] = 0.0
        self.v = np.zeros(self.n_owned)
        self.a = np.zeros(self.n_owned)
        self.z = np.zeros(self.n_owned)  # the filtered velocity (damping_cutoff)
        self.f_static = np.zeros(self.n_owned)  # see statics()
        self.history = []  # (t, vertical velocity per receiver)

    def save(self):
        return {"t": self.t, "u": self.u.copy(), "v": self.v.copy(), "a": self.a.copy(),
                "z": self.z.copy(), "f_static": self.f_static, "n_history": len(self.history)}

    def restore(self, state):
        self.t = state["t"]
        self.u[:] = state["u"]
        self.v[:] = state["v"]
        self.a[:] = state["a"]
        self.z[:] = state["z"]
        self.f_static = state["f_static"]
        del self.history[state["n_history"] :]

    # ---- footprints ---------------------------------------------------
    def load_vector(self, forces):
        """Forces (N, positive down, one per footprint, whole sleeper) as
        nodal forces: a uniform pressure over each footprint."""
        forces = np.asarray(forces, dtype=float)
        if forces.shape != (len(self.fp_area),):
            raise ValueError(
                f"soil: {forces.shape[0] if forces.ndim else 1} forces given for "
                f"{len(self.fp_area)} footprints"
            )
        coef = forces * self.fp_share / self.fp_area
        return np.bincount(self.fp_idx, weights=coef[self.fp_of] * self.fp_val,
                           minlength=self.n_owned)

    def _local_sums(self, *fields):
        """This rank's share of each field's footprint sums (one array per
        field, one entry per footprint)."""
        n = len(self.fp_area)
        return [np.bincount(self.fp_of, weights=self.fp_val * f[self.fp_idx], minlength=n)
                for f in fields]

    def _local_receivers(self):
        return np.bincount(self.rec_of, weights=self.rec_w * self.v[self.rec_idx],
                           minlength=3 * len(self.rec_points))

    def _reduce(self, parts):
        """The sum over ranks of the concatenated parts, split back."""
        local = np.concatenate(parts) if parts else np.zeros(0)
        total = np.zeros_like(local)
        self.comm.Allreduce(local, total, op=MPI.SUM)
        return np.split(total, np.cumsum([len(q) for q in parts])[:-1])

    def footprint_average(self, field):
        """Downward displacement (or velocity) averaged over each footprint."""
        return self._reduce(self._local_sums(field))[0] / self.fp_area

    # ---- the participant's calls -----------------------------------------
    STATIC_BASIS = 24  # solutions kept to start the next static solve from

    def statics(self, forces, rtol=1e-12, iterating=False):
        """Equilibrium under the footprint forces; the state becomes it (at
        rest). Returns the downward displacement of each footprint.

        A coupled static iteration asks again and again with forces that
        change less and less: the solver (CG + GAMG) is set up once, and a
        solve starts from the kept solutions' best fit (far_field.start_from).
        Forces asked for before get that solution back bitwise, so the
        iteration sees the change stop instead of the solver's round-off.
        With `static_reach` the outer soil's correction is added
        (far_field.StaticExtension); to the outputs, c_loc F (`_own`).

        `iterating` (the master's iteration): after the first solve, inexact
        while the forces still change (far_field.forcing; Eisenstat & Walker's
        forcing terms, 1996); a kept solution is given back only if solved
        as far as asked."""
        forces = np.asarray(forces, dtype=float)
        for f_old, _, x_old, c_old, r_old in self._static_basis:
            if r_old <= rtol and np.array_equal(f_old, forces):
                self._set_static(x_old, c_old)
                return self._own(self.footprint_average(self.u), forces)
        if iterating and self._static_basis:  # the first solve is exact
            rtol = far_field.forcing(forces, self._static_basis[-1][0], rtol)
        x_block = self._block_statics(forces, rtol)
        x = x_block + self._far_field(forces)
        # The force the soil outside the block exerts beyond the boundary
        # springs (zero without the extension), held in the dynamics.
        self.U.array[:] = x
        self.K.mult(self.U, self.KU)
        corr = (self.KU.array - self.load_vector(forces)) * self.mask * (self.p.static_reach > 0.0)
        self._static_basis.append((forces.copy(), x_block, x.copy(), corr, rtol))
        del self._static_basis[: -self.STATIC_BASIS]
        self._set_static(x, corr)
        return self._own(self.footprint_average(self.u), forces)

    def _far_field(self, forces):
        """The outer soil's change to the block's static displacement (zero
        without `static_reach`)."""
        if self.p.static_reach <= 0.0:
            return 0.0
        if self._extension is None:  # built at the first statics
            self._extension = far_field.StaticExtension(self.p, self.nodes, self.dof_coordinates(),
                                                          self.comm)
        return self._extension.correction(forces, self.fp_share) * self.mask

    def _block_statics(self, forces, rtol):
        b = self.U.duplicate()
        b.array[:] = self.load_vector(forces) * self.mask
        if self.ksp is None:
            # The rigid-body modes as GAMG's near null space: on the graded
            # ground-vibration block (219k DOFs, elements up to 7:1, nu = 0.478)
            # 145 CG iterations to 1e-12 against 253 without.
            self.K_static.setNearNullSpace(forms.rigid_body_modes(
                self.U, self.dof_coordinates(), self.mask, self.comm))
            self.ksp = far_field.cg_gamg(self.K_static, self.comm, counter=self)
        x = self.U.duplicate()
        x.array[:] = far_field.start_from(self._static_basis or self._static_start,
                                          forces) * self.mask
        far_field.solve(self.ksp, b, x, rtol, "")
        return x.array.copy()

    def static_solutions(self):
        """What another block of the same mesh starts its statics from
        (start_statics_from): this rank's DOF coordinates, and the kept
        forces with the block's solution under each."""
        return self.dof_coordinates(), [b[:2] for b in self._static_basis]

    def start_statics_from(self, solutions):
        """Static solves start from another block's (static_solutions) until
        this one has its own, if its DOFs are the same points on every rank
        (a study's variants share one mesh); otherwise from zero."""
        coords, kept = solutions
        mine = self.dof_coordinates()
        same = coords.shape == mine.shape and np.array_equal(coords, mine)
        self._static_start = kept if self.comm.allreduce(int(same), op=MPI.MIN) else []

    def forget_statics(self):
        """Static solves start from zero again, as on a fresh block."""
        self._static_basis, self._static_start = [], []

    def _set_static(self, x, corr):
        self.u[:] = x
        self.f_static = corr
        self.v[:] = 0.0
        self.a[:] = 0.0
        self.z[:] = 0.0

    def advance(self, t, H, forces_start, forces_end):
        """From t to t + H with forces varying linearly between the given
        values. Returns (downward displacement, downward velocity) per
        footprint at t + H, the displacement plus c_loc F (`_own`; not the
        velocity: c_loc dF/dt with the ballast's damper d_b is a loop of gain
        d_b c_loc / H, which diverged on the CI scene with ramped inputs)."""
        f0 = self.load_vector(forces_start)
        df = self.load_vector(forces_end) - f0
        f0 = f0 + self.f_static
        n = max(1, math.ceil(H / self.dt - 1e-9))
        self.run(H / n, n, f0, df)
        self.t = t + H
        # One reduction for both footprint outputs and the receivers.
        su, sv, rec = self._reduce(self._local_sums(self.u, self.v) + [self._local_receivers()])
        if len(self.rec_points):
            self.history.append((self.t, rec.reshape(-1, 3)))
        return self._own(su / self.fp_area, np.asarray(forces_end, dtype=float)), sv / self.fp_area

    def _own(self, values, forces):
        """values + c_loc forces (c_loc: near_field); the values alone when off."""
        return values if self.fp_compliance is None else values + self.fp_compliance * forces

    def run(self, dt, n, f0, df):
        """n steps of dt; the load is f0 + (k/n) df at the end of step k.
        In-place numpy on the owned DOFs (one K product per step)."""
        u, v, a, m, z = self.u, self.v, self.a, self.m, self.z
        decay = math.exp(-dt / self.tau) if self.tau > 0.0 else 0.0
        if self._inv is None or self._inv[0] != dt:
            self._inv = (dt, self.mask / (m + 0.5 * dt * self.c))
        inv = self._inv[1]
        W, KU = self.W, self.KU
        w, ku = W.array, KU.array
        vh, r = np.empty_like(v), np.empty_like(v)
        for k in range(1, n + 1):
            np.multiply(a, 0.5 * dt, out=vh)
            vh += v  # v(n + 1/2)
            np.multiply(vh, dt, out=r)
            u += r  # u(n + 1)
            dv = vh
            if decay:  # z(n + 1/2): the filter's exact update with v(n + 1/2) held
                z -= vh
                z *= decay
                z += vh
                dv = z
            for j, (a1, A) in enumerate(self.parts):  # sum A (u + a1 v), a part per ratio
                np.multiply(dv, a1, out=w)
                w += u
                if j == 0:
                    A.mult(W, KU)
                else:
                    A.multAdd(W, KU, KU)
            np.multiply(df, k / n, out=r)
            r += f0
            r -= ku
            r *= 0.5 * dt
            np.multiply(m, vh, out=a)
            r += a
            r *= inv  # v(n + 1)
            np.subtract(r, vh, out=a)
            a *= 2.0 / dt  # a(n + 1)
            v[:] = r

    # ---- receivers and energy -----------------------------------------------
    def receiver_velocities(self):
        """Velocity (3 components) at each receiver, on every rank."""
        return self._reduce([self._local_receivers()])[0].reshape(-1, 3)

    def receiver_series(self):
        """(times, velocities[time, receiver, component])."""
        t = np.array([h[0] for h in self.history])
        v = np.array([h[1] for h in self.history]).reshape(len(t), len(self.rec_points), 3)
        return t, v

    def kinetic_energy(self, dofs_weight=None):
        e = 0.5 * self.m * self.v**2 * (1.0 if dofs_weight is None else dofs_weight)
        return self.comm.allreduce(float(e.sum()), op=MPI.SUM)

    def dof_coordinates(self):
        """Coordinates of each owned DOF (rows repeat per component)."""
        c = self.V.tabulate_dof_coordinates()[: self.V.dofmap.index_map.size_local]
        return np.repeat(c, 3, axis=0)

    def global_dofs(self):
        return self.V.dofmap.index_map.size_global * self.V.dofmap.index_map_bs

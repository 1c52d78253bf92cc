"""The variational forms of the soil: elasticity with layer-wise material,
Lysmer-Kuhlemeyer dashpots and viscous-spring boundary springs, the lumped
mass, and the footprint indicator."""
from __future__ import annotations

import ufl
from dolfinx import fem
from petsc4py import PETSc

from .mesh import ABSORBING, SURFACE


def strain(u):
    return ufl.sym(ufl.grad(u))


def stress(u, f):
    return 2.0 * f["mu"] * strain(u) + f["lam"] * ufl.tr(strain(u)) * ufl.Identity(3)


def boundary_measures(mesh, tags):
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=tags)
    return ds


def stiffness_form(V, f, ds, spring_centre, alpha):
    """K: elasticity plus springs on the absorbing boundary, k_n = alpha_n G/R
    normal and k_t = alpha_t G/R tangential per unit area, R the distance of
    the boundary point from `spring_centre` (the viscous-spring boundary:
    with the dashpots it carries static load and absorbs)."""
    u, w = ufl.TrialFunction(V), ufl.TestFunction(V)
    x = ufl.SpatialCoordinate(V.mesh)
    n = ufl.FacetNormal(V.mesh)
    R = ufl.sqrt(ufl.dot(x - spring_centre, x - spring_centre))
    kn = alpha[0] * f["mu"] / R
    kt = alpha[1] * f["mu"] / R
    un, wn = ufl.dot(u, n), ufl.dot(w, n)
    spring = kn * un * wn + kt * ufl.dot(u - un * n, w - wn * n)
    a = ufl.inner(stress(u, f), strain(w)) * ufl.dx + spring * ds(ABSORBING)
    return fem.form(a)


def damping_stiffness_form(V, f, a1):
    """The stiffness-proportional Rayleigh part with a layer-wise a1."""
    u, w = ufl.TrialFunction(V), ufl.TestFunction(V)
    return fem.form(a1 * ufl.inner(stress(u, f), strain(w)) * ufl.dx)


def assemble_diagonal(form):
    vec = fem.petsc.assemble_vector(form)
    vec.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
    return vec.array.copy()


def lumped_mass(V, f):
    """Row-sum lumped mass (positive for Q1), one entry per DOF."""
    w = ufl.TestFunction(V)
    ones = ufl.as_vector((1.0, 1.0, 1.0))
    return assemble_diagonal(fem.form(f["rho"] * ufl.dot(ones, w) * ufl.dx))


def lumped_damping(V, f, ds, a0, dashpots=True):
    """Diagonal damping: the mass-proportional Rayleigh part a0 M (a0 layer-
    wise) plus the Lysmer-Kuhlemeyer dashpots, rho c_P normal and rho c_S
    tangential per unit area, lumped to the nodes."""
    w = ufl.TestFunction(V)
    n = ufl.FacetNormal(V.mesh)
    ones = ufl.as_vector((1.0, 1.0, 1.0))
    rho, cp, cs = f["rho"], f["cp"], f["cs"]
    dash = ufl.as_vector([rho * (cp * n[i] ** 2 + cs * (1.0 - n[i] ** 2)) for i in range(3)])
    form = a0 * rho * ufl.dot(ones, w) * ufl.dx
    if dashpots:
        form = form + ufl.dot(dash, w) * ds(ABSORBING)
    return assemble_diagonal(fem.form(form))


class FootprintForms:
    """One compiled pair of forms for every footprint: the indicator of the
    rectangle |x - xc| < a/2, |y - yc| < b/2 integrated against the downward
    test component (its load vector) and alone (its modelled area). The
    indicator is integrated at a high quadrature degree, so a footprint need
    not align with the mesh."""

    def __init__(self, V, ds, degree=16):
        mesh = V.mesh
        self.c = {k: fem.Constant(mesh, PETSc.ScalarType(0.0)) for k in ("xc", "yc", "ha", "hb")}
        x = ufl.SpatialCoordinate(mesh)
        inside = ufl.And(
            ufl.lt(abs(x[0] - self.c["xc"]), self.c["ha"]),
            ufl.lt(abs(x[1] - self.c["yc"]), self.c["hb"]),
        )
        chi = ufl.conditional(inside, 1.0, 0.0)
        w = ufl.TestFunction(V)
        dsq = ds(SURFACE, metadata={"quadrature_degree": degree})
        self.load = fem.form(-chi * w[2] * dsq)
        self.area = fem.form(chi * dsq)

    def vector(self, fp):
        self.c["xc"].value = fp.x
        self.c["yc"].value = fp.y
        self.c["ha"].value = 0.5 * fp.along
        self.c["hb"].value = 0.5 * fp.across
        b = assemble_diagonal(self.load)
        area = fem.assemble_scalar(self.area)
        return b, area

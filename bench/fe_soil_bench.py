#!/usr/bin/python3
"""Milliseconds per time step of the finite-element soil against DOFs and
MPI ranks, for the explicit central-difference step the soil uses and, for
comparison, an implicit Newmark step (average acceleration, beta = 1/4,
lumped mass, CG + Jacobi on the effective matrix).

Usage:  bench/fe_soil_bench.py [--dofs 20000,50000,100000,150000] [--steps 100]
        mpirun -n 2 /usr/bin/python3 bench/fe_soil_bench.py ...
Rank 0 prints one row per mesh; each time is the fastest of --repeats runs
(the machine is shared, the fastest is the least disturbed).
"""
import argparse
import math
import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

from mpi4py import MPI  # noqa: E402
from petsc4py import PETSc  # noqa: E402

from fe_soil.model import FESoil  # noqa: E402
from fe_soil.params import Footprint, Layer, SoilParams, uniform_nodes  # noqa: E402

SOIL = Layer(thickness=1.0, density=1900.0, shear_speed=150.0, poisson=1.0 / 3.0, damping=0.02)


def block(dofs):
    """A 2:1:1 half block of 0.5 m cubes with about `dofs` DOFs."""
    nodes = dofs / 3.0
    n = max(2, round((nodes / 2.0) ** (1.0 / 3.0)))
    L, W = 2 * n * 0.5, n * 0.5
    return SoilParams(
        length=L, half_width=W, depth=W, layers=[SOIL],
        footprints=[Footprint(x, 0.25, 2.6) for x in (L / 2 - 0.6, L / 2, L / 2 + 0.6)],
        receivers=[(L / 2, 4.0)],
        x_nodes=uniform_nodes(0, L, 0.5), y_nodes=uniform_nodes(0, W, 0.5), z_nodes=uniform_nodes(-W, 0, 0.5))


def timed(comm, fn, repeats):
    best = math.inf
    for _ in range(repeats):
        comm.Barrier()
        t0 = time.perf_counter()
        fn()
        comm.Barrier()
        best = min(best, comm.allreduce(time.perf_counter() - t0, op=MPI.MAX))
    return best


def newmark_solver(soil, dt, iterations):
    """(effective matrix, KSP) of Newmark beta = 1/4 in the acceleration
    unknown: (M + dt/2 C + dt^2/4 K) a = r."""
    A = soil.K.copy()
    A.scale(0.25 * dt * dt)
    d = A.createVecLeft()
    d.array[:] = soil.m + 0.5 * dt * soil.c
    A.setDiagonal(A.getDiagonal() + d)  # adds the lumped mass and damping
    ksp = PETSc.KSP().create(soil.comm)
    ksp.setOperators(A)
    ksp.setType("cg")
    ksp.getPC().setType("jacobi")
    ksp.setTolerances(rtol=1e-12, max_it=iterations)
    ksp.setNormType(PETSc.KSP.NormType.NONE)  # a fixed count: max_it iterations
    ksp.setInitialGuessNonzero(True)
    return A, ksp


def newmark_steps(soil, ksp, dt, n):
    u, v, a = soil.U, soil.U.duplicate(), soil.U.duplicate()
    r, ku = soil.U.duplicate(), soil.U.duplicate()
    for _ in range(n):
        u.axpy(dt, v)
        u.axpy(0.25 * dt * dt, a)  # predictor (the a-term of beta = 1/4)
        v.axpy(0.5 * dt, a)
        soil.K.mult(u, ku)
        r.array[:] = -ku.array - soil.c * v.array
        ksp.solve(r, a)
        u.axpy(0.25 * dt * dt, a)
        v.axpy(0.5 * dt, a)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--dofs", default="20000,50000,100000,150000")
    ap.add_argument("--steps", type=int, default=100)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--newmark-dt", type=float, default=1e-4)
    ap.add_argument("--cg-iterations", type=int, default=3)
    args = ap.parse_args()
    comm = MPI.COMM_WORLD
    if comm.rank == 0:
        print(f"ranks {comm.size}; explicit: one K product per step; Newmark: "
              f"{args.cg_iterations} CG + Jacobi iterations per step")
        print(f"{'DOFs':>8} {'setup s':>8} {'dt_stable ms':>12} {'explicit ms/step':>16} "
              f"{'K product ms':>12} {'Newmark ms/step':>15}")
    for target in (int(x) for x in args.dofs.split(",")):
        t0 = time.perf_counter()
        soil = FESoil(block(target), comm)
        setup = comm.allreduce(time.perf_counter() - t0, op=MPI.MAX)
        f0 = soil.load_vector([1e4, 2e4, 1e4])
        df = 0.0 * f0
        explicit = timed(comm, lambda: soil.run(soil.dt, args.steps, f0, df), args.repeats) / args.steps
        product = timed(comm, lambda: [soil.K.mult(soil.U, soil.KU) for _ in range(args.steps)],
                        args.repeats) / args.steps
        _, ksp = newmark_solver(soil, args.newmark_dt, args.cg_iterations)
        newmark = timed(comm, lambda: newmark_steps(soil, ksp, args.newmark_dt, args.steps // 2),
                        args.repeats) / (args.steps // 2)
        if comm.rank == 0:
            print(f"{soil.global_dofs():>8} {setup:>8.1f} {soil.dt * 1e3:>12.3f} {explicit * 1e3:>16.2f} "
                  f"{product * 1e3:>12.2f} {newmark * 1e3:>15.2f}", flush=True)


if __name__ == "__main__":
    main()

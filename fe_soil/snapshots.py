"""The FE soil's velocity field over time in an XDMF file (ParaView reads
it): the mesh once, then the velocity at each snapshot's time."""
import dolfinx.io


def open_xdmf(soil, path):
    """An XDMF file of `soil` (model.FESoil) with its mesh; `write_snapshot`
    adds the velocity."""
    xdmf = dolfinx.io.XDMFFile(soil.comm, path, "w")
    xdmf.write_mesh(soil.mesh)
    soil.vfun.name = "velocity"
    return xdmf


def write_snapshot(soil, xdmf):
    """The velocity at the soil's current time."""
    soil.vfun.x.array[: soil.n_owned] = soil.v
    soil.vfun.x.scatter_forward()
    xdmf.write_function(soil.vfun, soil.t)

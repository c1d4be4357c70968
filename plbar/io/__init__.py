"""File formats: meshes, other FE programs' structures, one response on the mesh, ParaView output.

Mesh files (meshio), structure files (``.npz`` of matrices: :mod:`.structures`), VTU/PVD and XDMF/HDF5.

No solving here.  meshio and pyvista are imported inside the functions that
need them, so ``import plbar`` does not load them.
"""

from .meshfile import SHIPPED, read_nodes, write_nodes, write_shipped
from .structures import file_digest, read_structure, write_structure
from .sampling import CELL_FIELDS, POINT_FIELDS, ResponseData, motion_data, nodal_stress, response_data
from .vtk import FORMATS, ResponseFiles, load_pvd, write_data, write_xi_along_mesh

__all__ = ["SHIPPED", "read_nodes", "write_nodes", "write_shipped", "POINT_FIELDS", "CELL_FIELDS", "ResponseData",
           "nodal_stress", "response_data", "motion_data", "FORMATS", "ResponseFiles", "load_pvd", "write_data",
           "write_xi_along_mesh", "read_structure", "write_structure", "file_digest"]

"""nitschedyn - Python bindings of libnitschedyn over its C ABI (ctypes, numpy).

Nitsche's method for dynamic frictionless contact of a linear elastic body
with a rigid obstacle. Two layers:

* ``lib``: the ctypes library with the prototype of every ``nd_*`` function
  of nitschedyn.h, to call them exactly as in C (the manual pages apply);
* ``Mesh``, ``Problem``, ``write_pvd``: a thin Pythonic layer taking and
  returning numpy arrays, raising ``Error`` (status code, name and the
  message of ``nd_last_error()``) instead of returning negative codes.
  ``Mesh`` and ``Problem`` own their handle: ``close()`` or a ``with`` block
  releases it (closing twice is harmless).

The ND_* constants (e.g. ``ND_SCHEME_HYBRID``, ``ND_ERR_TIMESTEP``) come from
``_constants.py``, generated at build time from the X-macro lists of
nitschedyn.h by the same program that writes the Fortran parameters; the
dictionaries ``STATUS``, ``SCHEME``, ``FIELD``, ``SCALAR``, ``SOLVER``, ``GUARD``, ``MATRIX`` map each
name to ``(value, description)``.

The shared library is found in this order: the path in the environment
variable ND_LIBRARY; the library this package was built or installed with
(``_library_path.py``); ``libnitschedyn.so.<major>`` through the dynamic
loader (LD_LIBRARY_PATH, the system directories).

Example::

    import numpy as np, nitschedyn as nd
    with nd.Mesh.interval(40, 0.0, 1.0) as m:
        m.mark_boundary_box(1, [-0.5], [0.5])       # x = 0: contact
        m.mark_boundary_box(2, [0.5], [1.5])        # x = 1: clamped
        p = nd.Problem(m, degree=1)                 # copies the mesh
    with p:
        p.set_material(1.0, 0.0, 1.0)
        p.set_dirichlet(2)
        p.set_contact_plane(1, [0.0], [1.0])
        p.set_nitsche(1.0, 0.2)
        p.set_scheme(nd.ND_SCHEME_HYBRID)
        p.set_timestep(1 / 80)
        x = p.node_coordinates()[:, 0]
        p.set_initial_state(0.5 * (1 - x))
        for _ in range(240):
            p.step()
        print(p.scalar(nd.ND_ENERGY_AUGMENTED))     # close to 1/8
"""

import ctypes
import os
import weakref

try:
    import numpy as np
except ImportError as e:  # python3 -m nitschedyn.plot runs without numpy; Mesh and Problem need it
    _NUMPY_MISSING = "nitschedyn needs numpy (Debian: apt-get install python3-numpy): %s" % e

    class _NoNumpy:
        def __getattr__(self, name):
            raise ImportError(_NUMPY_MISSING)

    np = _NoNumpy()

try:  # the package built by CMake (bindings/python) or installed
    from . import _constants
    from ._constants import *  # noqa: F401,F403  (the ND_* names)
except ImportError:  # nitschedyn.py next to a generated _constants.py
    import _constants  # type: ignore
    from _constants import *  # type: ignore # noqa: F401,F403

__all__ = ["Error", "Mesh", "Problem", "write_pvd", "version", "last_error", "strerror", "lib",
           "STATUS", "SCHEME", "FIELD", "SCALAR", "SOLVER", "GUARD", "MATRIX"]
__all__ += [name for name in dir(_constants) if name.startswith("ND_")]
__version__ = _constants.ND_VERSION_STRING

# ---- the library --------------------------------------------------------------


def _candidates():
    env = os.environ.get("ND_LIBRARY")
    if env:
        yield env
        return
    try:
        from . import _library_path as where
    except ImportError:
        where = None
    if where is not None:
        path = where.LIBRARY
        if where.RELATIVE:
            path = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), path))
        yield path
    yield "libnitschedyn.so.%d" % _constants.ND_VERSION_MAJOR


def _load():
    errors = []
    for path in _candidates():
        try:
            return ctypes.CDLL(path)
        except OSError as e:
            errors.append("%s: %s" % (path, e))
    raise ImportError("nitschedyn: cannot load libnitschedyn (set ND_LIBRARY to its path):\n  "
                      + "\n  ".join(errors))


lib = _load()

_int, _i64, _dbl, _ptr = ctypes.c_int, ctypes.c_int64, ctypes.c_double, ctypes.c_void_p
_pint, _pi64, _pdbl, _pptr = (ctypes.POINTER(ctypes.c_int), ctypes.POINTER(ctypes.c_int64),
                              ctypes.POINTER(ctypes.c_double), ctypes.POINTER(ctypes.c_void_p))
_str = ctypes.c_char_p
MONITOR = ctypes.CFUNCTYPE(_int, _ptr, _ptr)  # int (*)(nd_problem, void *)
# nd_distance_fn: int (*)(double t, const double *x, double *distance, double *normal, void *user)
DISTANCE = ctypes.CFUNCTYPE(_int, _dbl, _pdbl, _pdbl, _pdbl, _ptr)

# every function of nitschedyn.h: name -> (result, argument types); handles
# are void *, nd_mesh * and nd_problem * are void **
_PROTOTYPES = {
    "nd_version": (_int, [_pint, _pint, _pint]),
    "nd_last_error": (_str, []),
    "nd_strerror": (_str, [_int]),
    "nd_set_blas_threads": (_int, [_int]),
    "nd_get_blas_threads": (_int, [_pint]),
    "nd_mesh_create": (_int, [_int, _i64, _pdbl, _i64, _pi64, _pptr]),
    "nd_mesh_create_interval": (_int, [_i64, _dbl, _dbl, _pptr]),
    "nd_mesh_create_rectangle": (_int, [_i64, _i64, _pdbl, _pdbl, _pptr]),
    "nd_mesh_create_box": (_int, [_i64, _i64, _i64, _pdbl, _pdbl, _pptr]),
    "nd_mesh_create_cells": (_int, [_int, _int, _i64, _pdbl, _i64, _pi64, _pptr]),
    "nd_mesh_create_mixed": (_int, [_int, _i64, _pdbl, _i64, _pint, _pi64, _pptr]),
    "nd_mesh_create_rectangle_cells": (_int, [_i64, _i64, _pdbl, _pdbl, _int, _pptr]),
    "nd_mesh_create_box_cells": (_int, [_i64, _i64, _i64, _pdbl, _pdbl, _int, _pptr]),
    "nd_mesh_read_gmsh": (_int, [_str, _pptr]),
    "nd_mesh_set_region": (_int, [_ptr, _int, _i64, _pi64]),
    "nd_mesh_mark_boundary_box": (_int, [_ptr, _int, _pdbl, _pdbl]),
    "nd_mesh_set_cell_region": (_int, [_ptr, _int, _i64, _pi64]),
    "nd_mesh_get_cell_regions": (_int, [_ptr, _i64, _pint]),
    "nd_mesh_get_dimension": (_int, [_ptr, _pint]),
    "nd_mesh_get_vertex_count": (_int, [_ptr, _pi64]),
    "nd_mesh_get_cell_count": (_int, [_ptr, _pi64]),
    "nd_mesh_get_region_size": (_int, [_ptr, _int, _pi64]),
    "nd_mesh_destroy": (_int, [_pptr]),
    "nd_problem_create": (_int, [_ptr, _int, _pptr]),
    "nd_problem_set_material": (_int, [_ptr, _dbl, _dbl, _dbl]),
    "nd_problem_set_material_region": (_int, [_ptr, _int, _dbl, _dbl, _dbl]),
    "nd_problem_set_dirichlet": (_int, [_ptr, _int]),
    "nd_problem_set_dirichlet_value": (_int, [_ptr, _int, _pdbl]),
    "nd_problem_set_dirichlet_nodal": (_int, [_ptr, _i64, _pdbl]),
    "nd_problem_set_body_force": (_int, [_ptr, _pdbl]),
    "nd_problem_set_neumann": (_int, [_ptr, _int, _pdbl]),
    "nd_problem_set_contact_plane": (_int, [_ptr, _int, _pdbl, _pdbl]),
    "nd_problem_set_contact_pair": (_int, [_ptr, _int, _int]),
    "nd_problem_add_contact_sphere": (_int, [_ptr, _int, _pdbl, _dbl, _int]),
    "nd_problem_add_contact_cylinder": (_int, [_ptr, _int, _pdbl, _pdbl, _dbl, _int]),
    "nd_problem_add_contact_distance": (_int, [_ptr, _int, DISTANCE, _ptr]),
    "nd_problem_move_obstacle": (_int, [_ptr, _int, _int, _pdbl, _pdbl]),
    "nd_problem_set_nitsche": (_int, [_ptr, _dbl, _dbl]),
    "nd_problem_set_friction": (_int, [_ptr, _int, _int, _pdbl]),
    "nd_problem_set_scheme": (_int, [_ptr, _int, _pdbl]),
    "nd_problem_set_nodal_forces": (_int, [_ptr, _i64, _pdbl]),
    "nd_problem_set_newton": (_int, [_ptr, _dbl, _dbl, _int]),
    "nd_problem_set_guard": (_int, [_ptr, _int, _dbl]),
    "nd_problem_set_mass_lumping": (_int, [_ptr, _int]),
    "nd_problem_set_mass_redistribution": (_int, [_ptr, _int]),
    "nd_problem_set_damping": (_int, [_ptr, _dbl, _dbl]),
    "nd_problem_set_plane_stress": (_int, [_ptr, _int]),
    "nd_problem_set_linear_solver": (_int, [_ptr, _int]),
    "nd_problem_set_comm_f": (_int, [_ptr, _int]),
    "nd_problem_set_distributed_state": (_int, [_ptr, _int]),
    "nd_problem_set_timestep": (_int, [_ptr, _dbl]),
    "nd_problem_set_adaptive_timestep": (_int, [_ptr, _dbl, _dbl, _dbl]),
    "nd_problem_set_initial_state": (_int, [_ptr, _i64, _pdbl, _pdbl]),
    "nd_problem_get_state_size": (_int, [_ptr, ctypes.POINTER(ctypes.c_int64)]),
    "nd_problem_save_state": (_int, [_ptr, _i64, ctypes.c_void_p]),
    "nd_problem_load_state": (_int, [_ptr, _i64, ctypes.c_void_p]),
    "nd_problem_save_state_file": (_int, [_ptr, _str]),
    "nd_problem_load_state_file": (_int, [_ptr, _str]),
    "nd_problem_set_state": (_int, [_ptr, _i64, _pdbl, _pdbl]),
    "nd_problem_set_monitor": (_int, [_ptr, MONITOR, _ptr]),
    "nd_problem_get_node_count": (_int, [_ptr, _pi64]),
    "nd_problem_get_node_coordinates": (_int, [_ptr, _i64, _pdbl]),
    "nd_problem_get_contact_point_count": (_int, [_ptr, _pi64]),
    "nd_problem_get_contact_points": (_int, [_ptr, _i64, _pdbl, _pdbl]),
    "nd_problem_setup": (_int, [_ptr]),
    "nd_problem_estimate_critical_timestep": (_int, [_ptr, _pdbl]),
    "nd_step": (_int, [_ptr]),
    "nd_get_field": (_int, [_ptr, _int, _i64, _pdbl]),
    "nd_problem_get_owned_node_count": (_int, [_ptr, _pi64]),
    "nd_get_field_owned": (_int, [_ptr, _int, _i64, _pdbl, _pi64]),
    "nd_get_field_gathered": (_int, [_ptr, _int, _int, _i64, _pdbl]),
    "nd_get_scalar": (_int, [_ptr, _int, _pdbl]),
    "nd_get_region_scalar": (_int, [_ptr, _int, _int, _pdbl]),
    "nd_get_contact_pressure": (_int, [_ptr, _i64, _pdbl]),
    "nd_get_contact_pressure_applied": (_int, [_ptr, _i64, _pdbl]),
    "nd_problem_destroy": (_int, [_pptr]),
    "nd_problem_write_vtu": (_int, [_ptr, _str]),
    "nd_write_pvd": (_int, [_str, _i64, ctypes.POINTER(_str), _pdbl]),
    "nd_problem_get_matrix": (_int, [_ptr, _int, _pi64, _pi64, _pi64, _pi64, _pdbl]),
    "nd_problem_get_dof_map": (_int, [_ptr, _i64, _pi64, _pint]),
    "nd_problem_get_load": (_int, [_ptr, _i64, _pdbl]),
    "nd_problem_get_cells": (_int, [_ptr, _pi64, _pint, _pi64]),
    "nd_problem_contact_residual": (_int, [_ptr, _i64, _pdbl, _pdbl]),
    "nd_problem_contact_tangent": (_int, [_ptr, _i64, _pdbl, _pi64, _pi64, _pi64, _pdbl]),
    "nd_problem_contact_step_residual": (_int, [_ptr, _i64, _pdbl, _pdbl, _pdbl]),
    "nd_problem_contact_step_tangent": (_int, [_ptr, _i64, _pdbl, _pdbl, _pi64, _pi64, _pi64, _pdbl]),
    "nd_problem_contact_values": (_int, [_ptr, _i64, _pdbl, _int, _pdbl]),
}
for _name, (_res, _args) in _PROTOTYPES.items():
    _f = getattr(lib, _name)
    _f.restype, _f.argtypes = _res, _args


def _check_version():
    major, minor, patch = _int(), _int(), _int()
    lib.nd_version(ctypes.byref(major), ctypes.byref(minor), ctypes.byref(patch))
    if major.value != _constants.ND_VERSION_MAJOR:
        raise ImportError("nitschedyn: the library is version %d.%d.%d, these bindings need %d.x"
                          % (major.value, minor.value, patch.value, _constants.ND_VERSION_MAJOR))


_check_version()

# ---- errors and small helpers ------------------------------------------------------

_STATUS_NAMES = {value: name for name, (value, _) in _constants.STATUS.items()}


class Error(Exception):
    """A call of libnitschedyn failed: ``code`` (ND_ERR_*), ``name`` (its
    name), ``message`` (nd_last_error(), naming the function and argument)."""

    def __init__(self, code, message):
        self.code = code
        self.name = _STATUS_NAMES.get(code, "status %d" % code)
        self.message = message
        super().__init__("%s [%s]" % (message or strerror(code), self.name))


def version():
    """(major, minor, patch) of the loaded library."""
    v = [_int(), _int(), _int()]
    lib.nd_version(*(ctypes.byref(x) for x in v))
    return tuple(x.value for x in v)


def last_error():
    """nd_last_error(): the calling thread's last error message."""
    return (lib.nd_last_error() or b"").decode("utf-8", "replace")


def strerror(code):
    """nd_strerror(code)."""
    return (lib.nd_strerror(code) or b"").decode("utf-8", "replace")


def _check(status):
    if status < 0:
        raise Error(status, last_error())
    return status


def set_blas_threads(threads):
    """nd_set_blas_threads(threads): the BLAS threads inside the library's
    calls (process-wide; default 1; 0 leaves the BLAS as the caller set it)."""
    _check(lib.nd_set_blas_threads(threads))


def get_blas_threads():
    """nd_get_blas_threads(): the library's BLAS thread limit."""
    n = _int()
    _check(lib.nd_get_blas_threads(ctypes.byref(n)))
    return n.value


def _doubles(values, count=None, what="array"):
    """A C-contiguous float64 copy (or view) of values, of count entries."""
    a = np.ascontiguousarray(values, dtype=np.float64).reshape(-1)
    if count is not None and a.size != count:
        raise ValueError("%s has %d values, expected %d" % (what, a.size, count))
    return a


def _dptr(a):
    return None if a is None else a.ctypes.data_as(_pdbl)


def _i64ptr(a):
    return a.ctypes.data_as(_pi64)


# ---- mesh --------------------------------------------------------------------------


class _Handle:
    """Owns one nd_* handle; close() destroys it (harmless twice)."""

    _destroy = None

    def __init__(self):
        self._h = _ptr()

    @property
    def handle(self):
        """The C handle (a ctypes.c_void_p; NULL once closed)."""
        return self._h

    def close(self):
        if self._h:
            type(self)._destroy(ctypes.byref(self._h))

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def __del__(self):
        try:
            self.close()
        except Exception:  # at interpreter shutdown lib may be gone
            pass


class Mesh(_Handle):
    """A mesh (nd_mesh) of simplices, quadrilaterals or hexahedra (or 2D
    triangles and quadrilaterals mixed: Mesh.mixed), with boundary regions."""

    _destroy = lib.nd_mesh_destroy

    def __init__(self, coords=None, cells=None, cell_type=0):
        """A mesh from coords (n_nodes, dim) and cells (n_cells, dim+1) of
        0-based vertex indices (both copied); with cell_type
        ND_CELL_QUADRILATERAL or ND_CELL_HEXAHEDRON, cells (n_cells, 2**dim)
        (nd_mesh_create_cells). Mesh() alone is empty, for the constructors
        below."""
        super().__init__()
        if coords is None:
            return
        x = np.ascontiguousarray(coords, dtype=np.float64)
        if x.ndim == 1:  # 1D: a flat list of x
            x = x.reshape(-1, 1)
        c = np.ascontiguousarray(cells, dtype=np.int64)
        dim = x.shape[1]
        nv = dim + 1 if cell_type == 0 else 2**dim
        if c.ndim != 2 or c.shape[1] != nv:
            raise ValueError("cells must have shape (n_cells, %d)" % nv)
        if cell_type == 0:
            _check(lib.nd_mesh_create(dim, x.shape[0], _dptr(x), c.shape[0], _i64ptr(c), ctypes.byref(self._h)))
        else:
            _check(lib.nd_mesh_create_cells(dim, cell_type, x.shape[0], _dptr(x), c.shape[0], _i64ptr(c),
                                            ctypes.byref(self._h)))

    @classmethod
    def mixed(cls, coords, cell_types, cells):
        """A mesh whose cells have their own types (nd_mesh_create_mixed):
        coords (n_nodes, dim), cell_types (n_cells) of ND_CELL_LIST, cells
        each cell's vertices (a list of lists, or all of them in turn)."""
        x = np.ascontiguousarray(coords, dtype=np.float64)
        if x.ndim == 1:  # 1D: a flat list of x
            x = x.reshape(-1, 1)
        types = np.ascontiguousarray(cell_types, dtype=np.intc).reshape(-1)
        flat = [v for cell in cells for v in np.atleast_1d(cell)]
        c = np.ascontiguousarray(flat, dtype=np.int64)
        m = cls()
        _check(lib.nd_mesh_create_mixed(x.shape[1], x.shape[0], _dptr(x), types.size, types.ctypes.data_as(_pint),
                                        _i64ptr(c), ctypes.byref(m._h)))
        return m

    @classmethod
    def interval(cls, n_cells, a=0.0, b=1.0):
        m = cls()
        _check(lib.nd_mesh_create_interval(n_cells, a, b, ctypes.byref(m._h)))
        return m

    @classmethod
    def rectangle(cls, nx, ny, lo, hi, cell_type=0):
        """nx*ny rectangles, each in two triangles (cell_type 0) or whole
        (ND_CELL_QUADRILATERAL)"""
        m = cls()
        if cell_type == 0:
            _check(lib.nd_mesh_create_rectangle(nx, ny, _dptr(_doubles(lo, 2, "lo")), _dptr(_doubles(hi, 2, "hi")),
                                                ctypes.byref(m._h)))
        else:
            _check(lib.nd_mesh_create_rectangle_cells(nx, ny, _dptr(_doubles(lo, 2, "lo")),
                                                      _dptr(_doubles(hi, 2, "hi")), cell_type, ctypes.byref(m._h)))
        return m

    @classmethod
    def box(cls, nx, ny, nz, lo, hi, cell_type=0):
        """nx*ny*nz boxes, each in six tetrahedra (cell_type 0) or whole
        (ND_CELL_HEXAHEDRON)"""
        m = cls()
        if cell_type == 0:
            _check(lib.nd_mesh_create_box(nx, ny, nz, _dptr(_doubles(lo, 3, "lo")), _dptr(_doubles(hi, 3, "hi")),
                                          ctypes.byref(m._h)))
        else:
            _check(lib.nd_mesh_create_box_cells(nx, ny, nz, _dptr(_doubles(lo, 3, "lo")), _dptr(_doubles(hi, 3, "hi")),
                                                cell_type, ctypes.byref(m._h)))
        return m

    @classmethod
    def read_gmsh(cls, path):
        m = cls()
        _check(lib.nd_mesh_read_gmsh(os.fsencode(path), ctypes.byref(m._h)))
        return m

    @property
    def dimension(self):
        d = _int()
        _check(lib.nd_mesh_get_dimension(self._h, ctypes.byref(d)))
        return d.value

    @property
    def vertex_count(self):
        n = _i64()
        _check(lib.nd_mesh_get_vertex_count(self._h, ctypes.byref(n)))
        return n.value

    @property
    def cell_count(self):
        n = _i64()
        _check(lib.nd_mesh_get_cell_count(self._h, ctypes.byref(n)))
        return n.value

    def region_size(self, region):
        n = _i64()
        _check(lib.nd_mesh_get_region_size(self._h, region, ctypes.byref(n)))
        return n.value

    def set_region(self, region, facets):
        """Adds boundary facets (n_facets, dim) of 0-based vertex indices."""
        f = np.ascontiguousarray(facets, dtype=np.int64)
        dim = self.dimension
        f = f.reshape(-1, dim)
        _check(lib.nd_mesh_set_region(self._h, region, f.shape[0], _i64ptr(f)))

    def set_cell_region(self, region, cells):
        """Puts cells (0-based indices) in cell region `region` (>= 0; 0: none)."""
        c = np.ascontiguousarray(cells, dtype=np.int64).reshape(-1)
        _check(lib.nd_mesh_set_cell_region(self._h, region, c.shape[0], _i64ptr(c)))

    @property
    def cell_regions(self):
        """Each cell's region (0: in none), an int32 array of cell_count values."""
        r = np.zeros(self.cell_count, dtype=np.int32)
        _check(lib.nd_mesh_get_cell_regions(self._h, r.shape[0], r.ctypes.data_as(_pint)))
        return r

    def mark_boundary_box(self, region, lo, hi):
        """Adds the boundary facets whose vertices all lie in [lo, hi]."""
        dim = self.dimension
        _check(lib.nd_mesh_mark_boundary_box(self._h, region, _dptr(_doubles(lo, dim, "lo")),
                                             _dptr(_doubles(hi, dim, "hi"))))


# ---- problem -----------------------------------------------------------------------


class Problem(_Handle):
    """A dynamic contact problem (nd_problem) on its own copy of a mesh.

    Per-node arrays are (n_nodes, dim) numpy arrays in the library's node
    order (mesh vertices first, then P2 edge nodes); setters also accept any
    array of n_nodes*dim values.
    """

    _destroy = lib.nd_problem_destroy

    def __init__(self, mesh, degree=1):
        super().__init__()
        self.dim = mesh.dimension
        self._monitor = None  # the ctypes callback, kept alive
        self._monitor_error = None
        self._distances = []  # the ctypes callbacks of the distance obstacles, kept alive
        _check(lib.nd_problem_create(mesh.handle, degree, ctypes.byref(self._h)))

    def _vector(self, values, what):
        return _doubles(values, self.dim, what)

    def _nodal(self, values, what):
        return None if values is None else _doubles(values, self.node_count * self.dim, what)

    # definition
    def set_material(self, young, poisson, density):
        _check(lib.nd_problem_set_material(self._h, young, poisson, density))

    def set_material_region(self, cell_region, young, poisson, density):
        """The material of the cells of a cell region (>= 1); the others keep set_material's."""
        _check(lib.nd_problem_set_material_region(self._h, cell_region, young, poisson, density))

    def set_dirichlet(self, region):
        _check(lib.nd_problem_set_dirichlet(self._h, region))

    def set_dirichlet_value(self, region, u):
        """Prescribed motion: the clamped region's displacement (dim values) at
        t^{n+1} of the next step (before the first step, a first call gives t^0's)."""
        _check(lib.nd_problem_set_dirichlet_value(self._h, region, _dptr(self._vector(u, "u"))))

    def set_dirichlet_nodal(self, u):
        """Prescribed motion per FE node (node_count x dim values; only the clamped DOFs are read)."""
        _check(lib.nd_problem_set_dirichlet_nodal(self._h, self.node_count, _dptr(self._nodal(u, "u"))))

    def set_body_force(self, f):
        _check(lib.nd_problem_set_body_force(self._h, _dptr(self._vector(f, "f"))))

    def set_neumann(self, region, g):
        _check(lib.nd_problem_set_neumann(self._h, region, _dptr(self._vector(g, "g"))))

    def set_contact_plane(self, region, point, normal):
        _check(lib.nd_problem_set_contact_plane(self._h, region, _dptr(self._vector(point, "point")),
                                                _dptr(self._vector(normal, "normal"))))

    def set_contact_pair(self, slave, master):
        """Contact between two bodies of the mesh: the slave region's points
        against the master region's surface (nd_problem_set_contact_pair(3))."""
        _check(lib.nd_problem_set_contact_pair(self._h, slave, master))

    def add_contact_sphere(self, region, center, radius, inside=False):
        """Another obstacle of the region: a sphere (a circle in 2D); inside:
        the body within it (a bowl). At each contact point the nearest acts."""
        _check(lib.nd_problem_add_contact_sphere(self._h, region, _dptr(self._vector(center, "center")), radius,
                                                 1 if inside else 0))

    def add_contact_cylinder(self, region, point, axis, radius, inside=False):
        """Another obstacle of the region (3D): the circular cylinder of this
        axis through point."""
        _check(lib.nd_problem_add_contact_cylinder(self._h, region, _dptr(self._vector(point, "point")),
                                                   _dptr(self._vector(axis, "axis")), radius, 1 if inside else 0))

    def add_contact_distance(self, region, fn):
        """Another obstacle of the region: fn(t, x) -> (distance, normal), x
        and normal dim values, the signed distance positive on the body's
        side and the unit normal from the obstacle towards the body. An
        exception raised by fn fails the step (ND_ERR_CALLBACK) and is
        raised again by step()."""
        dim = self.dim

        def trampoline(t, x, d, nu, _user):
            try:
                dist, normal = fn(t, np.ctypeslib.as_array(x, shape=(dim,)).copy())
                normal = np.asarray(normal, dtype=np.float64).reshape(-1)
                if normal.size != dim:
                    raise ValueError("the distance callback's normal has %d values, expected %d" % (normal.size, dim))
                d[0] = float(dist)
                for k in range(dim):
                    nu[k] = normal[k]
                return 0
            except BaseException as e:  # noqa: B902 - carried to step()
                self._monitor_error = e
                return 1
        cb = DISTANCE(trampoline)
        _check(lib.nd_problem_add_contact_distance(self._h, region, cb, None))
        self._distances.append(cb)

    def move_obstacle(self, region, index, translation, rotation=None):
        """Places the region's added obstacle `index` (0-based) at x -> R x +
        translation from its definition (rotation: dim x dim, None: none),
        where it is at t^{n+1} of the next step."""
        r = None if rotation is None else _doubles(rotation, self.dim * self.dim, "rotation")
        _check(lib.nd_problem_move_obstacle(self._h, region, index, _dptr(self._vector(translation, "translation")),
                                            _dptr(r)))

    def set_nitsche(self, theta, gamma0):
        _check(lib.nd_problem_set_nitsche(self._h, theta, gamma0))

    def set_friction(self, region, law, coefficient=None):
        """The friction law of a contact region: ND_FRICTION_NONE,
        ND_FRICTION_TRESCA (coefficient: the threshold s, a stress) or
        ND_FRICTION_COULOMB (coefficient: F)."""
        a = None if coefficient is None else np.array([float(coefficient)])
        _check(lib.nd_problem_set_friction(self._h, region, law, _dptr(a)))

    def set_scheme(self, scheme, params=None):
        """An ND_SCHEME_* value and its parameters (SCHEME[name] describes them):
        ND_SCHEME_THETA (theta,), ND_SCHEME_NEWMARK (beta, gamma),
        ND_SCHEME_HYBRID (), ND_SCHEME_GENERALIZED_ALPHA (rho_inf,)."""
        a = None
        if params is not None:
            # the library reads as many values as the scheme takes: pad with
            # NaN, which every scheme refuses, so that too few values are an
            # nd.Error (ND_ERR_SCHEME) and never a read past the array
            given = _doubles(params)
            a = np.full(max(8, given.size), np.nan)
            a[:given.size] = given
        _check(lib.nd_problem_set_scheme(self._h, scheme, _dptr(a)))

    def set_nodal_forces(self, f):
        _check(lib.nd_problem_set_nodal_forces(self._h, self.node_count, _dptr(self._nodal(f, "f"))))

    def set_newton(self, rtol, atol, max_iter):
        _check(lib.nd_problem_set_newton(self._h, rtol, atol, max_iter))

    def set_guard(self, guard, value):
        """An ND_GUARD_* and its value (0 disables it); GUARD describes them."""
        _check(lib.nd_problem_set_guard(self._h, guard, float(value)))

    def set_mass_lumping(self, lumped):
        _check(lib.nd_problem_set_mass_lumping(self._h, int(bool(lumped))))

    def set_mass_redistribution(self, on):
        _check(lib.nd_problem_set_mass_redistribution(self._h, int(bool(on))))

    def set_damping(self, alpha, beta):
        """Rayleigh damping C = alpha M + beta K (0, 0: off, the default)."""
        _check(lib.nd_problem_set_damping(self._h, float(alpha), float(beta)))

    def set_plane_stress(self, on):
        """Plane stress in 2D (default: plane strain); ND_ERR_DIMENSION elsewhere."""
        _check(lib.nd_problem_set_plane_stress(self._h, int(bool(on))))

    def set_linear_solver(self, solver):
        _check(lib.nd_problem_set_linear_solver(self._h, solver))

    def set_comm_f(self, fortran_comm):
        """The MPI communicator's Fortran handle (mpi4py: comm.py2f())."""
        _check(lib.nd_problem_set_comm_f(self._h, fortran_comm))

    def set_distributed_state(self, on):
        """Each rank keeps the state on its rows (reads of whole fields become collective)."""
        _check(lib.nd_problem_set_distributed_state(self._h, int(bool(on))))

    def set_timestep(self, tau):
        _check(lib.nd_problem_set_timestep(self._h, tau))

    def set_adaptive_timestep(self, tolerance, tau_min=0.0, tau_max=0.0):
        """Adaptive steps in [tau_min, tau_max]; tolerance 0: fixed steps."""
        _check(lib.nd_problem_set_adaptive_timestep(self._h, tolerance, tau_min, tau_max))

    def set_initial_state(self, u0=None, v0=None):
        """u0, v0 per node; None means zero."""
        _check(lib.nd_problem_set_initial_state(self._h, self.node_count, _dptr(self._nodal(u0, "u0")),
                                                _dptr(self._nodal(v0, "v0"))))

    def save_state(self):
        """The checkpoint of the state at t^n, as bytes."""
        n = ctypes.c_int64()
        _check(lib.nd_problem_get_state_size(self._h, ctypes.byref(n)))
        buf = ctypes.create_string_buffer(n.value)
        _check(lib.nd_problem_save_state(self._h, n.value, buf))
        return buf.raw

    def load_state(self, data):
        """Restores a checkpoint of save_state() (all or nothing)."""
        data = bytes(data)
        _check(lib.nd_problem_load_state(self._h, len(data), ctypes.c_char_p(data)))

    def save_state_file(self, path):
        """The checkpoint of save_state() written to a file: atomically over a
        regular file; a symlink is followed, a device or FIFO written in place
        (nd_problem_save_state(3), FILES)."""
        _check(lib.nd_problem_save_state_file(self._h, os.fsencode(path)))

    def load_state_file(self, path):
        """Restores a checkpoint file of save_state_file() (all or nothing)."""
        _check(lib.nd_problem_load_state_file(self._h, os.fsencode(path)))

    def set_state(self, u=None, v=None):
        """Overwrites u and/or v (per node) at the current time; t, n and W stay."""
        _check(lib.nd_problem_set_state(self._h, self.node_count, _dptr(self._nodal(u, "u")),
                                        _dptr(self._nodal(v, "v"))))

    def set_monitor(self, fn):
        """fn(problem) after every accepted step; a true result makes step()
        return ND_MONITOR_STOP (the step is kept). An exception raised by fn
        stops too and is raised again by step(). None removes the monitor."""
        if fn is None:
            cb = MONITOR()  # NULL
        else:
            problem = weakref.ref(self)  # no reference cycle through the callback

            def trampoline(_p, _userdata):
                try:
                    return 1 if fn(problem()) else 0
                except BaseException as e:  # noqa: B902 - carried to step()
                    self._monitor_error = e
                    return 1
            cb = MONITOR(trampoline)
        _check(lib.nd_problem_set_monitor(self._h, cb, None))
        self._monitor = cb

    # queries
    @property
    def node_count(self):
        n = _i64()
        _check(lib.nd_problem_get_node_count(self._h, ctypes.byref(n)))
        return n.value

    def node_coordinates(self):
        n = self.node_count
        x = np.empty((n, self.dim))
        _check(lib.nd_problem_get_node_coordinates(self._h, n, _dptr(x)))
        return x

    @property
    def contact_point_count(self):
        n = _i64()
        _check(lib.nd_problem_get_contact_point_count(self._h, ctypes.byref(n)))
        return n.value

    def contact_points(self):
        """(coords (n, dim), weights (n,)) of the contact quadrature points."""
        n = self.contact_point_count
        x, w = np.empty((n, self.dim)), np.empty(n)
        _check(lib.nd_problem_get_contact_points(self._h, n, _dptr(x), _dptr(w)))
        return x, w

    # time stepping
    def critical_timestep(self):
        """The explicit critical time step limit/omega_max (nd_problem_estimate_critical_timestep)."""
        x = ctypes.c_double()
        _check(lib.nd_problem_estimate_critical_timestep(self._h, ctypes.byref(x)))
        return x.value

    def setup(self):
        """Assemble, factorize and compute the initial acceleration now
        (step() does it when needed). Raises Error when that fails."""
        _check(lib.nd_problem_setup(self._h))

    def step(self):
        """One time step: ND_OK, or ND_MONITOR_STOP when the monitor asked to
        stop (the step is kept). Raises Error when the step failed (the
        problem is then unchanged)."""
        self._monitor_error = None
        try:
            status = _check(lib.nd_step(self._h))
        except Error:
            if self._monitor_error is not None:  # a distance callback's exception: the cause
                e, self._monitor_error = self._monitor_error, None
                raise e
            raise
        if self._monitor_error is not None:
            e, self._monitor_error = self._monitor_error, None
            raise e
        return status

    def field(self, which=_constants.ND_FIELD_DISPLACEMENT):
        """ND_FIELD_DISPLACEMENT, _VELOCITY, _ACCELERATION, _CONTACT_FORCE
        (obstacle on body) or _REACTION (support on body, clamped DOFs): (n_nodes, dim)."""
        n = self.node_count
        out = np.empty((n, self.dim))
        _check(lib.nd_get_field(self._h, which, n, _dptr(out)))
        return out

    def field_owned(self, which=_constants.ND_FIELD_DISPLACEMENT):
        """nd_get_field_owned: this rank's part of a field, (values (n_owned, dim),
        node numbers (n_owned,)); the whole field without a communicator."""
        n = _i64()
        _check(lib.nd_problem_get_owned_node_count(self._h, ctypes.byref(n)))
        values = np.empty((n.value, self.dim))
        nodes = np.empty(n.value, dtype=np.int64)
        _check(lib.nd_get_field_owned(self._h, which, n.value, _dptr(values), _i64ptr(nodes)))
        return values, nodes

    def field_gathered(self, which=_constants.ND_FIELD_DISPLACEMENT, root=0):
        """nd_get_field_gathered: the whole field (n_nodes, dim) gathered on rank
        root from the nodes' owners; collective. The array is written on root
        only (elsewhere its contents are undefined); without a communicator
        root is 0 and it is field()."""
        n = self.node_count
        out = np.empty((n, self.dim))
        _check(lib.nd_get_field_gathered(self._h, which, root, n, _dptr(out)))
        return out

    def scalar(self, key):
        """nd_get_scalar: ND_TIME, ND_ENERGY_AUGMENTED, ..."""
        x = _dbl()
        _check(lib.nd_get_scalar(self._h, key, ctypes.byref(x)))
        return x.value

    def region_scalar(self, region, key):
        """nd_get_region_scalar: a contact scalar (ND_CONTACT_FORCE, ...) of
        one contact region's points (a contact pair's: its slave region)."""
        x = _dbl()
        _check(lib.nd_get_region_scalar(self._h, region, key, ctypes.byref(x)))
        return x.value

    def contact_pressure(self):
        """lambda_q = -[P_q]_+/gamma_q at each contact point."""
        n = self.contact_point_count
        out = np.empty(n)
        _check(lib.nd_get_contact_pressure(self._h, n, _dptr(out)))
        return out

    def contact_pressure_applied(self):
        """-phi_q/gamma_q: the pressure the last step applied at each contact point."""
        n = self.contact_point_count
        out = np.empty(n)
        _check(lib.nd_get_contact_pressure_applied(self._h, n, _dptr(out)))
        return out

    # operators out and contact on the host's operators (free DOFs, CSR 0-based)
    def matrix(self, which):
        """nd_problem_get_matrix: ND_MATRIX_MASS, _STIFFNESS, _NITSCHE, _STEP,
        _LUMPED_MASS or _DAMPING as CSR arrays (row_ptr (n+1,), col_idx (nnz,), values (nnz,))."""
        n, nnz = _i64(), _i64()
        _check(lib.nd_problem_get_matrix(self._h, which, ctypes.byref(n), ctypes.byref(nnz), None, None, None))
        ptr, col = np.empty(n.value + 1, dtype=np.int64), np.empty(nnz.value, dtype=np.int64)
        val = np.empty(nnz.value)
        _check(lib.nd_problem_get_matrix(self._h, which, ctypes.byref(n), ctypes.byref(nnz), _i64ptr(ptr),
                                         _i64ptr(col), _dptr(val)))
        return ptr, col, val

    @property
    def free_dof_count(self):
        """The number of free DOFs (the size of the matrices)."""
        n, nnz = _i64(), _i64()
        _check(lib.nd_problem_get_matrix(self._h, _constants.ND_MATRIX_LUMPED_MASS, ctypes.byref(n),
                                         ctypes.byref(nnz), None, None, None))
        return n.value

    def dof_map(self):
        """(node (n,), component (n,)) of each free DOF, 0-based."""
        n = self.free_dof_count
        node, comp = np.empty(n, dtype=np.int64), np.empty(n, dtype=np.intc)
        _check(lib.nd_problem_get_dof_map(self._h, n, _i64ptr(node), comp.ctypes.data_as(_pint)))
        return node, comp

    def load(self):
        """F^n on the free DOFs (nd_problem_get_load)."""
        f = np.empty(self.free_dof_count)
        _check(lib.nd_problem_get_load(self._h, f.size, _dptr(f)))
        return f

    def cells(self):
        """The cells' FE nodes (n_cells, nodes_per_cell), 0-based (P2: edge nodes after the vertices)."""
        nc, npc = _i64(), _int()
        _check(lib.nd_problem_get_cells(self._h, ctypes.byref(nc), ctypes.byref(npc), None))
        nodes = np.empty((nc.value, npc.value), dtype=np.int64)
        _check(lib.nd_problem_get_cells(self._h, ctypes.byref(nc), ctypes.byref(npc), _i64ptr(nodes)))
        return nodes

    def contact_residual(self, u):
        """N(u) at u on the free DOFs, the obstacle at the current time; the state is not touched."""
        u = _doubles(u, self.free_dof_count, "u")
        r = np.empty(u.size)
        _check(lib.nd_problem_contact_residual(self._h, u.size, _dptr(u), _dptr(r)))
        return r

    def contact_tangent(self, u):
        """N'(u) as CSR arrays (row_ptr, col_idx, values) on every contact point's pattern."""
        u = _doubles(u, self.free_dof_count, "u")
        nnz = _i64()
        _check(lib.nd_problem_contact_tangent(self._h, u.size, None, ctypes.byref(nnz), None, None, None))
        ptr, col = np.empty(u.size + 1, dtype=np.int64), np.empty(nnz.value, dtype=np.int64)
        val = np.empty(nnz.value)
        _check(lib.nd_problem_contact_tangent(self._h, u.size, _dptr(u), ctypes.byref(nnz), _i64ptr(ptr),
                                              _i64ptr(col), _dptr(val)))
        return ptr, col, val

    def contact_step_residual(self, u, u_old):
        """The step form: the scheme's time rule over the step from P_q(u_old) to P_q(u), u_old the host's U^n."""
        u = _doubles(u, self.free_dof_count, "u")
        u_old = _doubles(u_old, self.free_dof_count, "u_old")
        r = np.empty(u.size)
        _check(lib.nd_problem_contact_step_residual(self._h, u.size, _dptr(u), _dptr(u_old), _dptr(r)))
        return r

    def contact_step_tangent(self, u, u_old):
        """The step form's Jacobian in u as CSR arrays (row_ptr, col_idx, values)."""
        u = _doubles(u, self.free_dof_count, "u")
        u_old = _doubles(u_old, self.free_dof_count, "u_old")
        nnz = _i64()
        _check(lib.nd_problem_contact_step_tangent(self._h, u.size, None, None, ctypes.byref(nnz), None, None, None))
        ptr, col = np.empty(u.size + 1, dtype=np.int64), np.empty(nnz.value, dtype=np.int64)
        val = np.empty(nnz.value)
        _check(lib.nd_problem_contact_step_tangent(self._h, u.size, _dptr(u), _dptr(u_old), ctypes.byref(nnz),
                                                   _i64ptr(ptr), _i64ptr(col), _dptr(val)))
        return ptr, col, val

    def contact_values(self, u):
        """(force, active points, Nitsche energy R, max penetration) at u (nd_problem_contact_values)."""
        u = _doubles(u, self.free_dof_count, "u")
        v = np.empty(4)
        _check(lib.nd_problem_contact_values(self._h, u.size, _dptr(u), 4, _dptr(v)))
        return tuple(v)

    def write_vtu(self, path):
        _check(lib.nd_problem_write_vtu(self._h, os.fsencode(path)))


def write_pvd(path, vtu_files, times):
    """A ParaView time series of the VTU files (paths as written) at times."""
    names = [os.fsencode(f) for f in vtu_files]
    t = _doubles(times, len(names), "times")
    arr = (_str * max(len(names), 1))(*names)
    _check(lib.nd_write_pvd(os.fsencode(path), len(names), arr, _dptr(t)))

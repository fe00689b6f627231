! nitschedyn.f90 - the Fortran 2018 interface of libnitschedyn (module nitschedyn).
!
! Hand-written bind(C) interfaces, in the style of SUNDIALS' Fortran 2003
! modules: every function of nitschedyn.h is callable from Fortran under its
! own C name, with the same arguments in the same order, so that the C manual
! pages document it. The C types map as follows (see nitschedyn_fortran(3)):
!
!   nd_mesh, nd_problem (by value)  type(c_ptr), value
!   nd_mesh *, nd_problem * (out)   type(c_ptr)              (by reference)
!   int, int64_t, double (by value) integer(c_int), integer(c_int64_t), real(c_double), value
!   int *, int64_t *, double * (out scalar)  the same kinds, by reference
!   const double *, double * (arrays)        real(c_double), dimension(*)
!   const int64_t * (arrays)                 integer(c_int64_t), dimension(*)
!   pointers that C allows to be NULL        optional (absent means NULL; F2018)
!   const char * (in)                        character(kind=c_char), dimension(*),
!                                            NUL-terminated: use the *_f wrappers
!   const char * (returned)                  type(c_ptr): use the *_f wrappers
!   nd_monitor_fn, void *userdata            type(c_funptr), type(c_ptr), value
!
! Booleans are integer(c_int) (0 false, non-zero true), never logical.
! The ND_* constants are integer(c_int) parameters generated at build time
! from the X-macro lists of the header (nitschedyn_constants.inc).
module nitschedyn
  use, intrinsic :: iso_c_binding, only: c_int, c_int64_t, c_double, c_signed_char, c_char, c_ptr, c_funptr, &
                                         c_null_char, c_null_ptr, c_size_t, c_f_pointer, c_loc, &
                                         c_associated
  implicit none
  private

  include 'nitschedyn_constants.inc'

  ! ---- the C functions, under their C names --------------------------------
  public :: nd_version, nd_last_error, nd_strerror, nd_set_blas_threads, nd_get_blas_threads
  public :: nd_mesh_create, nd_mesh_create_interval, nd_mesh_create_rectangle, nd_mesh_create_box, &
            nd_mesh_create_cells, nd_mesh_create_mixed, nd_mesh_create_rectangle_cells, nd_mesh_create_box_cells, &
            nd_mesh_read_gmsh, nd_mesh_set_region, nd_mesh_mark_boundary_box, nd_mesh_get_dimension, &
            nd_mesh_get_vertex_count, nd_mesh_get_cell_count, nd_mesh_get_region_size, nd_mesh_destroy, &
            nd_mesh_set_cell_region, nd_mesh_get_cell_regions
  public :: nd_problem_create, nd_problem_set_material, nd_problem_set_material_region, nd_problem_set_dirichlet, &
            nd_problem_set_dirichlet_value, nd_problem_set_dirichlet_nodal, &
            nd_problem_set_body_force, nd_problem_set_neumann, nd_problem_set_contact_plane, &
            nd_problem_set_contact_pair, &
            nd_problem_add_contact_sphere, nd_problem_add_contact_cylinder, nd_problem_add_contact_distance, &
            nd_problem_move_obstacle, nd_problem_set_friction, &
            nd_problem_set_nitsche, nd_problem_set_scheme, nd_problem_set_nodal_forces, &
            nd_problem_set_newton, nd_problem_set_mass_lumping, nd_problem_set_mass_redistribution, nd_problem_set_linear_solver, &
            nd_problem_set_damping, nd_problem_set_plane_stress, &
            nd_problem_set_comm_f, nd_problem_set_distributed_state, &
            nd_problem_set_timestep, nd_problem_set_adaptive_timestep, &
            nd_problem_set_initial_state, nd_problem_set_monitor, &
            nd_problem_set_guard
  public :: nd_problem_get_node_count, nd_problem_get_node_coordinates, &
            nd_problem_get_contact_point_count, nd_problem_get_contact_points
  public :: nd_problem_estimate_critical_timestep
  public :: nd_problem_setup, nd_step, nd_get_field, nd_get_scalar, nd_get_contact_pressure, nd_problem_destroy
  public :: nd_get_region_scalar
  public :: nd_get_contact_pressure_applied
  public :: nd_problem_get_owned_node_count, nd_get_field_owned, nd_get_field_gathered
  public :: nd_problem_get_state_size, nd_problem_save_state, nd_problem_load_state, nd_problem_set_state
  public :: nd_problem_save_state_file, nd_problem_load_state_file
  public :: nd_problem_save_state_file_f, nd_problem_load_state_file_f
  public :: nd_problem_write_vtu, nd_write_pvd
  public :: nd_problem_get_matrix, nd_problem_get_dof_map, nd_problem_get_load, nd_problem_get_cells
  public :: nd_problem_contact_residual, nd_problem_contact_tangent, nd_problem_contact_values
  public :: nd_problem_contact_step_residual, nd_problem_contact_step_tangent
  ! ---- the monitor's interface and the Fortran string wrappers --------------
  public :: nd_monitor_fn, nd_distance_fn
  public :: nd_last_error_f, nd_strerror_f, nd_mesh_read_gmsh_f, nd_problem_write_vtu_f, nd_write_pvd_f

  abstract interface
    ! A monitor: called after every accepted step of nd_step; a non-zero
    ! result makes nd_step return ND_MONITOR_STOP (the step is kept). Write it
    !   integer(c_int) function my_monitor(p, userdata) bind(C)
    !     type(c_ptr), value :: p, userdata
    ! and pass c_funloc(my_monitor) to nd_problem_set_monitor.
    function nd_monitor_fn(p, userdata) result(stop_run) bind(C)
      import :: c_int, c_ptr
      type(c_ptr), value :: p, userdata
      integer(c_int) :: stop_run
    end function nd_monitor_fn
    ! A user's obstacle (nd_problem_add_contact_distance): the signed distance
    ! d (positive on the body's side) and the unit normal nu from the obstacle
    ! towards the body at x and time t; non-zero fails the step. Write it
    !   integer(c_int) function my_distance(t, x, d, nu, user) bind(C)
    !     real(c_double), value :: t
    !     real(c_double), intent(in) :: x(*)
    !     real(c_double), intent(out) :: d, nu(*)
    !     type(c_ptr), value :: user
    ! and pass c_funloc(my_distance).
    function nd_distance_fn(t, x, d, nu, user) result(status) bind(C)
      import :: c_int, c_double, c_ptr
      real(c_double), value :: t
      real(c_double), intent(in) :: x(*)
      real(c_double), intent(out) :: d, nu(*)
      type(c_ptr), value :: user
      integer(c_int) :: status
    end function nd_distance_fn
  end interface

  interface
    ! ---- library --------------------------------------------------------------
    function nd_version(major, minor, patch) result(status) bind(C, name='nd_version')
      import :: c_int
      integer(c_int), intent(out) :: major, minor, patch
      integer(c_int) :: status
    end function nd_version

    ! The C string of the calling thread's last error; nd_last_error_f() copies it.
    function nd_last_error() result(message) bind(C, name='nd_last_error')
      import :: c_ptr
      type(c_ptr) :: message
    end function nd_last_error

    ! The static C string describing a status code; nd_strerror_f(code) copies it.
    function nd_strerror(code) result(message) bind(C, name='nd_strerror')
      import :: c_int, c_ptr
      integer(c_int), value :: code
      type(c_ptr) :: message
    end function nd_strerror

    ! BLAS threads inside the library's calls (process-wide; default 1; 0:
    ! leave the BLAS as the caller set it).
    function nd_set_blas_threads(threads) result(status) bind(C, name='nd_set_blas_threads')
      import :: c_int
      integer(c_int), value :: threads
      integer(c_int) :: status
    end function nd_set_blas_threads

    function nd_get_blas_threads(threads) result(status) bind(C, name='nd_get_blas_threads')
      import :: c_int
      integer(c_int), intent(out) :: threads
      integer(c_int) :: status
    end function nd_get_blas_threads

    ! ---- mesh -----------------------------------------------------------------
    ! coords(dim, n_nodes), cells(dim+1, n_cells) of 0-based vertex indices
    function nd_mesh_create(dim, n_nodes, coords, n_cells, cells, out) result(status) &
        bind(C, name='nd_mesh_create')
      import :: c_int, c_int64_t, c_double, c_ptr
      integer(c_int), value :: dim
      integer(c_int64_t), value :: n_nodes
      real(c_double), intent(in) :: coords(*)
      integer(c_int64_t), value :: n_cells
      integer(c_int64_t), intent(in) :: cells(*)
      type(c_ptr), intent(out) :: out
      integer(c_int) :: status
    end function nd_mesh_create

    function nd_mesh_create_interval(n_cells, a, b, out) result(status) &
        bind(C, name='nd_mesh_create_interval')
      import :: c_int, c_int64_t, c_double, c_ptr
      integer(c_int64_t), value :: n_cells
      real(c_double), value :: a, b
      type(c_ptr), intent(out) :: out
      integer(c_int) :: status
    end function nd_mesh_create_interval

    function nd_mesh_create_rectangle(nx, ny, lo, hi, out) result(status) &
        bind(C, name='nd_mesh_create_rectangle')
      import :: c_int, c_int64_t, c_double, c_ptr
      integer(c_int64_t), value :: nx, ny
      real(c_double), intent(in) :: lo(2), hi(2)
      type(c_ptr), intent(out) :: out
      integer(c_int) :: status
    end function nd_mesh_create_rectangle

    function nd_mesh_create_box(nx, ny, nz, lo, hi, out) result(status) &
        bind(C, name='nd_mesh_create_box')
      import :: c_int, c_int64_t, c_double, c_ptr
      integer(c_int64_t), value :: nx, ny, nz
      real(c_double), intent(in) :: lo(3), hi(3)
      type(c_ptr), intent(out) :: out
      integer(c_int) :: status
    end function nd_mesh_create_box

    ! cell_type: ND_CELL_SIMPLEX, ND_CELL_QUADRILATERAL, ND_CELL_HEXAHEDRON
    function nd_mesh_create_cells(dim, cell_type, n_nodes, coords, n_cells, cells, out) result(status) &
        bind(C, name='nd_mesh_create_cells')
      import :: c_int, c_int64_t, c_double, c_ptr
      integer(c_int), value :: dim, cell_type
      integer(c_int64_t), value :: n_nodes, n_cells
      real(c_double), intent(in) :: coords(*)
      integer(c_int64_t), intent(in) :: cells(*)
      type(c_ptr), intent(out) :: out
      integer(c_int) :: status
    end function nd_mesh_create_cells

    ! cell_types(n_cells) of ND_CELL_LIST; cells: each cell's vertices in turn
    function nd_mesh_create_mixed(dim, n_nodes, coords, n_cells, cell_types, cells, out) result(status) &
        bind(C, name='nd_mesh_create_mixed')
      import :: c_int, c_int64_t, c_double, c_ptr
      integer(c_int), value :: dim
      integer(c_int64_t), value :: n_nodes, n_cells
      real(c_double), intent(in) :: coords(*)
      integer(c_int), intent(in) :: cell_types(*)
      integer(c_int64_t), intent(in) :: cells(*)
      type(c_ptr), intent(out) :: out
      integer(c_int) :: status
    end function nd_mesh_create_mixed

    function nd_mesh_create_rectangle_cells(nx, ny, lo, hi, cell_type, out) result(status) &
        bind(C, name='nd_mesh_create_rectangle_cells')
      import :: c_int, c_int64_t, c_double, c_ptr
      integer(c_int64_t), value :: nx, ny
      real(c_double), intent(in) :: lo(2), hi(2)
      integer(c_int), value :: cell_type
      type(c_ptr), intent(out) :: out
      integer(c_int) :: status
    end function nd_mesh_create_rectangle_cells

    function nd_mesh_create_box_cells(nx, ny, nz, lo, hi, cell_type, out) result(status) &
        bind(C, name='nd_mesh_create_box_cells')
      import :: c_int, c_int64_t, c_double, c_ptr
      integer(c_int64_t), value :: nx, ny, nz
      real(c_double), intent(in) :: lo(3), hi(3)
      integer(c_int), value :: cell_type
      type(c_ptr), intent(out) :: out
      integer(c_int) :: status
    end function nd_mesh_create_box_cells

    ! path NUL-terminated: trim(path)//c_null_char, or use nd_mesh_read_gmsh_f
    function nd_mesh_read_gmsh(path, out) result(status) bind(C, name='nd_mesh_read_gmsh')
      import :: c_int, c_char, c_ptr
      character(kind=c_char), intent(in) :: path(*)
      type(c_ptr), intent(out) :: out
      integer(c_int) :: status
    end function nd_mesh_read_gmsh

    ! facet_vertices(dim, n_facets) of 0-based vertex indices
    function nd_mesh_set_region(m, region, n_facets, facet_vertices) result(status) &
        bind(C, name='nd_mesh_set_region')
      import :: c_int, c_int64_t, c_ptr
      type(c_ptr), value :: m
      integer(c_int), value :: region
      integer(c_int64_t), value :: n_facets
      integer(c_int64_t), intent(in) :: facet_vertices(*)
      integer(c_int) :: status
    end function nd_mesh_set_region

    ! cells: 0-based cell indices; a cell in no region is in region 0
    function nd_mesh_set_cell_region(m, cell_region, n_cells, cells) result(status) &
        bind(C, name='nd_mesh_set_cell_region')
      import :: c_int, c_int64_t, c_ptr
      type(c_ptr), value :: m
      integer(c_int), value :: cell_region
      integer(c_int64_t), value :: n_cells
      integer(c_int64_t), intent(in) :: cells(*)
      integer(c_int) :: status
    end function nd_mesh_set_cell_region

    function nd_mesh_get_cell_regions(m, n_cells, region) result(status) &
        bind(C, name='nd_mesh_get_cell_regions')
      import :: c_int, c_int64_t, c_ptr
      type(c_ptr), value :: m
      integer(c_int64_t), value :: n_cells
      integer(c_int), intent(out) :: region(*)
      integer(c_int) :: status
    end function nd_mesh_get_cell_regions

    function nd_mesh_mark_boundary_box(m, region, lo, hi) result(status) &
        bind(C, name='nd_mesh_mark_boundary_box')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: m
      integer(c_int), value :: region
      real(c_double), intent(in) :: lo(*), hi(*)
      integer(c_int) :: status
    end function nd_mesh_mark_boundary_box

    function nd_mesh_get_dimension(m, dim) result(status) bind(C, name='nd_mesh_get_dimension')
      import :: c_int, c_ptr
      type(c_ptr), value :: m
      integer(c_int), intent(out) :: dim
      integer(c_int) :: status
    end function nd_mesh_get_dimension

    function nd_mesh_get_vertex_count(m, n_vertices) result(status) &
        bind(C, name='nd_mesh_get_vertex_count')
      import :: c_int, c_int64_t, c_ptr
      type(c_ptr), value :: m
      integer(c_int64_t), intent(out) :: n_vertices
      integer(c_int) :: status
    end function nd_mesh_get_vertex_count

    function nd_mesh_get_cell_count(m, n_cells) result(status) bind(C, name='nd_mesh_get_cell_count')
      import :: c_int, c_int64_t, c_ptr
      type(c_ptr), value :: m
      integer(c_int64_t), intent(out) :: n_cells
      integer(c_int) :: status
    end function nd_mesh_get_cell_count

    function nd_mesh_get_region_size(m, region, n_facets) result(status) &
        bind(C, name='nd_mesh_get_region_size')
      import :: c_int, c_int64_t, c_ptr
      type(c_ptr), value :: m
      integer(c_int), value :: region
      integer(c_int64_t), intent(out) :: n_facets
      integer(c_int) :: status
    end function nd_mesh_get_region_size

    ! Sets m to c_null_ptr; harmless on c_null_ptr (safe twice).
    function nd_mesh_destroy(m) result(status) bind(C, name='nd_mesh_destroy')
      import :: c_int, c_ptr
      type(c_ptr), intent(inout) :: m
      integer(c_int) :: status
    end function nd_mesh_destroy

    ! ---- problem: definition -------------------------------------------------
    function nd_problem_create(m, degree, out) result(status) bind(C, name='nd_problem_create')
      import :: c_int, c_ptr
      type(c_ptr), value :: m
      integer(c_int), value :: degree
      type(c_ptr), intent(out) :: out
      integer(c_int) :: status
    end function nd_problem_create

    function nd_problem_set_material(p, young, poisson, density) result(status) &
        bind(C, name='nd_problem_set_material')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: p
      real(c_double), value :: young, poisson, density
      integer(c_int) :: status
    end function nd_problem_set_material

    function nd_problem_set_material_region(p, cell_region, young, poisson, density) result(status) &
        bind(C, name='nd_problem_set_material_region')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: p
      integer(c_int), value :: cell_region
      real(c_double), value :: young, poisson, density
      integer(c_int) :: status
    end function nd_problem_set_material_region

    function nd_problem_set_dirichlet(p, region) result(status) bind(C, name='nd_problem_set_dirichlet')
      import :: c_int, c_ptr
      type(c_ptr), value :: p
      integer(c_int), value :: region
      integer(c_int) :: status
    end function nd_problem_set_dirichlet

    function nd_problem_set_body_force(p, f) result(status) bind(C, name='nd_problem_set_body_force')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: p
      real(c_double), intent(in) :: f(*)
      integer(c_int) :: status
    end function nd_problem_set_body_force

    function nd_problem_set_neumann(p, region, g) result(status) bind(C, name='nd_problem_set_neumann')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: p
      integer(c_int), value :: region
      real(c_double), intent(in) :: g(*)
      integer(c_int) :: status
    end function nd_problem_set_neumann

    function nd_problem_set_contact_plane(p, region, point, normal) result(status) &
        bind(C, name='nd_problem_set_contact_plane')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: p
      integer(c_int), value :: region
      real(c_double), intent(in) :: point(*), normal(*)
      integer(c_int) :: status
    end function nd_problem_set_contact_plane

    ! contact between two bodies: the slave region's points against the
    ! master region's surface (nd_problem_set_contact_pair(3))
    function nd_problem_set_contact_pair(p, slave, master) result(status) &
        bind(C, name='nd_problem_set_contact_pair')
      import :: c_int, c_ptr
      type(c_ptr), value :: p
      integer(c_int), value :: slave, master
      integer(c_int) :: status
    end function nd_problem_set_contact_pair

    function nd_problem_add_contact_sphere(p, region, center, radius, inside) result(status) &
        bind(C, name='nd_problem_add_contact_sphere')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: p
      integer(c_int), value :: region, inside
      real(c_double), intent(in) :: center(*)
      real(c_double), value :: radius
      integer(c_int) :: status
    end function nd_problem_add_contact_sphere

    function nd_problem_add_contact_cylinder(p, region, point, axis, radius, inside) result(status) &
        bind(C, name='nd_problem_add_contact_cylinder')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: p
      integer(c_int), value :: region, inside
      real(c_double), intent(in) :: point(*), axis(*)
      real(c_double), value :: radius
      integer(c_int) :: status
    end function nd_problem_add_contact_cylinder

    ! f = c_funloc(g) of a procedure with the interface nd_distance_fn
    function nd_problem_add_contact_distance(p, region, f, user) result(status) &
        bind(C, name='nd_problem_add_contact_distance')
      import :: c_int, c_ptr, c_funptr
      type(c_ptr), value :: p
      integer(c_int), value :: region
      type(c_funptr), value :: f
      type(c_ptr), value :: user
      integer(c_int) :: status
    end function nd_problem_add_contact_distance

    ! rotation: dim x dim, row-major (the transpose of a Fortran array R(i, j)
    ! as stored: pass transpose(R), or reshape in row order); absent: none
    function nd_problem_move_obstacle(p, region, index, translation, rotation) result(status) &
        bind(C, name='nd_problem_move_obstacle')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: p
      integer(c_int), value :: region, index
      real(c_double), intent(in) :: translation(*)
      real(c_double), intent(in), optional :: rotation(*)
      integer(c_int) :: status
    end function nd_problem_move_obstacle

    ! law one of ND_FRICTION_*; params(1): Coulomb's F or Tresca's s (absent for ND_FRICTION_NONE)
    function nd_problem_set_friction(p, region, law, params) result(status) bind(C, name='nd_problem_set_friction')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: p
      integer(c_int), value :: region, law
      real(c_double), intent(in), optional :: params(*)
      integer(c_int) :: status
    end function nd_problem_set_friction

    function nd_problem_set_nitsche(p, theta, gamma0) result(status) bind(C, name='nd_problem_set_nitsche')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: p
      real(c_double), value :: theta, gamma0
      integer(c_int) :: status
    end function nd_problem_set_nitsche

    ! params absent (NULL) for ND_SCHEME_HYBRID
    function nd_problem_set_scheme(p, scheme, params) result(status) bind(C, name='nd_problem_set_scheme')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: p
      integer(c_int), value :: scheme
      real(c_double), intent(in), optional :: params(*)
      integer(c_int) :: status
    end function nd_problem_set_scheme

    ! u(dim): the region's displacement at t^{n+1} of the next step
    function nd_problem_set_dirichlet_value(p, region, u) result(status) &
        bind(C, name='nd_problem_set_dirichlet_value')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: p
      integer(c_int), value :: region
      real(c_double), intent(in) :: u(*)
      integer(c_int) :: status
    end function nd_problem_set_dirichlet_value

    ! u(dim, n): n FE nodes (only the clamped DOFs are read)
    function nd_problem_set_dirichlet_nodal(p, n, u) result(status) &
        bind(C, name='nd_problem_set_dirichlet_nodal')
      import :: c_int, c_int64_t, c_double, c_ptr
      type(c_ptr), value :: p
      integer(c_int64_t), value :: n
      real(c_double), intent(in) :: u(*)
      integer(c_int) :: status
    end function nd_problem_set_dirichlet_nodal

    ! f(dim, n): n FE nodes
    function nd_problem_set_nodal_forces(p, n, f) result(status) &
        bind(C, name='nd_problem_set_nodal_forces')
      import :: c_int, c_int64_t, c_double, c_ptr
      type(c_ptr), value :: p
      integer(c_int64_t), value :: n
      real(c_double), intent(in) :: f(*)
      integer(c_int) :: status
    end function nd_problem_set_nodal_forces

    function nd_problem_set_newton(p, rtol, atol, max_iter) result(status) &
        bind(C, name='nd_problem_set_newton')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: p
      real(c_double), value :: rtol, atol
      integer(c_int), value :: max_iter
      integer(c_int) :: status
    end function nd_problem_set_newton

    function nd_problem_set_guard(p, guard, value) result(status) &
        bind(C, name='nd_problem_set_guard')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: p
      integer(c_int), value :: guard
      real(c_double), value :: value
      integer(c_int) :: status
    end function nd_problem_set_guard

    function nd_problem_set_mass_lumping(p, lumped) result(status) &
        bind(C, name='nd_problem_set_mass_lumping')
      import :: c_int, c_ptr
      type(c_ptr), value :: p
      integer(c_int), value :: lumped
      integer(c_int) :: status
    end function nd_problem_set_mass_lumping

    function nd_problem_set_damping(p, alpha, beta) result(status) &
        bind(C, name='nd_problem_set_damping')
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: p
      real(c_double), value :: alpha, beta
      integer(c_int) :: status
    end function nd_problem_set_damping

    function nd_problem_set_plane_stress(p, on) result(status) &
        bind(C, name='nd_problem_set_plane_stress')
      import :: c_int, c_ptr
      type(c_ptr), value :: p
      integer(c_int), value :: on
      integer(c_int) :: status
    end function nd_problem_set_plane_stress

    function nd_problem_set_mass_redistribution(p, on) result(status) &
        bind(C, name='nd_problem_set_mass_redistribution')
      import :: c_int, c_ptr
      type(c_ptr), value :: p
      integer(c_int), value :: on
      integer(c_int) :: status
    end function nd_problem_set_mass_redistribution

    function nd_problem_set_linear_solver(p, solver) result(status) &
        bind(C, name='nd_problem_set_linear_solver')
      import :: c_int, c_ptr
      type(c_ptr), value :: p
      integer(c_int), value :: solver
      integer(c_int) :: status
    end function nd_problem_set_linear_solver

    ! fortran_comm: an MPI communicator as `use mpi` gives it (MPI_COMM_WORLD,
    ! or %MPI_VAL of mpi_f08's type(MPI_Comm))
    function nd_problem_set_comm_f(p, fortran_comm) result(status) bind(C, name='nd_problem_set_comm_f')
      import :: c_int, c_ptr
      type(c_ptr), value :: p
      integer(c_int), value :: fortran_comm
      integer(c_int) :: status
    end function nd_problem_set_comm_f

    function nd_problem_set_distributed_state(p, on) result(status) &
        bind(C, name='nd_problem_set_distributed_state')
      import :: c_int, c_ptr
      type(c_ptr), value :: p
      integer(c_int), value :: on
      integer(c_int) :: status
    end function nd_problem_set_distributed_state

    function nd_problem_set_timestep(p, tau) result(status) bind(C, name='nd_problem_set_timestep')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: p
      real(c_double), value :: tau
      integer(c_int) :: status
    end function nd_problem_set_timestep

    ! tolerance 0: fixed steps again
    function nd_problem_set_adaptive_timestep(p, tolerance, tau_min, tau_max) result(status) &
        bind(C, name='nd_problem_set_adaptive_timestep')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: p
      real(c_double), value :: tolerance, tau_min, tau_max
      integer(c_int) :: status
    end function nd_problem_set_adaptive_timestep

    ! u0(dim, n), v0(dim, n); an absent array (NULL) means zero
    function nd_problem_set_initial_state(p, n, u0, v0) result(status) &
        bind(C, name='nd_problem_set_initial_state')
      import :: c_int, c_int64_t, c_double, c_ptr
      type(c_ptr), value :: p
      integer(c_int64_t), value :: n
      real(c_double), intent(in), optional :: u0(*), v0(*)
      integer(c_int) :: status
    end function nd_problem_set_initial_state

    ! The checkpoint is a byte array: integer(c_signed_char) buf(nbytes).
    function nd_problem_get_state_size(p, nbytes) result(status) bind(C, name='nd_problem_get_state_size')
      import :: c_int, c_int64_t, c_ptr
      type(c_ptr), value :: p
      integer(c_int64_t), intent(out) :: nbytes
      integer(c_int) :: status
    end function nd_problem_get_state_size

    function nd_problem_save_state(p, nbytes, buf) result(status) bind(C, name='nd_problem_save_state')
      import :: c_int, c_int64_t, c_ptr, c_signed_char
      type(c_ptr), value :: p
      integer(c_int64_t), value :: nbytes
      integer(c_signed_char), intent(out) :: buf(*)
      integer(c_int) :: status
    end function nd_problem_save_state

    function nd_problem_load_state(p, nbytes, buf) result(status) bind(C, name='nd_problem_load_state')
      import :: c_int, c_int64_t, c_ptr, c_signed_char
      type(c_ptr), value :: p
      integer(c_int64_t), value :: nbytes
      integer(c_signed_char), intent(in) :: buf(*)
      integer(c_int) :: status
    end function nd_problem_load_state

    ! path NUL-terminated, or use the *_f wrappers
    function nd_problem_save_state_file(p, path) result(status) bind(C, name='nd_problem_save_state_file')
      import :: c_int, c_char, c_ptr
      type(c_ptr), value :: p
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int) :: status
    end function nd_problem_save_state_file

    function nd_problem_load_state_file(p, path) result(status) bind(C, name='nd_problem_load_state_file')
      import :: c_int, c_char, c_ptr
      type(c_ptr), value :: p
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int) :: status
    end function nd_problem_load_state_file

    function nd_problem_set_state(p, n, u, v) result(status) bind(C, name='nd_problem_set_state')
      import :: c_int, c_int64_t, c_double, c_ptr
      type(c_ptr), value :: p
      integer(c_int64_t), value :: n
      real(c_double), intent(in), optional :: u(*), v(*)
      integer(c_int) :: status
    end function nd_problem_set_state

    ! fn = c_funloc(f) of a procedure with the interface nd_monitor_fn, or
    ! c_null_funptr to remove the monitor; userdata is passed back to fn.
    function nd_problem_set_monitor(p, fn, userdata) result(status) bind(C, name='nd_problem_set_monitor')
      import :: c_int, c_ptr, c_funptr
      type(c_ptr), value :: p
      type(c_funptr), value :: fn
      type(c_ptr), value :: userdata
      integer(c_int) :: status
    end function nd_problem_set_monitor

    ! ---- problem: queries ------------------------------------------------------
    function nd_problem_get_node_count(p, n_nodes) result(status) bind(C, name='nd_problem_get_node_count')
      import :: c_int, c_int64_t, c_ptr
      type(c_ptr), value :: p
      integer(c_int64_t), intent(out) :: n_nodes
      integer(c_int) :: status
    end function nd_problem_get_node_count

    ! coords(dim, n)
    function nd_problem_get_node_coordinates(p, n, coords) result(status) &
        bind(C, name='nd_problem_get_node_coordinates')
      import :: c_int, c_int64_t, c_double, c_ptr
      type(c_ptr), value :: p
      integer(c_int64_t), value :: n
      real(c_double), intent(out) :: coords(*)
      integer(c_int) :: status
    end function nd_problem_get_node_coordinates

    function nd_problem_get_contact_point_count(p, n_points) result(status) &
        bind(C, name='nd_problem_get_contact_point_count')
      import :: c_int, c_int64_t, c_ptr
      type(c_ptr), value :: p
      integer(c_int64_t), intent(out) :: n_points
      integer(c_int) :: status
    end function nd_problem_get_contact_point_count

    ! coords(dim, n), weights(n); either may be absent (NULL)
    function nd_problem_get_contact_points(p, n, coords, weights) result(status) &
        bind(C, name='nd_problem_get_contact_points')
      import :: c_int, c_int64_t, c_double, c_ptr
      type(c_ptr), value :: p
      integer(c_int64_t), value :: n
      real(c_double), intent(out), optional :: coords(*), weights(*)
      integer(c_int) :: status
    end function nd_problem_get_contact_points

    ! ---- time stepping -------------------------------------------------------
    function nd_problem_estimate_critical_timestep(p, tau_c) result(status) &
        bind(C, name='nd_problem_estimate_critical_timestep')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: p
      real(c_double), intent(out) :: tau_c
      integer(c_int) :: status
    end function nd_problem_estimate_critical_timestep

    function nd_problem_setup(p) result(status) bind(C, name='nd_problem_setup')
      import :: c_int, c_ptr
      type(c_ptr), value :: p
      integer(c_int) :: status
    end function nd_problem_setup

    function nd_step(p) result(status) bind(C, name='nd_step')
      import :: c_int, c_ptr
      type(c_ptr), value :: p
      integer(c_int) :: status
    end function nd_step

    ! out(dim, n): n FE nodes
    function nd_get_field(p, field, n, out) result(status) bind(C, name='nd_get_field')
      import :: c_int, c_int64_t, c_double, c_ptr
      type(c_ptr), value :: p
      integer(c_int), value :: field
      integer(c_int64_t), value :: n
      real(c_double), intent(out) :: out(*)
      integer(c_int) :: status
    end function nd_get_field

    ! The nodes this rank owns (all of them without a communicator): see
    ! nd_get_field_owned(3).
    function nd_problem_get_owned_node_count(p, n_owned) result(status) &
        bind(C, name='nd_problem_get_owned_node_count')
      import :: c_int, c_int64_t, c_ptr
      type(c_ptr), value :: p
      integer(c_int64_t), intent(out) :: n_owned
      integer(c_int) :: status
    end function nd_problem_get_owned_node_count

    ! values(dim, n_owned), nodes(n_owned): 0-based node numbers; either may be absent (NULL)
    function nd_get_field_owned(p, field, n_owned, values, nodes) result(status) bind(C, name='nd_get_field_owned')
      import :: c_int, c_int64_t, c_double, c_ptr
      type(c_ptr), value :: p
      integer(c_int), value :: field
      integer(c_int64_t), value :: n_owned
      real(c_double), intent(out), optional :: values(*)
      integer(c_int64_t), intent(out), optional :: nodes(*)
      integer(c_int) :: status
    end function nd_get_field_owned

    ! out(dim, n) on rank root only (absent elsewhere, n not read): collective,
    ! see nd_get_field_gathered(3)
    function nd_get_field_gathered(p, field, root, n, out) result(status) bind(C, name='nd_get_field_gathered')
      import :: c_int, c_int64_t, c_double, c_ptr
      type(c_ptr), value :: p
      integer(c_int), value :: field, root
      integer(c_int64_t), value :: n
      real(c_double), intent(out), optional :: out(*)
      integer(c_int) :: status
    end function nd_get_field_gathered

    function nd_get_scalar(p, key, out) result(status) bind(C, name='nd_get_scalar')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: p
      integer(c_int), value :: key
      real(c_double), intent(out) :: out
      integer(c_int) :: status
    end function nd_get_scalar

    ! a contact scalar of one contact region's points (nd_get_field(3))
    function nd_get_region_scalar(p, region, key, out) result(status) bind(C, name='nd_get_region_scalar')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: p
      integer(c_int), value :: region, key
      real(c_double), intent(out) :: out
      integer(c_int) :: status
    end function nd_get_region_scalar

    function nd_get_contact_pressure(p, n, out) result(status) bind(C, name='nd_get_contact_pressure')
      import :: c_int, c_int64_t, c_double, c_ptr
      type(c_ptr), value :: p
      integer(c_int64_t), value :: n
      real(c_double), intent(out) :: out(*)
      integer(c_int) :: status
    end function nd_get_contact_pressure

    function nd_get_contact_pressure_applied(p, n, out) result(status) &
        bind(C, name='nd_get_contact_pressure_applied')
      import :: c_int, c_int64_t, c_double, c_ptr
      type(c_ptr), value :: p
      integer(c_int64_t), value :: n
      real(c_double), intent(out) :: out(*)
      integer(c_int) :: status
    end function nd_get_contact_pressure_applied

    ! Sets p to c_null_ptr; harmless on c_null_ptr (safe twice).
    function nd_problem_destroy(p) result(status) bind(C, name='nd_problem_destroy')
      import :: c_int, c_ptr
      type(c_ptr), intent(inout) :: p
      integer(c_int) :: status
    end function nd_problem_destroy

    ! ---- operators out -------------------------------------------------------
    ! two calls: row_ptr, col_idx, values absent -> n, nnz set; then present
    ! (n+1, nnz, nnz entries, 0-based) with n, nnz holding those sizes
    function nd_problem_get_matrix(p, which, n, nnz, row_ptr, col_idx, values) result(status) &
        bind(C, name='nd_problem_get_matrix')
      import :: c_int, c_int64_t, c_double, c_ptr
      type(c_ptr), value :: p
      integer(c_int), value :: which
      integer(c_int64_t), intent(inout) :: n, nnz
      integer(c_int64_t), intent(out), optional :: row_ptr(*), col_idx(*)
      real(c_double), intent(out), optional :: values(*)
      integer(c_int) :: status
    end function nd_problem_get_matrix

    ! node(n) (0-based FE node), component(n) (0-based); either may be absent
    function nd_problem_get_dof_map(p, n, node, component) result(status) &
        bind(C, name='nd_problem_get_dof_map')
      import :: c_int, c_int64_t, c_ptr
      type(c_ptr), value :: p
      integer(c_int64_t), value :: n
      integer(c_int64_t), intent(out), optional :: node(*)
      integer(c_int), intent(out), optional :: component(*)
      integer(c_int) :: status
    end function nd_problem_get_dof_map

    function nd_problem_get_load(p, n, f) result(status) bind(C, name='nd_problem_get_load')
      import :: c_int, c_int64_t, c_double, c_ptr
      type(c_ptr), value :: p
      integer(c_int64_t), value :: n
      real(c_double), intent(out) :: f(*)
      integer(c_int) :: status
    end function nd_problem_get_load

    ! nodes absent: n_cells, nodes_per_cell set; then nodes(nodes_per_cell, n_cells), 0-based
    function nd_problem_get_cells(p, n_cells, nodes_per_cell, nodes) result(status) &
        bind(C, name='nd_problem_get_cells')
      import :: c_int, c_int64_t, c_ptr
      type(c_ptr), value :: p
      integer(c_int64_t), intent(inout) :: n_cells
      integer(c_int), intent(out) :: nodes_per_cell
      integer(c_int64_t), intent(out), optional :: nodes(*)
      integer(c_int) :: status
    end function nd_problem_get_cells

    ! ---- contact on the host's operators --------------------------------------
    function nd_problem_contact_residual(p, n, u, r) result(status) bind(C, name='nd_problem_contact_residual')
      import :: c_int, c_int64_t, c_double, c_ptr
      type(c_ptr), value :: p
      integer(c_int64_t), value :: n
      real(c_double), intent(in) :: u(*)
      real(c_double), intent(out) :: r(*)
      integer(c_int) :: status
    end function nd_problem_contact_residual

    ! two calls as nd_problem_get_matrix (u may be absent in the first)
    function nd_problem_contact_tangent(p, n, u, nnz, row_ptr, col_idx, values) result(status) &
        bind(C, name='nd_problem_contact_tangent')
      import :: c_int, c_int64_t, c_double, c_ptr
      type(c_ptr), value :: p
      integer(c_int64_t), value :: n
      real(c_double), intent(in), optional :: u(*)
      integer(c_int64_t), intent(inout) :: nnz
      integer(c_int64_t), intent(out), optional :: row_ptr(*), col_idx(*)
      real(c_double), intent(out), optional :: values(*)
      integer(c_int) :: status
    end function nd_problem_contact_tangent

    ! the step form: the scheme's time rule from P_q(u_old) to P_q(u) (u_old: the host's U^n)
    function nd_problem_contact_step_residual(p, n, u, u_old, r) result(status) &
        bind(C, name='nd_problem_contact_step_residual')
      import :: c_int, c_int64_t, c_double, c_ptr
      type(c_ptr), value :: p
      integer(c_int64_t), value :: n
      real(c_double), intent(in) :: u(*), u_old(*)
      real(c_double), intent(out) :: r(*)
      integer(c_int) :: status
    end function nd_problem_contact_step_residual

    ! two calls as nd_problem_get_matrix (u, u_old may be absent in the first)
    function nd_problem_contact_step_tangent(p, n, u, u_old, nnz, row_ptr, col_idx, values) result(status) &
        bind(C, name='nd_problem_contact_step_tangent')
      import :: c_int, c_int64_t, c_double, c_ptr
      type(c_ptr), value :: p
      integer(c_int64_t), value :: n
      real(c_double), intent(in), optional :: u(*), u_old(*)
      integer(c_int64_t), intent(inout) :: nnz
      integer(c_int64_t), intent(out), optional :: row_ptr(*), col_idx(*)
      real(c_double), intent(out), optional :: values(*)
      integer(c_int) :: status
    end function nd_problem_contact_step_tangent

    ! values(nvalues): force, active points, Nitsche energy R, max penetration (first nvalues)
    function nd_problem_contact_values(p, n, u, nvalues, values) result(status) &
        bind(C, name='nd_problem_contact_values')
      import :: c_int, c_int64_t, c_double, c_ptr
      type(c_ptr), value :: p
      integer(c_int64_t), value :: n
      real(c_double), intent(in) :: u(*)
      integer(c_int), value :: nvalues
      real(c_double), intent(out) :: values(*)
      integer(c_int) :: status
    end function nd_problem_contact_values

    ! ---- output --------------------------------------------------------------
    ! path NUL-terminated: trim(path)//c_null_char, or use nd_problem_write_vtu_f
    function nd_problem_write_vtu(p, path) result(status) bind(C, name='nd_problem_write_vtu')
      import :: c_int, c_char, c_ptr
      type(c_ptr), value :: p
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int) :: status
    end function nd_problem_write_vtu

    ! vtu_files(n): C pointers to NUL-terminated strings; or use nd_write_pvd_f
    function nd_write_pvd(path, n, vtu_files, times) result(status) bind(C, name='nd_write_pvd')
      import :: c_int, c_int64_t, c_double, c_char, c_ptr
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int64_t), value :: n
      type(c_ptr), intent(in) :: vtu_files(*)
      real(c_double), intent(in) :: times(*)
      integer(c_int) :: status
    end function nd_write_pvd
  end interface

  interface
    ! the C library's strlen, to copy the strings that nd_last_error and
    ! nd_strerror return
    function c_strlen(s) result(n) bind(C, name='strlen')
      import :: c_ptr, c_size_t
      type(c_ptr), value :: s
      integer(c_size_t) :: n
    end function c_strlen
  end interface

contains

  ! A Fortran copy of a NUL-terminated C string ('' for a null pointer).
  function c_string_copy(s) result(f)
    type(c_ptr), intent(in) :: s
    character(len=:), allocatable :: f
    character(kind=c_char), pointer :: chars(:)
    integer(c_size_t) :: n, i
    if (.not. c_associated(s)) then
      f = ''
      return
    end if
    n = c_strlen(s)
    allocate(character(len=n) :: f)
    if (n == 0) return
    call c_f_pointer(s, chars, [n])
    do i = 1, n
      f(i:i) = chars(i)
    end do
  end function c_string_copy

  ! nd_last_error() as a Fortran string: what went wrong in the calling
  ! thread's last failed call ('' after a successful one).
  function nd_last_error_f() result(message)
    character(len=:), allocatable :: message
    message = c_string_copy(nd_last_error())
  end function nd_last_error_f

  ! nd_strerror(code) as a Fortran string.
  function nd_strerror_f(code) result(message)
    integer(c_int), intent(in) :: code
    character(len=:), allocatable :: message
    message = c_string_copy(nd_strerror(code))
  end function nd_strerror_f

  ! nd_mesh_read_gmsh with a Fortran path (trailing blanks are ignored).
  function nd_mesh_read_gmsh_f(path, out) result(status)
    character(len=*), intent(in) :: path
    type(c_ptr), intent(out) :: out
    integer(c_int) :: status
    status = nd_mesh_read_gmsh(trim(path)//c_null_char, out)
  end function nd_mesh_read_gmsh_f

  ! the checkpoint files with a Fortran path (trailing blanks are ignored)
  function nd_problem_save_state_file_f(p, path) result(status)
    type(c_ptr), value :: p
    character(len=*), intent(in) :: path
    integer(c_int) :: status
    status = nd_problem_save_state_file(p, trim(path)//c_null_char)
  end function nd_problem_save_state_file_f

  function nd_problem_load_state_file_f(p, path) result(status)
    type(c_ptr), value :: p
    character(len=*), intent(in) :: path
    integer(c_int) :: status
    status = nd_problem_load_state_file(p, trim(path)//c_null_char)
  end function nd_problem_load_state_file_f

  ! nd_problem_write_vtu with a Fortran path (trailing blanks are ignored).
  function nd_problem_write_vtu_f(p, path) result(status)
    type(c_ptr), value :: p
    character(len=*), intent(in) :: path
    integer(c_int) :: status
    status = nd_problem_write_vtu(p, trim(path)//c_null_char)
  end function nd_problem_write_vtu_f

  ! nd_write_pvd with Fortran strings: n = size(vtu_files) files (trailing
  ! blanks of each are ignored) at times(1:n). Pass sections, e.g.
  ! nd_write_pvd_f('run.pvd', names(1:k), times(1:k)), for the first k.
  function nd_write_pvd_f(path, vtu_files, times) result(status)
    character(len=*), intent(in) :: path
    character(len=*), intent(in) :: vtu_files(:)
    real(c_double), intent(in) :: times(*)
    integer(c_int) :: status
    ! all names NUL-terminated, one after the other, and a pointer to each
    character(kind=c_char), allocatable, target :: buffer(:)
    type(c_ptr), allocatable :: pointers(:)
    integer :: i, j, k, n
    n = size(vtu_files)
    allocate(buffer(sum(len_trim(vtu_files)) + n), pointers(max(n, 1)))
    pointers = c_null_ptr
    k = 1
    do i = 1, n
      pointers(i) = c_loc(buffer(k))
      do j = 1, len_trim(vtu_files(i))
        buffer(k) = vtu_files(i)(j:j)
        k = k + 1
      end do
      buffer(k) = c_null_char
      k = k + 1
    end do
    status = nd_write_pvd(trim(path)//c_null_char, int(n, c_int64_t), pointers, times)
  end function nd_write_pvd_f

end module nitschedyn

! The 1D bar of docs/design.md §7 for the Fortran tests, set up with exactly the
! calls of examples/bar1d.c and of its C twin bar_twin.c, in the same order:
! Omega = (0,1), rho = E = 1, clamped at x = 1 (region 1), rigid obstacle at
! x = 0 (region 2), hybrid scheme, Theta = 1, gamma0 = 0.2, u0 = (1-x)/2, v0 = 0.
module nd_fortran_bar
  use, intrinsic :: iso_c_binding, only: c_int, c_int64_t, c_double, c_ptr, c_null_ptr
  use nitschedyn
  implicit none
  private
  public :: make_bar

  integer(c_int), parameter :: CLAMPED = 1, CONTACT = 2

contains

  ! p: the new problem (c_null_ptr on failure); n: its FE node count.
  ! Returns the first status that is not ND_OK, with nd_last_error_f() printed.
  function make_bar(nx, degree, tau, p, n) result(status)
    integer(c_int64_t), intent(in) :: nx
    integer(c_int), intent(in) :: degree
    real(c_double), intent(in) :: tau
    type(c_ptr), intent(out) :: p
    integer(c_int64_t), intent(out) :: n
    integer(c_int) :: status
    type(c_ptr) :: mesh
    real(c_double), allocatable :: x(:), u0(:), v0(:)
    integer(c_int) :: ignored

    p = c_null_ptr
    n = 0
    mesh = c_null_ptr
    status = nd_mesh_create_interval(nx, 0.0_c_double, 1.0_c_double, mesh)
    if (status == ND_OK) status = nd_mesh_mark_boundary_box(mesh, CLAMPED, [0.5_c_double], [1.5_c_double])
    if (status == ND_OK) status = nd_mesh_mark_boundary_box(mesh, CONTACT, [-0.5_c_double], [0.5_c_double])
    if (status == ND_OK) status = nd_problem_create(mesh, degree, p)
    ignored = nd_mesh_destroy(mesh) ! the problem keeps its own copy
    if (status == ND_OK) status = nd_problem_set_material(p, 1.0_c_double, 0.0_c_double, 1.0_c_double)
    if (status == ND_OK) status = nd_problem_set_dirichlet(p, CLAMPED)
    if (status == ND_OK) status = nd_problem_set_contact_plane(p, CONTACT, [0.0_c_double], [1.0_c_double])
    if (status == ND_OK) status = nd_problem_set_nitsche(p, 1.0_c_double, 0.2_c_double)
    if (status == ND_OK) status = nd_problem_set_scheme(p, ND_SCHEME_HYBRID) ! params absent: NULL
    if (status == ND_OK) status = nd_problem_set_mass_lumping(p, 0_c_int)
    if (status == ND_OK) status = nd_problem_set_timestep(p, tau)
    if (status == ND_OK) status = nd_problem_get_node_count(p, n)
    if (status == ND_OK) then
      allocate(x(n), u0(n), v0(n))
      status = nd_problem_get_node_coordinates(p, n, x)
    end if
    if (status == ND_OK) then
      u0 = 0.5_c_double * (1 - x)
      v0 = 0
      status = nd_problem_set_initial_state(p, n, u0, v0)
    end if
    if (status /= ND_OK) then
      write (*, '(a)') 'make_bar: ' // nd_last_error_f()
      ignored = nd_problem_destroy(p)
    end if
  end function make_bar

end module nd_fortran_bar

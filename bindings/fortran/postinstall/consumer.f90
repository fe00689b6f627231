! The 1D bar of docs/design.md §7 dropped on an obstacle at x = 0, from Fortran,
! compiled against the installed module and libraries (postinstall_fortran).
program consumer
  use, intrinsic :: iso_c_binding
  use nitschedyn
  implicit none
  type(c_ptr) :: m = c_null_ptr, p = c_null_ptr
  integer(c_int64_t) :: n
  integer(c_int) :: k, major, minor, patch
  real(c_double) :: e_theta
  real(c_double), allocatable :: x(:)

  call ok(nd_version(major, minor, patch))
  print '(a, i0, ".", i0, ".", i0)', 'libnitschedyn ', major, minor, patch
  call ok(nd_mesh_create_interval(40_c_int64_t, 0.0_c_double, 1.0_c_double, m))
  call ok(nd_mesh_mark_boundary_box(m, 1, [-0.5_c_double], [0.5_c_double])) ! x = 0: contact
  call ok(nd_mesh_mark_boundary_box(m, 2, [0.5_c_double], [1.5_c_double]))  ! x = 1: clamped
  call ok(nd_problem_create(m, 1, p))                   ! P1; the problem copies m
  call ok(nd_mesh_destroy(m))
  call ok(nd_problem_set_material(p, 1.0_c_double, 0.0_c_double, 1.0_c_double))
  call ok(nd_problem_set_dirichlet(p, 2))
  call ok(nd_problem_set_contact_plane(p, 1, [0.0_c_double], [1.0_c_double]))
  call ok(nd_problem_set_nitsche(p, 1.0_c_double, 0.2_c_double))
  call ok(nd_problem_set_scheme(p, ND_SCHEME_HYBRID))   ! no params: NULL
  call ok(nd_problem_set_timestep(p, 1.0_c_double / 80))
  call ok(nd_problem_get_node_count(p, n))
  allocate(x(n))
  call ok(nd_problem_get_node_coordinates(p, n, x))
  call ok(nd_problem_set_initial_state(p, n, 0.5_c_double * (1 - x)))  ! v0 absent: 0
  do k = 1, 240
    call ok(nd_step(p))
  end do
  call ok(nd_get_scalar(p, ND_ENERGY_AUGMENTED, e_theta))
  print '(a, f9.6, a)', 'E_Theta(3) = ', e_theta, ' (exact energy 1/8)'
  call ok(nd_problem_destroy(p))
  if (abs(e_theta - 0.125_c_double) > 1e-3_c_double) error stop 'E_Theta is not close to 1/8'

contains

  subroutine ok(status)
    integer(c_int), intent(in) :: status
    if (status /= ND_OK) then
      print '(a)', nd_last_error_f()
      error stop 1
    end if
  end subroutine ok
end program consumer

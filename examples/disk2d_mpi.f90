! disk2d_mpi.f90 - the 2D disk of DESIGN §7 dropped on a plane, driven from
! Fortran on the ranks of MPI_COMM_WORLD (builds with PETSc).
!
! The scene of examples/disk2d.c (drop_scene.c): radius 20, centre 25 above
! the plane, lambda = mu = 20, rho = 1, gravity (0, -0.1); P1, hybrid scheme,
! Theta = 1, gamma0 = 1e-3. Every rank reads the same mesh and builds the same
! problem (the mesh and the state are replicated); nd_problem_set_comm_f gives
! it MPI_COMM_WORLD, and the PETSc solver spreads the linear solves over the
! ranks. Rank 0 prints t, the augmented energy E_Theta and the contact force
! after every step, with 17 significant digits. With OUT, rank 0 also writes
! the final displacement there (u_x u_y per node), gathered from the ranks
! that own the nodes by nd_get_field_gathered: the array exists on rank 0
! alone, as in a code whose I/O rank holds the whole field.
!
! usage: mpiexec -n N disk2d_mpi MESH [mumps|gamg|serial] [T] [tau] [OUT]
!   serial: CHOLMOD on every rank, no communicator (the reference).
! Exit status: 0 ok, 1 library error, 2 usage error.
program disk2d_mpi
  use, intrinsic :: iso_c_binding, only: c_int, c_int64_t, c_double, c_ptr, c_null_ptr, c_associated
  use mpi, only: MPI_COMM_WORLD, mpi_init, mpi_finalize, mpi_comm_rank
  use nitschedyn
  implicit none
  character(len=1024) :: mesh_path, arg, out_path = ''
  real(c_double), allocatable :: u(:, :)
  integer(c_int64_t) :: n_nodes
  character(len=16) :: solver_name
  type(c_ptr) :: m = c_null_ptr, p = c_null_ptr
  integer(c_int) :: status, solver
  integer :: ierr, rank, k, steps, unit
  real(c_double) :: t_end = 11, tau = 0.25_c_double, t, e, force
  real(c_double), parameter :: lambda = 20, mu = 20
  real(c_double) :: young, nu

  call mpi_init(ierr)
  call mpi_comm_rank(MPI_COMM_WORLD, rank, ierr)
  if (command_argument_count() < 1) then
    if (rank == 0) print '(a)', 'usage: disk2d_mpi MESH [mumps|gamg|serial] [T] [tau]'
    call mpi_finalize(ierr)
    stop 2
  end if
  call get_command_argument(1, mesh_path)
  solver_name = 'mumps'
  if (command_argument_count() >= 2) call get_command_argument(2, solver_name)
  if (command_argument_count() >= 3) then
    call get_command_argument(3, arg)
    read (arg, *) t_end
  end if
  if (command_argument_count() >= 4) then
    call get_command_argument(4, arg)
    read (arg, *) tau
  end if
  if (command_argument_count() >= 5) call get_command_argument(5, out_path)
  select case (trim(solver_name))
  case ('mumps')
    solver = ND_SOLVER_PETSC_MUMPS
  case ('gamg')
    solver = ND_SOLVER_PETSC_GAMG
  case ('serial')
    solver = ND_SOLVER_CHOLMOD
  case default
    if (rank == 0) print '(2a)', 'unknown solver ', trim(solver_name)
    call mpi_finalize(ierr)
    stop 2
  end select

  young = mu * (3 * lambda + 2 * mu) / (lambda + mu)
  nu = lambda / (2 * (lambda + mu))
  status = nd_mesh_read_gmsh_f(mesh_path, m)
  if (status == ND_OK) status = nd_problem_create(m, 1_c_int, p)
  if (c_associated(m)) ierr = nd_mesh_destroy(m) ! the problem keeps its own copy
  if (status == ND_OK) status = nd_problem_set_material(p, young, nu, 1.0_c_double)
  if (status == ND_OK) status = nd_problem_set_body_force(p, [0.0_c_double, -0.1_c_double])
  if (status == ND_OK) status = nd_problem_set_contact_plane(p, 1_c_int, [0.0_c_double, 0.0_c_double], &
                                                            [0.0_c_double, 1.0_c_double])
  if (status == ND_OK) status = nd_problem_set_nitsche(p, 1.0_c_double, 1e-3_c_double)
  if (status == ND_OK) status = nd_problem_set_scheme(p, ND_SCHEME_HYBRID)
  if (status == ND_OK) status = nd_problem_set_timestep(p, tau)
  if (status == ND_OK) status = nd_problem_set_linear_solver(p, solver)
  ! the ranks step the problem together (the reference runs alone on each)
  if (status == ND_OK .and. solver /= ND_SOLVER_CHOLMOD) status = nd_problem_set_comm_f(p, MPI_COMM_WORLD)

  steps = nint(t_end / tau)
  do k = 1, steps
    if (status /= ND_OK) exit
    status = nd_step(p)
    if (status == ND_OK) status = nd_get_scalar(p, ND_TIME, t)
    if (status == ND_OK) status = nd_get_scalar(p, ND_ENERGY_AUGMENTED, e)
    if (status == ND_OK) status = nd_get_scalar(p, ND_CONTACT_FORCE, force)
    if (status == ND_OK .and. rank == 0) print '(f10.4, 2es26.17)', t, e, force
  end do
  ! the final displacement on rank 0: every rank calls the gather, only rank 0 has the array
  if (status == ND_OK .and. len_trim(out_path) > 0) then
    status = nd_problem_get_node_count(p, n_nodes)
    if (status == ND_OK .and. rank == 0) then
      allocate(u(2, n_nodes))
      status = nd_get_field_gathered(p, ND_FIELD_DISPLACEMENT, 0_c_int, n_nodes, u)
    else
      status = nd_get_field_gathered(p, ND_FIELD_DISPLACEMENT, 0_c_int, 0_c_int64_t)
    end if
    if (status == ND_OK .and. rank == 0) then
      open (newunit=unit, file=trim(out_path), status='replace', action='write')
      write (unit, '(2es26.17)') u
      close (unit)
    end if
  end if
  if (status /= ND_OK) print '(a, i0, 2a)', 'rank ', rank, ': ', nd_last_error_f()
  if (c_associated(p)) ierr = nd_problem_destroy(p) ! collective: before MPI_Finalize
  call mpi_finalize(ierr)
  if (status /= ND_OK) stop 1

end program disk2d_mpi

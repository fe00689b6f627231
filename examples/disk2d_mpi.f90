! disk2d_mpi.f90 - the 2D disk of docs/design.md §7 dropped on a plane, driven from
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
! With LAYOUT = distributed each rank keeps the state on its own rows
! (nd_problem_set_distributed_state: a step gathers no whole solution) and,
! as a partitioned code holds its nodes, reads its part of the displacement
! after every step (nd_get_field_owned, no message); at the end the parts'
! sum of squares, added over the ranks, is checked against the gathered
! field's (exit status 1 if they differ by more than the sums' round-off).
!
! usage: mpiexec -n N disk2d_mpi MESH [mumps|gamg|serial] [T] [tau] [OUT] [whole|distributed]
!   serial: CHOLMOD on every rank, no communicator (the reference).
! Exit status: 0 ok, 1 library error, 2 usage error.
program disk2d_mpi
  use, intrinsic :: iso_c_binding, only: c_int, c_int64_t, c_double, c_ptr, c_null_ptr, c_associated
  use mpi, only: MPI_COMM_WORLD, MPI_DOUBLE_PRECISION, MPI_SUM, mpi_init, mpi_finalize, mpi_comm_rank, mpi_allreduce
  use nitschedyn
  implicit none
  character(len=1024) :: mesh_path, arg, out_path = ''
  real(c_double), allocatable :: u(:, :), u_own(:, :)
  integer(c_int64_t), allocatable :: own_nodes(:)
  integer(c_int64_t) :: n_nodes, n_owned
  character(len=16) :: solver_name, layout = 'whole'
  real(c_double) :: own_squares, all_squares
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
  if (command_argument_count() >= 6) call get_command_argument(6, layout)
  if (layout /= 'whole' .and. layout /= 'distributed') then
    if (rank == 0) print '(2a)', 'unknown layout ', trim(layout)
    call mpi_finalize(ierr)
    stop 2
  end if
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
  ! each rank's nodes, as a partitioned code holds them
  if (status == ND_OK .and. layout == 'distributed') status = nd_problem_set_distributed_state(p, 1_c_int)
  if (status == ND_OK) status = nd_problem_get_owned_node_count(p, n_owned)
  if (status == ND_OK) allocate(u_own(2, n_owned), own_nodes(n_owned))

  steps = nint(t_end / tau)
  do k = 1, steps
    if (status /= ND_OK) exit
    status = nd_step(p)
    if (status == ND_OK) status = nd_get_scalar(p, ND_TIME, t)
    if (status == ND_OK) status = nd_get_scalar(p, ND_ENERGY_AUGMENTED, e)
    if (status == ND_OK) status = nd_get_scalar(p, ND_CONTACT_FORCE, force)
    if (status == ND_OK .and. rank == 0) print '(f10.4, 2es26.17)', t, e, force
    if (status == ND_OK .and. layout == 'distributed') &
      status = nd_get_field_owned(p, ND_FIELD_DISPLACEMENT, n_owned, u_own, own_nodes)
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
    ! the ranks' parts read after the last step are the gathered field
    if (status == ND_OK .and. layout == 'distributed') then
      own_squares = sum(u_own**2)
      call mpi_allreduce(own_squares, all_squares, 1, MPI_DOUBLE_PRECISION, MPI_SUM, MPI_COMM_WORLD, ierr)
      if (rank == 0) then
        if (abs(all_squares - sum(u**2)) > 1e-12_c_double * sum(u**2)) then
          print '(a, 2es26.17)', 'the owned parts differ from the gathered field: ', all_squares, sum(u**2)
          status = ND_ERR_INTERNAL
        end if
      end if
    end if
  end if
  if (status /= ND_OK) print '(a, i0, 2a)', 'rank ', rank, ': ', nd_last_error_f()
  if (c_associated(p)) ierr = nd_problem_destroy(p) ! collective: before MPI_Finalize
  call mpi_finalize(ierr)
  if (status /= ND_OK) stop 1

end program disk2d_mpi

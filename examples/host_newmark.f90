! host_newmark.f90 - a legacy-style host code that keeps its own arrays, its
! own Newmark loop (beta = 1/4, gamma = 1/2) and its own semi-smooth Newton,
! and asks libnitschedyn only for its operators at set-up (M, K and
! K_Theta - K, the load) and for the Nitsche contact term at each Newton
! iteration (nd_problem_contact_residual, nd_problem_contact_tangent):
! docs/design.md §10.4.
!
! With the argument "hybrid" the host runs the paper's hybrid scheme instead
! (Crank-Nicolson for the bulk, c = 4/tau^2, kappa = 2), whose contact term
! Phi_q switches per point on the sign of P_q^n: it asks for the step form,
! nd_problem_contact_step_residual and nd_problem_contact_step_tangent, with
! its own U^n.
!
! With the argument "hexahedra" the Newmark run is in 3D on a mesh of
! trilinear hexahedra (Q1, nd_mesh_create_box_cells), the host's arrays and
! loop unchanged: the library's operators and contact term are the same
! calls whatever the cells.
!
! With the argument "damped" the Newmark run has Rayleigh damping
! C = alpha M + beta K (alpha = 0.5, beta = 0.01, docs/design.md §10.5): the
! host reads C (ND_MATRIX_DAMPING) and adds C V^{n+1} to its equation,
! V^{n+1} = gamma/(beta tau) (U - U^n) + (1 - gamma/beta) V^n + tau (1 - gamma/(2 beta)) A^n:
! A gains gamma/(beta tau) C, r the rest, M A^0 the term - C V^0.
!
! The scene: a free elastic block (1 x 0.25, E = 1, nu = 0.3, rho = 1, P1)
! falling under gravity onto a rigid plane 0.002 below it, Theta = 1, the
! automatic gamma0, tau = 0.01. The same problem is stepped by nd_step
! alongside; after each step the program prints nothing but keeps the
! largest difference of the displacements, and at the end
!
!   host_newmark: N steps (K in contact), max |U_host - U_lib| = D, bound B
!
! The bound is derived, step by step, not chosen: with Theta = 1 the host's
! step map G_h(U) = A U + kappa N_h(U) - r_h (A = c M + K_Theta, N_h its
! contact term: phi_q(P_q(U)) p_q with phi_q nondecreasing in P_q, the
! hybrid Phi_q for a fixed P_q^n too) is strongly monotone with constant
! lambda_min(A), so the host's solution and the library's are at most
!   (|G_h(U_host)| + |G_h(U_lib)|) / lambda_min(A)
! apart, the first below the Newton tolerance rtol (|r| + c |M U|), the
! second holding every difference of history (r_h - r_l, and U^n where the
! contact term reads it).
! lambda_min(A) is bounded below by a Cholesky factorization of A - mu I.
! At the end it checks nd_problem_contact_values against nd_get_scalar at the
! state's U (bitwise) and reads the cells (nd_problem_get_cells).
! Exit status 0 when every step is within its bound and those agree, 1 otherwise.
program host_newmark
  use, intrinsic :: iso_c_binding, only: c_int, c_int64_t, c_double, c_ptr
  use nitschedyn
  implicit none

  real(c_double), parameter :: tau = 0.01d0, beta = 0.25d0, gam = 0.5d0, rtol = 1d-10
  real(c_double), parameter :: alpha_d = 0.5d0, beta_d = 0.01d0  ! the damped run's Rayleigh coefficients
  character(len=16) :: mode
  logical :: hybrid, damped, hexahedra
  integer :: dim
  real(c_double) :: kappa
  integer, parameter :: nsteps = 30
  type(c_ptr) :: p
  integer(c_int64_t) :: n, nn, i
  real(c_double), allocatable :: Mass(:,:), K(:,:), KT(:,:), A(:,:), T(:,:), Cd(:,:)
  real(c_double), allocatable :: F(:), U(:), V(:), Acc(:), U1(:), V1(:), A1(:), r(:), G(:), Nc(:)
  real(c_double), allocatable :: Ulib(:), full(:), work(:)
  integer(c_int64_t), allocatable :: node(:), tptr(:), tcol(:)
  integer(c_int), allocatable :: comp(:)
  real(c_double), allocatable :: tval(:), last(:)
  integer(c_int64_t) :: tnnz
  real(c_double) :: c, lam, gh, gl, bound, diff, worst, worst_bound, active
  integer :: step, it, contact_steps
  logical :: ok
  real(c_double) :: cvalues(4)
  integer(c_int) :: npc
  integer(c_int64_t) :: ncells
  integer(c_int64_t), allocatable :: cells(:)
  integer(c_int), parameter :: keys(4) = [ND_CONTACT_FORCE, ND_ACTIVE_POINTS, ND_ENERGY_NITSCHE, ND_MAX_PENETRATION]

  call get_command_argument(1, mode)
  hybrid = mode == 'hybrid'
  damped = mode == 'damped'
  hexahedra = mode == 'hexahedra'
  dim = 2
  if (hexahedra) dim = 3
  p = make_scene()
  c = 1d0 / (beta * tau * tau)
  kappa = 1
  if (hybrid) then
    c = 4 / (tau * tau)
    kappa = 2
  end if

  ! ---- set-up: the operators, once, into the host's own dense arrays ----
  call get_dense(ND_MATRIX_MASS, Mass)
  call get_dense(ND_MATRIX_STIFFNESS, K)
  call get_dense(ND_MATRIX_NITSCHE, KT)
  n = size(Mass, 1, kind=c_int64_t)
  KT = K + KT                    ! K_Theta = K + (K_Theta - K)
  A = c * Mass + KT
  if (damped) then               ! C V^{n+1}: its part in U^{n+1}
    call get_dense(ND_MATRIX_DAMPING, Cd)
    A = A + gam / (beta * tau) * Cd
  end if
  allocate(F(n), U(n), V(n), Acc(n), U1(n), V1(n), A1(n), r(n), G(n), Nc(n))
  allocate(Ulib(n), work(n), T(n, n), node(n), comp(n))
  call check(nd_problem_get_load(p, n, F), 'nd_problem_get_load')
  call check(nd_problem_get_dof_map(p, n, node, comp), 'nd_problem_get_dof_map')
  call check(nd_problem_get_node_count(p, nn), 'nd_problem_get_node_count')
  allocate(full(dim * nn))
  call check(nd_problem_contact_tangent(p, n, nnz=tnnz), 'nd_problem_contact_tangent')
  allocate(tptr(n + 1), tcol(tnnz), tval(tnnz), last(tnnz))
  lam = lambda_min_lower(A)

  ! ---- the initial state: the library's u0, v0; A^0 from M A^0 = F - K_Theta U - N(U) ----
  call field(ND_FIELD_DISPLACEMENT, U)
  call field(ND_FIELD_VELOCITY, V)
  call check(nd_problem_contact_residual(p, n, U, Nc), 'nd_problem_contact_residual')
  Acc = F - matmul(KT, U) - Nc
  if (damped) Acc = Acc - matmul(Cd, V)
  call solve(Mass, Acc)
  if (hybrid) Acc = 0            ! (the hybrid scheme carries no acceleration: predictor U + tau V)

  worst = 0; worst_bound = 0; contact_steps = 0; ok = .true.
  do step = 1, nsteps
    if (hybrid) then  ! 2 F^{n+1/2} - K_Theta U^n + M (c U^n + 4/tau V^n)
      r = 2 * F - matmul(KT, U) + matmul(Mass, c * U + 4 / tau * V)
    else
      r = F + matmul(Mass, c * U + V / (beta * tau) + (0.5d0 / beta - 1) * Acc)
      if (damped) r = r + matmul(Cd, gam / (beta * tau) * U - (1 - gam / beta) * V - tau * (1 - gam / (2 * beta)) * Acc)
    end if
    ! ---- the host's Newmark step: semi-smooth Newton from the predictor ----
    U1 = U + tau * V + 0.5d0 * tau * tau * Acc
    last = 0
    do it = 0, 50
      if (it == 50) stop 'host_newmark: the host Newton did not converge'
      call contact_residual(U1, Nc)
      G = matmul(A, U1) + kappa * Nc - r
      gh = norm2(G)
      if (hybrid) then  ! the step form's Jacobian in U1, from the host's U^n
        call check(nd_problem_contact_step_tangent(p, n, U1, U, tnnz, tptr, tcol, tval), &
                   'nd_problem_contact_step_tangent')
      else
        call check(nd_problem_contact_tangent(p, n, U1, tnnz, tptr, tcol, tval), 'nd_problem_contact_tangent')
      end if
      ! converged: the active set (the tangent) repeats and G is within the tolerance
      if (it > 0 .and. .not. any(abs(tval - last) > 0) .and. gh <= rtol * (norm2(r) + c * norm2(matmul(Mass, U1)))) exit
      last = tval
      T = A
      do i = 1, n
        T(i, tcol(tptr(i) + 1:tptr(i + 1)) + 1) = T(i, tcol(tptr(i) + 1:tptr(i + 1)) + 1) &
                                                  + kappa * tval(tptr(i) + 1:tptr(i + 1))
      end do
      G = -G
      call solve(T, G)
      U1 = U1 + G
    end do
    if (hybrid) then
      V1 = 2 * (U1 - U) / tau - V
      A1 = 0
    else
      A1 = c * (U1 - U) - V / (beta * tau) - (0.5d0 / beta - 1) * Acc
      V1 = V + tau * ((1 - gam) * Acc + gam * A1)
    end if
    ! ---- the library's step, and the comparison ----
    call check(nd_step(p), 'nd_step')
    call field(ND_FIELD_DISPLACEMENT, Ulib)
    call contact_residual(Ulib, Nc)  ! the host's equation (its r, its U^n) at U_lib
    gl = norm2(matmul(A, Ulib) + kappa * Nc - r)
    bound = (gh + gl) / lam
    diff = norm2(U1 - Ulib)
    if (diff > bound) then
      ok = .false.
      print '(a, i0, a, es10.3, a, es10.3)', 'host_newmark: step ', step, ': |U_host - U_lib| = ', diff, &
            ' > bound ', bound
    end if
    worst = max(worst, maxval(abs(U1 - Ulib)))
    worst_bound = max(worst_bound, bound)
    call check(nd_get_scalar(p, ND_ACTIVE_POINTS, active), 'nd_get_scalar')
    if (active > 0) contact_steps = contact_steps + 1
    U = U1; V = V1; Acc = A1
  end do
  ! the contact values at the state's U are nd_get_scalar's, bit for bit; the cells' nodes
  call check(nd_problem_contact_values(p, n, Ulib, 4, cvalues), 'nd_problem_contact_values')
  do it = 1, 4
    call check(nd_get_scalar(p, keys(it), active), 'nd_get_scalar')
    if (abs(cvalues(it) - active) > 0) ok = .false.
  end do
  call check(nd_problem_get_cells(p, ncells, npc), 'nd_problem_get_cells')
  allocate(cells(npc * ncells))
  call check(nd_problem_get_cells(p, ncells, npc, cells), 'nd_problem_get_cells')
  if (hexahedra) then  ! 4 x 1 x 1 hexahedra, 8 nodes each
    if (npc /= 8 .or. ncells /= 4) ok = .false.
  else                 ! 4 x 1 rectangles, 2 triangles each
    if (npc /= 3 .or. ncells /= 8) ok = .false.
  end if
  if (minval(cells) /= 0 .or. maxval(cells) /= nn - 1) ok = .false.
  call check(nd_problem_destroy(p), 'nd_problem_destroy')
  print '(a, i0, a, i0, a, es10.3, a, es10.3)', 'host_newmark'//trim(' '//mode)//': ', nsteps, ' steps (', &
        contact_steps, &
        ' in contact), max |U_host - U_lib| = ', worst, ', bound ', worst_bound
  ! (a main program's arrays are never freed by themselves: a legacy code frees them)
  if (damped) deallocate(Cd)
  deallocate(Mass, K, KT, A, T, F, U, V, Acc, U1, V1, A1, r, G, Nc, Ulib, full, work, node, tptr, tcol, comp, &
             tval, last, cells)
  if (.not. ok .or. contact_steps < 3) stop 1

contains

  ! the host's contact term at W: N(W), or the hybrid scheme's from the host's U^n = U
  subroutine contact_residual(W, out)
    real(c_double), intent(in) :: W(:)
    real(c_double), intent(out) :: out(:)
    if (hybrid) then
      call check(nd_problem_contact_step_residual(p, n, W, U, out), 'nd_problem_contact_step_residual')
    else
      call check(nd_problem_contact_residual(p, n, W, out), 'nd_problem_contact_residual')
    end if
  end subroutine contact_residual

  subroutine check(status, what)
    integer(c_int), intent(in) :: status
    character(len=*), intent(in) :: what
    if (status /= ND_OK) then
      print '(a, a, a, a)', 'host_newmark: ', what, ': ', nd_last_error_f()
      stop 1
    end if
  end subroutine check

  function make_scene() result(q)
    type(c_ptr) :: q, m
    ! the block 1 x 0.25 (x 0.25 in 3D, the last coordinate up) 0.002 above the plane
    real(c_double) :: lo(3), hi(3), blo(3), bhi(3), origin(3) = 0d0, up(3) = 0d0, gravity(3) = 0d0
    real(c_double), allocatable :: x(:), v0(:)
    integer(c_int64_t) :: nodes, j
    lo = 0d0; hi = [1d0, 0.25d0, 0.25d0]; blo = -1d0; bhi = 2d0
    lo(dim) = 0.002d0; hi(dim) = 0.252d0; bhi(dim) = 0.0021d0
    up(dim) = 1d0; gravity(1) = 0.05d0; gravity(dim) = -1d0
    if (hexahedra) then
      call check(nd_mesh_create_box_cells(4_c_int64_t, 1_c_int64_t, 1_c_int64_t, lo, hi, ND_CELL_HEXAHEDRON, m), &
                 'nd_mesh_create_box_cells')
    else
      call check(nd_mesh_create_rectangle(4_c_int64_t, 1_c_int64_t, lo(1:2), hi(1:2), m), 'nd_mesh_create_rectangle')
    end if
    call check(nd_mesh_mark_boundary_box(m, 1, blo(1:dim), bhi(1:dim)), 'nd_mesh_mark_boundary_box')
    call check(nd_problem_create(m, 1, q), 'nd_problem_create')
    call check(nd_mesh_destroy(m), 'nd_mesh_destroy')
    call check(nd_problem_set_material(q, 1d0, 0.3d0, 1d0), 'nd_problem_set_material')
    call check(nd_problem_set_contact_plane(q, 1, origin(1:dim), up(1:dim)), 'nd_problem_set_contact_plane')
    call check(nd_problem_set_nitsche(q, 1d0, 0d0), 'nd_problem_set_nitsche')
    call check(nd_problem_set_body_force(q, gravity(1:dim)), 'nd_problem_set_body_force')
    if (damped) call check(nd_problem_set_damping(q, alpha_d, beta_d), 'nd_problem_set_damping')
    if (hybrid) then
      call check(nd_problem_set_scheme(q, ND_SCHEME_HYBRID, [0d0]), 'nd_problem_set_scheme')
    else
      call check(nd_problem_set_scheme(q, ND_SCHEME_NEWMARK, [beta, gam]), 'nd_problem_set_scheme')
    end if
    call check(nd_problem_set_timestep(q, tau), 'nd_problem_set_timestep')
    call check(nd_problem_get_node_count(q, nodes), 'nd_problem_get_node_count')
    allocate(x(dim * nodes), v0(dim * nodes))
    call check(nd_problem_get_node_coordinates(q, nodes, x), 'nd_problem_get_node_coordinates')
    v0 = 0d0
    do j = 0, nodes - 1   ! falling, sliding, spinning and stretching a little
      v0(dim * j + 1) = 0.2d0 - 0.3d0 * x(dim * j + dim) + 0.1d0 * x(dim * j + 1)**2
      v0(dim * j + dim) = -0.5d0 + 0.3d0 * (x(dim * j + 1) - 0.5d0)
    end do
    call check(nd_problem_set_initial_state(q, nodes, v0=v0), 'nd_problem_set_initial_state')
  end function make_scene

  ! an operator on the free DOFs as a dense matrix (the host's own storage)
  subroutine get_dense(which, D)
    integer(c_int), intent(in) :: which
    real(c_double), allocatable, intent(out) :: D(:,:)
    integer(c_int64_t) :: rows, entries, row
    integer(c_int64_t), allocatable :: ptr(:), col(:)
    real(c_double), allocatable :: val(:)
    call check(nd_problem_get_matrix(p, which, rows, entries), 'nd_problem_get_matrix')
    allocate(ptr(rows + 1), col(entries), val(entries), D(rows, rows))
    call check(nd_problem_get_matrix(p, which, rows, entries, ptr, col, val), 'nd_problem_get_matrix')
    D = 0
    do row = 1, rows
      D(row, col(ptr(row) + 1:ptr(row + 1)) + 1) = val(ptr(row) + 1:ptr(row + 1))
    end do
  end subroutine get_dense

  ! a field of the library's state on the free DOFs
  subroutine field(which, out)
    integer(c_int), intent(in) :: which
    real(c_double), intent(out) :: out(:)
    integer(c_int64_t) :: j
    call check(nd_get_field(p, which, nn, full), 'nd_get_field')
    do j = 1, n
      out(j) = full(dim * node(j) + comp(j) + 1)
    end do
  end subroutine field

  ! x <- B^{-1} x: Gaussian elimination with partial pivoting (B copied)
  subroutine solve(B, x)
    real(c_double), intent(in) :: B(:,:)
    real(c_double), intent(inout) :: x(:)
    real(c_double), allocatable :: L(:,:)
    real(c_double) :: t
    integer :: k, q, piv, m
    m = size(x)
    allocate(L(m, m))
    L = B
    do k = 1, m
      piv = k - 1 + maxloc(abs(L(k:m, k)), 1)
      if (piv /= k) then
        work(1:m) = L(k, :); L(k, :) = L(piv, :); L(piv, :) = work(1:m)
        t = x(k); x(k) = x(piv); x(piv) = t
      end if
      do q = k + 1, m
        t = L(q, k) / L(k, k)
        L(q, k:m) = L(q, k:m) - t * L(k, k:m)
        x(q) = x(q) - t * x(k)
      end do
    end do
    do k = m, 1, -1
      x(k) = (x(k) - dot_product(L(k, k + 1:m), x(k + 1:m))) / L(k, k)
    end do
  end subroutine solve

  ! whether B - mu I has a Cholesky factor (then lambda_min(B) > mu)
  logical function factors(B, mu)
    real(c_double), intent(in) :: B(:,:), mu
    real(c_double), allocatable :: L(:,:)
    real(c_double) :: s
    integer :: ii, jj, m
    m = size(B, 1)
    allocate(L(m, m))
    L = 0
    factors = .true.
    do ii = 1, m
      do jj = 1, ii
        s = B(ii, jj) - dot_product(L(ii, 1:jj - 1), L(jj, 1:jj - 1))
        if (ii == jj) then
          s = s - mu
          if (.not. (s > 0)) then
            factors = .false.
            return
          end if
          L(ii, ii) = sqrt(s)
        else
          L(ii, jj) = s / L(jj, jj)
        end if
      end do
    end do
  end function factors

  ! a certified lower bound of lambda_min(B), B symmetric positive definite:
  ! inverse iteration's Rayleigh quotient (>= lambda_min), lowered until B - mu I factors
  real(c_double) function lambda_min_lower(B) result(mu)
    real(c_double), intent(in) :: B(:,:)
    real(c_double), allocatable :: x(:), y(:)
    integer :: k, m
    m = size(B, 1)
    allocate(x(m), y(m))
    do k = 1, m
      x(k) = 1 + 0.1d0 * mod(k - 1, 7)
    end do
    do k = 1, 40
      x = x / norm2(x)
      y = x
      call solve(B, y)
      mu = 1 / dot_product(x, y)
      x = y
    end do
    mu = 0.999d0 * mu
    do while (.not. factors(B, mu))
      mu = 0.5d0 * mu
    end do
  end function lambda_min_lower

end program host_newmark

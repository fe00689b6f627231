! bar_history - test (a): the 1D bar driven from Fortran gives the same
! displacement and velocity histories as its C twin (bar_twin.c), at every
! FE node and every time level.
!
! usage: bar_history C_DUMP [NX [DEGREE [F_DUMP]]]
! C_DUMP is written by bar_twin with the same NX and DEGREE; F_DUMP, when
! given, receives the Fortran history in the same format.
!
! Expected: bitwise identical. Both programs make the same library calls in
! the same order with the same arguments: tau = 0.5/nx and u0 = 0.5*(1 - x)
! are single correctly rounded IEEE operations in both languages (no FMA can
! contract them), and the library is deterministic for a given machine and
! BLAS (no uninitialised data, no address-dependent ordering). Measured: 0 of
! 19762 (P1) and 0 of 39042 (P2) values differ. The test accepts a normwise
! relative difference max|F - C| / max|C| of at most 1e-14, the allowance
! for a compiler that evaluated the initial data differently (e.g. with x87
! extended precision); any difference is reported. Both programs must run
! on the same BLAS kernels: OpenBLAS chooses them by the CPU it sees. With
! the C twin run under valgrind (OpenBLAS then sees a Haswell instead of the
! host's Cooperlake) or with OPENBLAS_CORETYPE=Haswell, the P2 histories
! differ by 5e-13 and 2.4e-13 relative: the rounding of another summation
! order in the factorization, not a binding error.
program bar_history
  use, intrinsic :: iso_c_binding, only: c_int, c_int64_t, c_double, c_ptr
  use, intrinsic :: iso_fortran_env, only: error_unit
  use nitschedyn
  use nd_fortran_bar, only: make_bar
  use nd_fortran_checks, only: check, finish
  implicit none

  character(len=4096) :: c_dump, f_dump, arg
  integer(c_int64_t) :: nx, n, n_c, levels_c, steps, k
  integer(c_int) :: degree, status, ignored
  type(c_ptr) :: p
  real(c_double) :: tau, scale, max_abs, rel
  real(c_double), allocatable :: u(:), v(:), uc(:), vc(:)
  integer(c_int64_t) :: n_values, n_identical, n_unequal
  integer :: unit_c, unit_f, ios
  character(len=200) :: line

  nx = 40
  degree = 1
  f_dump = ''
  if (command_argument_count() < 1) then
    write (error_unit, '(a)') 'usage: bar_history C_DUMP [NX [DEGREE [F_DUMP]]]'
    stop 2, quiet=.true.
  end if
  call get_command_argument(1, c_dump)
  if (command_argument_count() >= 2) then
    call get_command_argument(2, arg)
    read (arg, *) nx
  end if
  if (command_argument_count() >= 3) then
    call get_command_argument(3, arg)
    read (arg, *) degree
  end if
  if (command_argument_count() >= 4) call get_command_argument(4, f_dump)

  tau = 0.5_c_double / real(nx, c_double)
  steps = nint(3.0_c_double / tau, c_int64_t)
  status = make_bar(nx, degree, tau, p, n)
  call check(status == ND_OK, 'the Fortran bar is set up')
  if (status /= ND_OK) call finish()

  open (newunit=unit_c, file=trim(c_dump), access='stream', form='unformatted', status='old', &
        action='read', iostat=ios)
  call check(ios == 0, 'the C history ' // trim(c_dump) // ' opens')
  if (ios /= 0) call finish()
  read (unit_c) n_c, levels_c
  call check(n_c == n .and. levels_c == steps + 1, 'the C history has the same nodes and time levels')
  if (n_c /= n .or. levels_c /= steps + 1) call finish()
  if (len_trim(f_dump) > 0) then
    open (newunit=unit_f, file=trim(f_dump), access='stream', form='unformatted', status='replace', &
          action='write')
    write (unit_f) n, steps + 1
  end if

  allocate(u(n), v(n), uc(n), vc(n))
  scale = 0
  max_abs = 0
  n_values = 0
  n_identical = 0
  do k = 0, steps
    if (k > 0) then
      status = nd_step(p)
      if (status /= ND_OK) exit
    end if
    status = nd_get_field(p, ND_FIELD_DISPLACEMENT, n, u)
    if (status == ND_OK) status = nd_get_field(p, ND_FIELD_VELOCITY, n, v)
    if (status /= ND_OK) exit
    if (len_trim(f_dump) > 0) write (unit_f) u, v
    read (unit_c) uc, vc
    ! bitwise: compare the bit patterns, not the values (0 and -0 differ)
    n_values = n_values + 2 * n
    n_identical = n_identical + count(transfer(u, 1_c_int64_t, n) == transfer(uc, 1_c_int64_t, n)) &
                              + count(transfer(v, 1_c_int64_t, n) == transfer(vc, 1_c_int64_t, n))
    max_abs = max(max_abs, maxval(abs(u - uc)), maxval(abs(v - vc)))
    scale = max(scale, maxval(abs(uc)), maxval(abs(vc)))
  end do
  call check(status == ND_OK, 'all steps of the Fortran bar succeed')
  if (status /= ND_OK) write (*, '(a)') '  ' // nd_last_error_f()
  close (unit_c)
  if (len_trim(f_dump) > 0) close (unit_f)
  ignored = nd_problem_destroy(p)
  deallocate(u, v, uc, vc)

  n_unequal = n_values - n_identical
  rel = max_abs / max(scale, tiny(scale))
  write (line, '(a, i0, a, i0, a, i0, a, i0, a, i0)') 'nx=', nx, ' degree=', degree, ' levels=', steps + 1, &
      ' values=', n_values, ' bitwise different=', n_unequal
  write (*, '(a)') trim(line)
  write (line, '(a, es10.3, a, es10.3)') 'max |F - C| = ', max_abs, ', relative to max |C| = ', rel
  write (*, '(a)') trim(line)
  call check(n_values == 2 * n * (steps + 1), 'every time level was compared')
  call check(rel <= 1e-14_c_double, 'the Fortran and C histories agree to 1e-14 (relative)')
  call finish()
end program bar_history

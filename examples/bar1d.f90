! bar1d.f90 - the 1D bar of docs/design.md §7 driven step by step from Fortran
! through the module nitschedyn, compared with its exact solution.
!
! The same scene as examples/bar1d.c: Omega = (0,1), rho = E = 1, clamped at
! x = 1, rigid obstacle at x = 0 (gap 0), u0(x) = (1-x)/2, v0 = 0; P1,
! hybrid scheme, Theta = 1, gamma0 = 0.2, tau = h/2, T = 3 by default. It
! prints the summary of `bar1d --quiet`, line for line the same text (the
! run times aside).
!
! The exact solution and the seven relative error norms are not ported: the
! program calls the C functions of examples/bar1d_exact.c (linked from the
! static library nd_bar1d_exact) through the bind(C) interfaces of module
! bar1d_exact below. One implementation of the norms serves the C example,
! the convergence test and this program, so their numbers can only differ if
! the discrete solutions do; a Fortran port would be ~150 lines to keep in
! step by hand. It is also a second exercise of C interoperability:
! structures passed and returned by value, pointers inside structures, and
! a C array of strings.
!
! usage: bar1d_f90 [--scheme hybrid|galpha] [--rho-inf X] [--nx N] [--degree 1|2] [--tau X] [--T X] [--quiet]
! (--key=value also works; --quiet is accepted for symmetry with bar1d, the
! summary is all this program prints). Exit status: 0 ok, 1 library error,
! 2 usage error.

! ---- the C helpers of examples/bar1d_exact.h ----------------------------------
module bar1d_exact
  use, intrinsic :: iso_c_binding, only: c_int, c_int64_t, c_double, c_ptr
  implicit none
  private
  public :: phase, exact_value, grid, space_norms, norm_acc, N_NORMS, LINF_L2_V, norm_names
  public :: phase_at, exact_at, exact_stress, grid_init, grid_free, norms_at, acc_add, acc_relative

  ! the enum of bar1d_exact.h: LINF_L2_U, LINF_H1_U, LINF_L2_V, L2_L2_U,
  ! L2_H1_U, L2_L2_V, L2_SIGMA, N_NORMS (0-based, as in C)
  integer(c_int), parameter :: LINF_L2_V = 2, N_NORMS = 7

  type, bind(C) :: phase ! k = 0 flight, 1 contact, 2 release; r in [0,1)
    integer(c_int) :: k
    real(c_double) :: r
  end type phase

  type, bind(C) :: exact_value
    real(c_double) :: u, v, ux
  end type exact_value

  type, bind(C) :: grid ! the FE nodes sorted by coordinate
    integer(c_int) :: degree
    integer(c_int64_t) :: n_nodes, n_cells
    type(c_ptr) :: x  ! double *: sorted coordinates
    type(c_ptr) :: id ! int64_t *: id(i) = 0-based library index of the i-th sorted node
  end type grid

  type, bind(C) :: space_norms ! squared L2 norms: (1) u, (2) u_x, (3) v
    real(c_double) :: err(3), ref(3)
  end type space_norms

  type, bind(C) :: norm_acc ! running max (Linf) or trapezoidal sum (L2) of squares
    real(c_double) :: err(N_NORMS), ref(N_NORMS)
  end type norm_acc

  ! extern const char *const norm_names[N_NORMS]; gfortran emits this
  ! declaration as a common symbol, which the linker merges with the
  ! definition in bar1d_exact.c (the Fortran side never defines it)
  type(c_ptr), bind(C, name='norm_names'), protected :: norm_names(N_NORMS)

  interface
    function phase_at(t) result(ph) bind(C, name='phase_at')
      import :: c_double, phase
      real(c_double), value :: t
      type(phase) :: ph
    end function phase_at

    function exact_at(ph, x) result(e) bind(C, name='exact_at')
      import :: c_double, phase, exact_value
      type(phase), value :: ph
      real(c_double), value :: x
      type(exact_value) :: e
    end function exact_at

    function exact_stress(ph) result(sigma) bind(C, name='exact_stress')
      import :: c_double, phase
      type(phase), value :: ph
      real(c_double) :: sigma
    end function exact_stress

    function grid_init(g, degree, n_cells, coords, n_nodes) result(status) bind(C, name='grid_init')
      import :: c_int, c_int64_t, c_double, grid
      type(grid), intent(out) :: g
      integer(c_int), value :: degree
      integer(c_int64_t), value :: n_cells
      real(c_double), intent(in) :: coords(*)
      integer(c_int64_t), value :: n_nodes
      integer(c_int) :: status
    end function grid_init

    subroutine grid_free(g) bind(C, name='grid_free')
      import :: grid
      type(grid), intent(inout) :: g
    end subroutine grid_free

    function norms_at(g, u, v, ph) result(s) bind(C, name='norms_at')
      import :: c_double, grid, phase, space_norms
      type(grid), intent(in) :: g
      real(c_double), intent(in) :: u(*), v(*)
      type(phase), value :: ph
      type(space_norms) :: s
    end function norms_at

    subroutine acc_add(a, s, sigma_err, sigma_ref, w) bind(C, name='acc_add')
      import :: c_double, norm_acc, space_norms
      type(norm_acc), intent(inout) :: a
      type(space_norms), intent(in) :: s
      real(c_double), value :: sigma_err, sigma_ref, w
    end subroutine acc_add

    function acc_relative(a, i) result(rel) bind(C, name='acc_relative')
      import :: c_int, c_double, norm_acc
      type(norm_acc), intent(in) :: a
      integer(c_int), value :: i ! 0-based
      real(c_double) :: rel
    end function acc_relative
  end interface
end module bar1d_exact

! ---- C's printf conversions %g, %.Ne and %.Nf, for identical summaries --------
module c_format
  use, intrinsic :: iso_c_binding, only: c_double
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_is_nan, ieee_class, ieee_negative_zero, &
                                           ieee_positive_zero, operator(==)
  implicit none
  private
  public :: fmt_g, fmt_e, fmt_f

contains

  ! nan, inf, -inf as C prints them ('' for a finite x)
  function special(x) result(s)
    real(c_double), intent(in) :: x
    character(len=:), allocatable :: s
    s = ''
    if (ieee_is_nan(x)) then
      s = 'nan'
    else if (.not. ieee_is_finite(x)) then
      s = 'inf'
      if (x < 0) s = '-inf'
    end if
  end function special

  ! %.<d>e
  function fmt_e(x, d) result(s)
    real(c_double), intent(in) :: x
    integer, intent(in) :: d
    character(len=:), allocatable :: s
    character(len=64) :: buf, fmt
    integer :: ie, expo
    s = special(x)
    if (len(s) > 0) return
    write (fmt, '(a, i0, a)') '(es40.', d, 'e4)' ! mantissa d.ddd, exponent E+dddd
    write (buf, fmt) x
    buf = adjustl(buf)
    ie = index(buf, 'E')
    read (buf(ie + 1:), *) expo
    write (fmt, '(sp, i0.2)') expo ! C: sign and at least two digits
    s = buf(1:ie - 1) // 'e' // trim(fmt)
  end function fmt_e

  ! %.<d>f
  function fmt_f(x, d) result(s)
    real(c_double), intent(in) :: x
    integer, intent(in) :: d
    character(len=:), allocatable :: s
    character(len=64) :: buf, fmt
    s = special(x)
    if (len(s) > 0) return
    write (fmt, '(a, i0, a)') '(f0.', d, ')'
    write (buf, fmt) x
    s = trim(buf)
    ! F0.d may drop the zero before the point; C never does
    if (s(1:1) == '.') s = '0' // s
    if (len(s) >= 2) then
      if (s(1:2) == '-.') s = '-0' // s(2:)
    end if
    if (len(s) == 0) s = '0'
  end function fmt_f

  ! %g: 6 significant digits, trailing zeros removed; %f style when the
  ! decimal exponent X (after rounding) satisfies -4 <= X < 6, else %e style.
  function fmt_g(x) result(s)
    real(c_double), intent(in) :: x
    character(len=:), allocatable :: s
    integer, parameter :: P = 6
    integer :: expo, ie
    s = special(x)
    if (len(s) > 0) return
    if (ieee_class(x) == ieee_positive_zero) then
      s = '0'
      return
    else if (ieee_class(x) == ieee_negative_zero) then
      s = '-0'
      return
    end if
    s = fmt_e(x, P - 1)
    ie = index(s, 'e')
    read (s(ie + 1:), *) expo
    if (expo >= -4 .and. expo < P) then
      s = strip_zeros(fmt_f(x, P - 1 - expo))
    else
      s = strip_zeros(s(1:ie - 1)) // s(ie:)
    end if
  end function fmt_g

  ! removes trailing zeros after a decimal point, and then the point
  function strip_zeros(a) result(s)
    character(len=*), intent(in) :: a
    character(len=:), allocatable :: s
    integer :: n
    s = a
    if (index(s, '.') == 0) return
    n = len(s)
    do while (s(n:n) == '0')
      n = n - 1
    end do
    if (s(n:n) == '.') n = n - 1
    s = s(1:n)
  end function strip_zeros

end module c_format

! ---- the program ------------------------------------------------------------
program bar1d
  use, intrinsic :: iso_c_binding, only: c_int, c_int64_t, c_double, c_ptr, c_null_ptr, c_char, c_size_t, &
                                         c_f_pointer
  use, intrinsic :: iso_fortran_env, only: error_unit, output_unit
  use nitschedyn
  use bar1d_exact
  use c_format, only: fmt_g, fmt_e, fmt_f
  implicit none

  integer(c_int), parameter :: CLAMPED = 1, CONTACT = 2
  real(c_double), parameter :: THETA = 1, GAMMA0 = 0.2_c_double

  integer(c_int64_t) :: nx = 40, steps, n_nodes, n
  integer(c_int) :: degree = 1
  real(c_double) :: tau = 0, t_final = 3
  integer(c_int) :: scheme = ND_SCHEME_HYBRID
  real(c_double) :: rho_inf = 0.8_c_double ! generalized-alpha's parameter
  type(c_ptr) :: p = c_null_ptr
  type(grid) :: g
  logical :: have_grid = .false.
  real(c_double), allocatable :: u(:), v(:)
  ! the run: norms, energy bounds, Newton iterations, times (s)
  type(norm_acc) :: norms
  real(c_double) :: e_min, e_max, et_min, et_max, newton_sum, it
  real(c_double) :: e0, et0, drift ! max |E_Theta - E_Theta(0) - W| / E(0)
  real(c_double) :: t_setup, t_loop, t_eval
  integer(c_int64_t) :: clock_rate, t0, t1
  integer(c_int) :: ignored
  logical :: fail

  interface
    ! the C library's strlen, for the names in norm_names
    function c_strlen(s) result(length) bind(C, name='strlen')
      import :: c_ptr, c_size_t
      type(c_ptr), value :: s
      integer(c_size_t) :: length
    end function c_strlen
  end interface

  call parse_args()
  steps = nint(t_final / tau, c_int64_t)
  call system_clock(count_rate=clock_rate)

  call system_clock(t0)
  fail = setup()
  if (.not. fail) fail = check(nd_problem_setup(p)) ! the first step's set-up, timed here
  call system_clock(t1)
  t_setup = real(t1 - t0, c_double) / real(clock_rate, c_double)

  norms%err = 0
  norms%ref = 0
  newton_sum = 0
  t_loop = 0
  t_eval = 0
  if (.not. fail) allocate(u(n_nodes), v(n_nodes))
  do n = 0, steps
    if (fail) exit
    if (n > 0) then
      call system_clock(t0)
      fail = check(nd_step(p)) ! no monitor is set, so ND_MONITOR_STOP cannot come
      call system_clock(t1)
      t_loop = t_loop + real(t1 - t0, c_double) / real(clock_rate, c_double)
      it = 0
      if (.not. fail) fail = check(nd_get_scalar(p, ND_NEWTON_ITERATIONS, it))
      newton_sum = newton_sum + it
      if (fail) then
        write (error_unit, '(a, i0, a, i0, a)') 'bar1d: step ', n, ' of ', steps, ' failed'
        exit
      end if
    end if
    call system_clock(t0)
    fail = sample(n)
    call system_clock(t1)
    t_eval = t_eval + real(t1 - t0, c_double) / real(clock_rate, c_double)
  end do

  if (have_grid) call grid_free(g)
  if (allocated(u)) deallocate(u, v)
  ignored = nd_problem_destroy(p)
  if (fail) stop 1, quiet=.true.
  call print_summary()

contains

  subroutine usage_error(message)
    character(len=*), intent(in) :: message
    write (error_unit, '(a)') 'bar1d: ' // message // ' (try --help)'
    stop 2, quiet=.true.
  end subroutine usage_error

  subroutine parse_args()
    character(len=256) :: arg, key, val
    integer :: i, eq, ios
    i = 1
    do while (i <= command_argument_count())
      call get_command_argument(i, arg)
      i = i + 1
      if (arg == '--help' .or. arg == '-h') then
        write (output_unit, '(a)') &
          'usage: bar1d_f90 [--scheme hybrid|galpha] [--rho-inf X] [--nx N] [--degree 1|2] [--tau X] [--T X] [--quiet]', &
          'The 1D bar of docs/design.md §7 from Fortran (Theta = 1, gamma0 = 0.2): the summary of bar1d --quiet.', &
          'Defaults: hybrid scheme, rho_inf 0.8 (generalized-alpha), nx 40, degree 1, tau h/2, T 3.'
        stop
      end if
      if (arg == '--quiet') cycle
      eq = index(arg, '=')
      if (eq > 0) then
        key = arg(1:eq - 1)
        val = arg(eq + 1:)
      else
        key = arg
        if (i > command_argument_count()) call usage_error(trim(key) // ' needs a value')
        call get_command_argument(i, val)
        i = i + 1
      end if
      select case (trim(key))
      case ('--scheme')
        select case (trim(val))
        case ('hybrid')
          scheme = ND_SCHEME_HYBRID
        case ('galpha')
          scheme = ND_SCHEME_GENERALIZED_ALPHA
        case default
          call usage_error("bad value '" // trim(val) // "'")
        end select
      case ('--rho-inf')
        read (val, *, iostat=ios) rho_inf
        if (ios /= 0) call usage_error("bad value '" // trim(val) // "'")
      case ('--nx')
        read (val, *, iostat=ios) nx
        if (ios /= 0 .or. nx < 1 .or. nx > 100000000) call usage_error("bad value '" // trim(val) // "'")
      case ('--degree')
        read (val, *, iostat=ios) degree
        if (ios /= 0 .or. (degree /= 1 .and. degree /= 2)) call usage_error("bad value '" // trim(val) // "'")
      case ('--tau')
        read (val, *, iostat=ios) tau
        if (ios /= 0 .or. .not. tau > 0) call usage_error("bad value '" // trim(val) // "'")
      case ('--T')
        read (val, *, iostat=ios) t_final
        if (ios /= 0 .or. .not. t_final > 0) call usage_error("bad value '" // trim(val) // "'")
      case default
        call usage_error('unknown option ' // trim(arg))
      end select
    end do
    if (.not. tau > 0) tau = 0.5_c_double / real(nx, c_double)
    if (nint(t_final / tau, c_int64_t) < 1) call usage_error('T/tau rounds to zero steps')
  end subroutine parse_args

  ! .true. (failed) when status is not ND_OK, after printing nd_last_error
  logical function check(status_)
    integer(c_int), intent(in) :: status_
    check = status_ /= ND_OK
    if (check) write (error_unit, '(a)') 'bar1d: ' // nd_last_error_f()
  end function check

  ! Mesh, regions, material, contact, scheme, initial state; the sorted grid.
  ! The calls of examples/bar1d.c, in the same order.
  logical function setup() result(failed)
    type(c_ptr) :: mesh
    real(c_double), allocatable :: x(:), u0(:), v0(:)
    integer(c_int64_t) :: n_contact
    mesh = c_null_ptr
    failed = check(nd_mesh_create_interval(nx, 0.0_c_double, 1.0_c_double, mesh))
    if (.not. failed) failed = check(nd_mesh_mark_boundary_box(mesh, CLAMPED, [0.5_c_double], [1.5_c_double]))
    if (.not. failed) failed = check(nd_mesh_mark_boundary_box(mesh, CONTACT, [-0.5_c_double], [0.5_c_double]))
    if (.not. failed) failed = check(nd_problem_create(mesh, degree, p))
    ignored = nd_mesh_destroy(mesh) ! the problem keeps its own copy
    if (failed) return
    failed = check(nd_problem_set_material(p, 1.0_c_double, 0.0_c_double, 1.0_c_double))
    if (.not. failed) failed = check(nd_problem_set_dirichlet(p, CLAMPED))
    if (.not. failed) failed = check(nd_problem_set_contact_plane(p, CONTACT, [0.0_c_double], [1.0_c_double]))
    if (.not. failed) failed = check(nd_problem_set_nitsche(p, THETA, GAMMA0))
    if (.not. failed) then
      if (scheme == ND_SCHEME_HYBRID) then
        failed = check(nd_problem_set_scheme(p, scheme)) ! no parameter: NULL
      else
        failed = check(nd_problem_set_scheme(p, scheme, [rho_inf]))
      end if
    end if
    if (.not. failed) failed = check(nd_problem_set_mass_lumping(p, 0_c_int))
    if (.not. failed) failed = check(nd_problem_set_timestep(p, tau))
    if (.not. failed) failed = check(nd_problem_get_node_count(p, n_nodes))
    if (failed) return
    allocate(x(n_nodes), u0(n_nodes), v0(n_nodes))
    failed = check(nd_problem_get_node_coordinates(p, n_nodes, x))
    if (failed) return
    if (grid_init(g, degree, nx, x, n_nodes) /= 0) then
      write (error_unit, '(a, i0, a, i0, a)') 'bar1d: expected ', nx * degree + 1, ' FE nodes, got ', n_nodes, &
        ' (or out of memory)'
      failed = .true.
      return
    end if
    have_grid = .true.
    u0 = 0.5_c_double * (1 - x)
    v0 = 0 ! the bar starts at rest
    failed = check(nd_problem_set_initial_state(p, n_nodes, u0, v0))
    if (.not. failed) failed = check(nd_problem_get_contact_point_count(p, n_contact))
    if (.not. failed .and. n_contact /= 1) then
      write (error_unit, '(a, i0)') 'bar1d: expected 1 contact point, got ', n_contact
      failed = .true.
    end if
  end function setup

  ! Samples time level k: errors and energies (as bar1d.c's sample()).
  logical function sample(k) result(failed)
    integer(c_int64_t), intent(in) :: k
    real(c_double) :: lam(1), e, et, work, t, sigma, w
    type(phase) :: ph
    type(space_norms) :: s
    failed = check(nd_get_field(p, ND_FIELD_DISPLACEMENT, n_nodes, u))
    if (.not. failed) failed = check(nd_get_field(p, ND_FIELD_VELOCITY, n_nodes, v))
    if (.not. failed) failed = check(nd_get_contact_pressure(p, 1_c_int64_t, lam))
    if (.not. failed) failed = check(nd_get_scalar(p, ND_ENERGY_MECHANICAL, e))
    if (.not. failed) failed = check(nd_get_scalar(p, ND_ENERGY_AUGMENTED, et))
    if (.not. failed) failed = check(nd_get_scalar(p, ND_WORK, work))
    if (failed) return
    t = real(k, c_double) * tau
    ph = phase_at(t)
    s = norms_at(g, u, v, ph)
    sigma = exact_stress(ph)
    w = tau
    if (k == 0 .or. k == steps) w = 0.5_c_double * tau ! trapezoidal weight
    call acc_add(norms, s, lam(1) - sigma, sigma, w)
    if (k == 0) then
      e0 = e
      et0 = et
      drift = 0
      e_min = e
      e_max = e
      et_min = et
      et_max = et
    else
      e_min = min(e_min, e)
      e_max = max(e_max, e)
      et_min = min(et_min, et)
      et_max = max(et_max, et)
    end if
    drift = max(drift, abs(et - et0 - work) / e0)
  end function sample

  ! a C string of the norm_names array
  function c_name(i) result(s)
    integer, intent(in) :: i
    character(len=:), allocatable :: s
    character(kind=c_char), pointer :: chars(:)
    integer :: length, j
    length = int(c_strlen(norm_names(i)))
    call c_f_pointer(norm_names(i), chars, [length])
    allocate(character(len=length) :: s)
    do j = 1, length
      s(j:j) = chars(j)
    end do
  end function c_name

  subroutine print_summary()
    character(len=18) :: name
    integer :: i
    logical :: relative
    character(len=:), allocatable :: label
    if (scheme == ND_SCHEME_HYBRID) then
      label = 'hybrid'
    else
      label = 'galpha(' // fmt_g(rho_inf) // ')'
    end if
    write (output_unit, '(a)') 'scheme=' // label // ' degree=' // itoa(int(degree, c_int64_t)) // ' Theta=' // &
      fmt_g(THETA) // ' gamma0=' // fmt_g(GAMMA0) // ' nx=' // itoa(nx) // ' tau=' // fmt_g(tau) // &
      ' T=' // fmt_g(real(steps, c_double) * tau) // ' steps=' // itoa(steps)
    do i = 1, N_NORMS
      relative = norms%ref(i) > 0
      name = c_name(i)
      if (relative) then
        write (output_unit, '(a)') 'rel. error  ' // name // ' ' // fmt_e(acc_relative(norms, i - 1), 6)
      else
        write (output_unit, '(a)') 'abs. error  ' // name // ' ' // fmt_e(acc_relative(norms, i - 1), 6) // &
          '  (exact norm is 0)'
      end if
    end do
    write (output_unit, '(a)') 'E        min ' // fmt_f(e_min, 8) // ' max ' // fmt_f(e_max, 8) // &
      '    E_Theta min ' // fmt_f(et_min, 8) // ' max ' // fmt_f(et_max, 8) // '   (exact E = 0.125)'
    write (output_unit, '(a)') 'energy drift max|E_Theta - E_Theta(0) - W|/E(0) ' // fmt_e(drift, 3)
    write (output_unit, '(a)') 'Newton iterations per step (mean) ' // fmt_f(newton_sum / real(steps, c_double), 3)
    write (output_unit, '(a)') 'run time: setup ' // fmt_f(t_setup, 4) // ' s, time loop ' // fmt_f(t_loop, 4) // &
      ' s (' // fmt_f(1e3_c_double * t_loop / real(steps, c_double), 4) // &
      ' ms/step; nd_step calls only), error evaluation ' // fmt_f(t_eval, 4) // ' s'
  end subroutine print_summary

  function itoa(i) result(s)
    integer(c_int64_t), intent(in) :: i
    character(len=:), allocatable :: s
    character(len=24) :: buf
    write (buf, '(i0)') i
    s = trim(buf)
  end function itoa

end program bar1d

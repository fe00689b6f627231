! test_api - the Fortran module against the library, one part per CTest:
!   errors     (b) a bad argument returns its ND_ERR_* code and the message of
!                  nd_last_error reaches Fortran intact
!   destroy    (c) destroying a handle twice is harmless
!   monitor    (d) a monitor written in Fortran runs once per step and can stop
!   api        generated constants, nd_version, absent optional arguments
!              (NULL), a general mesh
!   obstacles  a plane given as a distance callback written in Fortran
!              (bind(C), type(c_funptr)) steps bitwise as the built-in plane;
!              a circle added and moved, with and without a rotation
!   friction   a block on a plane with Coulomb friction (the plane tilted
!              against gravity): it slides, the tangential resultant is F
!              times the normal one, friction dissipates; bad arguments
!   checkpoint a state saved into a Fortran byte array and loaded back: the
!              resumed run is bitwise the uninterrupted one; set_state and
!              guards from Fortran
! usage: test_api PART; prints "N passed, M failed", exits 1 on a failure.
program test_api
  use, intrinsic :: iso_c_binding
  use, intrinsic :: iso_fortran_env, only: error_unit
  use nitschedyn
  use nd_fortran_bar, only: make_bar
  use nd_fortran_checks, only: check, finish
  implicit none

  ! what the monitor sees through its userdata pointer
  type :: monitor_data
    integer :: calls = 0
    integer :: stop_at = -1 ! the call that asks to stop
    type(c_ptr) :: expected = c_null_ptr
    real(c_double) :: last_time = -1
    integer :: wrong_handle = 0
  end type monitor_data

  interface
    ! the C library's strlen, to check the length of nd_last_error()
    function c_strlen(s) result(n) bind(C, name='strlen')
      import :: c_ptr, c_size_t
      type(c_ptr), value :: s
      integer(c_size_t) :: n
    end function c_strlen
  end interface

  character(len=32) :: part
  if (command_argument_count() /= 1) then
    write (error_unit, '(a)') 'usage: test_api errors|destroy|monitor|api|checkpoint|obstacles|friction|pairs|adaptive'
    stop 2, quiet=.true.
  end if
  call get_command_argument(1, part)
  select case (trim(part))
  case ('errors')
    call test_errors()
  case ('destroy')
    call test_destroy()
  case ('monitor')
    call test_monitor()
  case ('api')
    call test_constants_and_api()
  case ('checkpoint')
    call test_checkpoint()
  case ('obstacles')
    call test_obstacles()
  case ('friction')
    call test_friction()
  case ('pairs')
    call test_pairs()
    call test_pair_hexahedra()
    call test_pair_friction()
    call test_self_pair()
  case ('adaptive')
    call test_adaptive()
  case default
    write (error_unit, '(a)') 'test_api: unknown part ' // trim(part)
    stop 2, quiet=.true.
  end select
  call finish()

contains

  logical function starts_with(s, prefix)
    character(len=*), intent(in) :: s, prefix
    starts_with = len(s) >= len(prefix)
    if (starts_with) starts_with = s(1:len(prefix)) == prefix
  end function starts_with

  ! ---- (b) ---------------------------------------------------------------
  subroutine test_errors()
    type(c_ptr) :: p, m
    integer(c_int64_t) :: n
    integer(c_int) :: status
    character(len=:), allocatable :: msg
    real(c_double) :: x
    real(c_double), allocatable :: buf(:)
    integer(c_size_t) :: length

    call check(make_bar(10_c_int64_t, 1_c_int, 0.05_c_double, p, n) == ND_OK, 'the bar is set up')

    status = nd_problem_set_timestep(p, -1.0_c_double)
    call check(status == ND_ERR_TIMESTEP, 'nd_problem_set_timestep(p, -1) returns ND_ERR_TIMESTEP')
    msg = nd_last_error_f()
    write (*, '(a)') '  nd_last_error_f() = "' // msg // '"'
    call check(starts_with(msg, 'nd_problem_set_timestep:'), 'the message starts with "nd_problem_set_timestep:"')
    length = c_strlen(nd_last_error())
    call check(len(msg) == length .and. index(msg, c_null_char) == 0 &
               .and. len(msg) > len('nd_problem_set_timestep: '), &
               'the message arrives whole: its length is strlen(nd_last_error()), no NUL inside')
    call check(msg == nd_last_error_f(), 'reading the message does not clear it')
    call check(nd_strerror_f(status) == 'the time step is not positive and finite', &
               'nd_strerror_f(ND_ERR_TIMESTEP) is the header''s text')

    x = ieee_nan()
    call check(nd_problem_set_timestep(p, x) == ND_ERR_TIMESTEP, 'a NaN time step returns ND_ERR_TIMESTEP')
    call check(nd_problem_set_timestep(p, 0.05_c_double) == ND_OK, 'a good time step returns ND_OK')
    call check(len(nd_last_error_f()) == 0, 'a successful call clears the message')

    call check(nd_step(c_null_ptr) == ND_ERR_NULL, 'nd_step(c_null_ptr) returns ND_ERR_NULL')
    call check(starts_with(nd_last_error_f(), 'nd_step:'), 'and its message names nd_step')

    status = nd_mesh_create_interval(0_c_int64_t, 0.0_c_double, 1.0_c_double, m)
    call check(status < 0 .and. .not. c_associated(m), 'nd_mesh_create_interval with 0 cells fails, no handle')
    call check(starts_with(nd_last_error_f(), 'nd_mesh_create_interval:'), &
               'and its message names nd_mesh_create_interval')

    allocate(buf(n + 1))
    call check(nd_get_field(p, ND_FIELD_DISPLACEMENT, n + 1, buf) == ND_ERR_SIZE, &
               'nd_get_field with a wrong node count returns ND_ERR_SIZE')
    call check(nd_get_scalar(p, 9999_c_int, x) == ND_ERR_KEY, 'nd_get_scalar with an unknown key returns ND_ERR_KEY')
    call check(nd_problem_set_scheme(p, ND_SCHEME_THETA) == ND_ERR_NULL, &
               'ND_SCHEME_THETA with params absent (NULL) returns ND_ERR_NULL')
    call check(nd_problem_destroy(p) == ND_OK, 'nd_problem_destroy')
  end subroutine test_errors

  real(c_double) function ieee_nan()
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
    ieee_nan = ieee_value(0.0_c_double, ieee_quiet_nan)
  end function ieee_nan

  ! ---- (c) ---------------------------------------------------------------
  subroutine test_destroy()
    type(c_ptr) :: m, p
    integer(c_int64_t) :: n
    integer(c_int) :: status

    m = c_null_ptr
    call check(nd_mesh_destroy(m) == ND_OK, 'nd_mesh_destroy(c_null_ptr) returns ND_OK')
    status = nd_mesh_create_interval(4_c_int64_t, 0.0_c_double, 1.0_c_double, m)
    call check(status == ND_OK .and. c_associated(m), 'nd_mesh_create_interval gives a handle')
    call check(nd_mesh_destroy(m) == ND_OK, 'first nd_mesh_destroy returns ND_OK')
    call check(.not. c_associated(m), 'and sets the handle to c_null_ptr')
    call check(nd_mesh_destroy(m) == ND_OK, 'second nd_mesh_destroy returns ND_OK')
    call check(.not. c_associated(m), 'and the handle stays c_null_ptr')

    status = make_bar(4_c_int64_t, 1_c_int, 0.1_c_double, p, n)
    call check(status == ND_OK .and. c_associated(p), 'the bar problem is set up')
    call check(nd_step(p) == ND_OK, 'one step')
    call check(nd_problem_destroy(p) == ND_OK, 'first nd_problem_destroy returns ND_OK')
    call check(.not. c_associated(p), 'and sets the handle to c_null_ptr')
    call check(nd_problem_destroy(p) == ND_OK, 'second nd_problem_destroy returns ND_OK')
    call check(.not. c_associated(p), 'and the handle stays c_null_ptr')
    call check(nd_step(p) == ND_ERR_NULL, 'nd_step on the destroyed handle returns ND_ERR_NULL')
  end subroutine test_destroy

  ! ---- (d) ---------------------------------------------------------------
  ! The monitor: counts its calls, checks it gets the problem it was set on,
  ! queries the problem, and asks to stop at call stop_at.
  integer(c_int) function count_steps(p, userdata) bind(C)
    type(c_ptr), value :: p, userdata
    type(monitor_data), pointer :: d
    call c_f_pointer(userdata, d)
    d%calls = d%calls + 1
    if (.not. c_associated(p, d%expected)) d%wrong_handle = d%wrong_handle + 1
    if (nd_get_scalar(p, ND_TIME, d%last_time) /= ND_OK) d%last_time = -1
    count_steps = 0
    if (d%calls == d%stop_at) count_steps = 1
  end function count_steps

  subroutine test_monitor()
    type(c_ptr) :: p
    integer(c_int64_t) :: n
    integer(c_int) :: status
    type(monitor_data), target :: data
    real(c_double), parameter :: tau = 0.05_c_double
    real(c_double) :: steps_taken, t
    integer :: k

    call check(make_bar(10_c_int64_t, 1_c_int, tau, p, n) == ND_OK, 'the bar is set up')
    data%expected = p
    call check(nd_problem_set_monitor(p, c_funloc(count_steps), c_loc(data)) == ND_OK, &
               'nd_problem_set_monitor(p, c_funloc(count_steps), c_loc(data))')
    status = ND_OK
    do k = 1, 10
      status = nd_step(p)
      if (status /= ND_OK) exit
    end do
    call check(status == ND_OK, '10 steps return ND_OK while the monitor returns 0')
    call check(data%calls == 10, 'the monitor was called once per step (10 times)')
    call check(data%wrong_handle == 0, 'the monitor received the problem''s handle')
    call check(abs(data%last_time - 10 * tau) <= 1e-12_c_double, 'the monitor can query the problem (time 10 tau)')

    data%stop_at = 15
    do k = 1, 100
      status = nd_step(p)
      if (status /= ND_OK) exit
    end do
    call check(status == ND_MONITOR_STOP, 'nd_step returns ND_MONITOR_STOP when the monitor asks to stop')
    call check(k == 5 .and. data%calls == 15, 'the run stopped at the 15th step, as asked')
    status = nd_get_scalar(p, ND_STEP_INDEX, steps_taken)
    call check(status == ND_OK .and. nint(steps_taken) == 15, 'the stopping step was kept (ND_STEP_INDEX = 15)')
    status = nd_get_scalar(p, ND_TIME, t)
    call check(status == ND_OK .and. abs(t - 15 * tau) <= 1e-12_c_double, 'the time is 15 tau')
    status = nd_step(p)
    call check(status == ND_OK .and. data%calls == 16, 'stepping on after a stop works')

    call check(nd_problem_set_monitor(p, c_null_funptr, c_null_ptr) == ND_OK, &
               'nd_problem_set_monitor(p, c_null_funptr, c_null_ptr) removes the monitor')
    status = nd_step(p)
    call check(status == ND_OK .and. data%calls == 16, 'without a monitor nothing is called')
    call check(nd_problem_destroy(p) == ND_OK, 'nd_problem_destroy')
  end subroutine test_monitor

  ! ---- obstacles ------------------------------------------------------------
  ! the plane y = 0 as a signed distance: d = y, nu = (0, 1)
  integer(c_int) function plane_y0(t, x, d, nu, user) bind(C)
    real(c_double), value :: t
    real(c_double), intent(in) :: x(*)
    real(c_double), intent(out) :: d, nu(*)
    type(c_ptr), value :: user
    integer, pointer :: calls
    call c_f_pointer(user, calls)
    calls = calls + 1
    d = x(2) + 0 * t
    nu(1) = 0
    nu(2) = 1
    plane_y0 = 0
  end function plane_y0

  ! a 4 x 2 block [-1, 1] x [0.5, 1.5] under gravity; region 1 its bottom
  subroutine block(p, n)
    type(c_ptr), intent(out) :: p
    integer(c_int64_t), intent(out) :: n
    type(c_ptr) :: m
    real(c_double) :: lo(2) = [-1.0_c_double, 0.5_c_double], hi(2) = [1.0_c_double, 1.5_c_double]
    real(c_double) :: blo(2) = [-2.0_c_double, 0.4_c_double], bhi(2) = [2.0_c_double, 0.6_c_double]
    real(c_double) :: g(2) = [0.0_c_double, -1.0_c_double]
    call check(nd_mesh_create_rectangle(8_c_int64_t, 4_c_int64_t, lo, hi, m) == ND_OK, 'nd_mesh_create_rectangle')
    call check(nd_mesh_mark_boundary_box(m, 1_c_int, blo, bhi) == ND_OK, 'nd_mesh_mark_boundary_box')
    call check(nd_problem_create(m, 1_c_int, p) == ND_OK, 'nd_problem_create')
    call check(nd_mesh_destroy(m) == ND_OK, 'nd_mesh_destroy')
    call check(nd_problem_set_material(p, 100.0_c_double, 0.3_c_double, 1.0_c_double) == ND_OK, 'material')
    call check(nd_problem_set_body_force(p, g) == ND_OK, 'body force')
    call check(nd_problem_set_nitsche(p, 1.0_c_double, 0.0_c_double) == ND_OK, 'Nitsche')
    call check(nd_problem_set_scheme(p, ND_SCHEME_HYBRID) == ND_OK, 'scheme')
    call check(nd_problem_set_timestep(p, 0.02_c_double) == ND_OK, 'time step')
    call check(nd_problem_get_node_count(p, n) == ND_OK, 'node count')
  end subroutine block

  subroutine test_obstacles()
    type(c_ptr) :: a, b
    integer(c_int64_t) :: n
    integer, target :: calls
    real(c_double), allocatable :: ua(:), ub(:)
    real(c_double) :: origin(2) = 0, up(2) = [0.0_c_double, 1.0_c_double], centre(2) = [0.0_c_double, -10.0_c_double]
    real(c_double) :: shift(2) = [0.01_c_double, 0.0_c_double], rot(4), active, touched, angle
    integer :: k
    logical :: same

    call block(a, n)
    call block(b, n)
    calls = 0
    call check(nd_problem_add_contact_distance(a, 1_c_int, c_funloc(plane_y0), c_loc(calls)) == ND_OK, &
               'nd_problem_add_contact_distance(p, 1, c_funloc(plane_y0), c_loc(calls))')
    call check(nd_problem_set_contact_plane(b, 1_c_int, origin, up) == ND_OK, 'nd_problem_set_contact_plane')
    allocate (ua(2 * n), ub(2 * n))
    same = .true.
    touched = 0
    do k = 1, 60
      call check(nd_step(a) == ND_OK, 'a step on the callback''s plane')
      call check(nd_step(b) == ND_OK, 'a step on the plane')
      call check(nd_get_field(a, ND_FIELD_DISPLACEMENT, n, ua) == ND_OK, 'displacement')
      call check(nd_get_field(b, ND_FIELD_DISPLACEMENT, n, ub) == ND_OK, 'displacement')
      ! (bit for bit: the same doubles as integers)
      same = same .and. all(transfer(ua, 1_c_int64_t, size(ua)) == transfer(ub, 1_c_int64_t, size(ub)))
      call check(nd_get_scalar(b, ND_ACTIVE_POINTS, active) == ND_OK, 'ND_ACTIVE_POINTS')
      touched = max(touched, active)
    end do
    call check(touched > 0, 'the block came into contact')
    call check(calls > 0, 'the Fortran callback was called')
    call check(same, 'the plane as a Fortran callback steps bitwise as the built-in plane')
    call check(nd_problem_destroy(a) == ND_OK, 'destroy')
    call check(nd_problem_destroy(b) == ND_OK, 'destroy')

    call block(a, n)
    call check(nd_problem_add_contact_sphere(a, 1_c_int, centre, 10.0_c_double, 0_c_int) == ND_OK, &
               'nd_problem_add_contact_sphere')
    call check(nd_problem_move_obstacle(a, 1_c_int, 0_c_int, shift) == ND_OK, &
               'nd_problem_move_obstacle without a rotation (absent: NULL)')
    angle = 0.01_c_double
    rot = [cos(angle), -sin(angle), sin(angle), cos(angle)]
    call check(nd_problem_move_obstacle(a, 1_c_int, 0_c_int, shift, rot) == ND_OK, &
               'nd_problem_move_obstacle with a rotation')
    rot(2) = 1
    call check(nd_problem_move_obstacle(a, 1_c_int, 0_c_int, shift, rot) == ND_ERR_VALUE, &
               'a matrix that is no rotation is refused')
    call check(nd_problem_move_obstacle(a, 1_c_int, 1_c_int, shift) == ND_ERR_INDEX, 'a second obstacle is refused')
    touched = 0
    do k = 1, 60
      call check(nd_step(a) == ND_OK, 'a step on the circle')
      call check(nd_get_scalar(a, ND_ACTIVE_POINTS, active) == ND_OK, 'ND_ACTIVE_POINTS')
      touched = max(touched, active)
    end do
    call check(touched > 0, 'the block came onto the circle')
    call check(nd_get_scalar(a, ND_WORK_GEOMETRY, active) == ND_OK .and. abs(active) > 0 .and. abs(active) < huge(active), &
               'ND_WORK_GEOMETRY: the re-linearisations on the circle changed E_Theta')
    call check(nd_problem_destroy(a) == ND_OK, 'destroy')
  end subroutine test_obstacles

  ! ---- friction -------------------------------------------------------------
  subroutine test_friction()
    type(c_ptr) :: p
    integer(c_int64_t) :: n
    real(c_double) :: origin(2) = 0, up(2) = [0.0_c_double, 1.0_c_double], tilt(2), F(1) = [0.3_c_double]
    real(c_double) :: fn, fx, stick, slide, D, worst, bad(1) = [-1.0_c_double]
    integer :: k, sliding

    call block(p, n)
    tilt = [sin(0.5_c_double), -cos(0.5_c_double)]
    call check(nd_problem_set_body_force(p, tilt) == ND_OK, 'the tilted gravity')
    call check(nd_problem_set_contact_plane(p, 1_c_int, origin, up) == ND_OK, 'nd_problem_set_contact_plane')
    call check(nd_problem_set_friction(p, 1_c_int, ND_FRICTION_COULOMB, F) == ND_OK, 'nd_problem_set_friction')
    call check(nd_problem_set_friction(p, 1_c_int, ND_FRICTION_COULOMB, bad) == ND_ERR_VALUE, &
               'a negative coefficient is refused')
    call check(nd_problem_set_friction(p, 1_c_int, ND_FRICTION_TRESCA) == ND_ERR_NULL, &
               'Tresca without its threshold (params absent: NULL) is refused')
    call check(nd_problem_set_friction(p, 1_c_int, 9_c_int, F) == ND_ERR_KEY, 'an unknown law is refused')
    worst = 0
    sliding = 0
    do k = 1, 100
      call check(nd_step(p) == ND_OK, 'a step with friction')
      call check(nd_get_scalar(p, ND_STICKING_POINTS, stick) == ND_OK, 'ND_STICKING_POINTS')
      call check(nd_get_scalar(p, ND_SLIDING_POINTS, slide) == ND_OK, 'ND_SLIDING_POINTS')
      if (.not. (stick > 0) .and. slide > 0) then
        sliding = sliding + 1
        call check(nd_get_scalar(p, ND_CONTACT_FORCE_APPLIED, fn) == ND_OK, 'ND_CONTACT_FORCE_APPLIED')
        call check(nd_get_scalar(p, ND_CONTACT_FORCE_TANGENTIAL_X, fx) == ND_OK, 'ND_CONTACT_FORCE_TANGENTIAL_X')
        worst = max(worst, abs(fx + F(1) * fn) / (F(1) * fn))
      end if
    end do
    call check(sliding > 0, 'the block slides')
    call check(worst <= 1e-12_c_double, 'f_t = -F f_n while every pressed point slides')
    call check(nd_get_scalar(p, ND_DISSIPATION_FRICTION, D) == ND_OK .and. D > 0, 'friction dissipates')
    ! the plane moves along x and down (slip is relative): a step with friction on a moving plane is taken
    call check(nd_problem_set_contact_plane(p, 1_c_int, [0.02_c_double, -0.01_c_double], up) == ND_OK, &
               'the plane moves')
    call check(nd_step(p) == ND_OK, 'a step with friction on a moving plane')
    call check(nd_problem_destroy(p) == ND_OK, 'destroy')
  end subroutine test_friction

  ! ---- two bodies (the twin of tests/test_pairs.c's bars) ------------------
  ! bars [0, 1] and [1.01, 2.01], ten cells each, rho = E = 1, at +-0.1: no
  ! load and no support, so the total momentum stays 0 to round-off; with
  ! Theta = 1 the hybrid scheme's E_Theta - W - W_geometry never rises; the
  ! contact lasts about 2L/c = 2 and bar 1 leaves backwards
  subroutine test_pairs()
    type(c_ptr) :: m, p
    real(c_double) :: x(22), v(22), mom, e, previous, rise, active, t, first, last
    integer(c_int64_t) :: cells(40), a(1) = [10_c_int64_t], b(1) = [11_c_int64_t]
    integer :: i, k
    do i = 0, 10
      x(1 + i) = i / 10.0_c_double
      x(12 + i) = 1.01_c_double + i / 10.0_c_double
    end do
    do i = 0, 19
      cells(1 + 2 * i) = merge(i, i + 1, i < 10)
      cells(2 + 2 * i) = cells(1 + 2 * i) + 1
    end do
    call check(nd_mesh_create(1_c_int, 22_c_int64_t, x, 20_c_int64_t, cells, m) == ND_OK, 'two bars in one mesh')
    call check(nd_mesh_set_region(m, 1_c_int, 1_c_int64_t, a) == ND_OK, 'bar 1''s end')
    call check(nd_mesh_set_region(m, 2_c_int, 1_c_int64_t, b) == ND_OK, 'bar 2''s end')
    call check(nd_problem_create(m, 1_c_int, p) == ND_OK, 'nd_problem_create')
    call check(nd_mesh_destroy(m) == ND_OK, 'nd_mesh_destroy')
    call check(nd_problem_set_material(p, 1.0_c_double, 0.0_c_double, 1.0_c_double) == ND_OK, 'material')
    call check(nd_problem_set_contact_pair(p, 1_c_int, 1_c_int) == ND_OK, 'a region as its own master (replaced next)')
    call check(nd_problem_set_contact_pair(p, 1_c_int, 2_c_int) == ND_OK, 'nd_problem_set_contact_pair')
    call check(nd_problem_set_nitsche(p, 1.0_c_double, 0.0_c_double) == ND_OK, 'nd_problem_set_nitsche')
    call check(nd_problem_set_scheme(p, ND_SCHEME_HYBRID) == ND_OK, 'the hybrid scheme')
    call check(nd_problem_set_timestep(p, 0.01_c_double) == ND_OK, 'nd_problem_set_timestep')
    v = merge(0.1_c_double, -0.1_c_double, [(i <= 10, i = 0, 21)])
    call check(nd_problem_set_initial_state(p, 22_c_int64_t, v0=v) == ND_OK, 'the bars at +-0.1')
    call check(nd_get_scalar(p, ND_ENERGY_AUGMENTED, previous) == ND_OK, 'ND_ENERGY_AUGMENTED')
    rise = 0
    first = -1
    last = -1
    do k = 1, 300
      call check(nd_step(p) == ND_OK, 'a step of the bars')
      call check(nd_get_scalar(p, ND_MOMENTUM_X, mom) == ND_OK, 'ND_MOMENTUM_X')
      call check(abs(mom) <= 1.3e-12_c_double, 'the total momentum stays 0 to round-off')
      call check(nd_get_scalar(p, ND_ENERGY_AUGMENTED, e) == ND_OK, 'ND_ENERGY_AUGMENTED')
      call check(nd_get_scalar(p, ND_WORK_GEOMETRY, t) == ND_OK, 'ND_WORK_GEOMETRY')
      rise = max(rise, (e - t) - previous)
      previous = e - t
      call check(nd_get_scalar(p, ND_ACTIVE_POINTS, active) == ND_OK, 'ND_ACTIVE_POINTS')
      call check(nd_get_region_scalar(p, 1_c_int, ND_ACTIVE_POINTS, t) == ND_OK .and. abs(t - active) < 0.5_c_double, &
                 'nd_get_region_scalar: the one pair''s points are all the points')
      call check(nd_get_scalar(p, ND_TIME, t) == ND_OK, 'ND_TIME')
      if (active > 0) then
        if (first < 0) first = t
        last = t
      end if
    end do
    call check(rise <= 1e-12_c_double * 0.01_c_double, 'E_Theta - W_geometry never rises (Theta = 1, hybrid)')
    call check(abs(last - first - 2) <= 0.05_c_double, 'the contact lasts 2L/c to the discretization''s error')
    call check(nd_get_field(p, ND_FIELD_VELOCITY, 22_c_int64_t, v) == ND_OK, 'ND_FIELD_VELOCITY')
    call check(sum(v(1:11)) / 11 < -0.09_c_double, 'bar 1 leaves backwards at about -v0')
    call check(nd_problem_destroy(p) == ND_OK, 'destroy')
  end subroutine test_pairs

  ! ---- the bars as Q1 hexahedra (the twin of test_pairs.c's
  ! hex_bars_head_on_are_the_1d_bars) -------------------------------------
  ! the same bars, one cell across a square section of side 0.1, nu = 0 (the
  ! 1D motion per unit section), bar 2's end face a bilinear master face:
  ! the total momentum stays 0 to round-off, the ledger never rises, the
  ! contact lasts about 2L/c = 2 and bar 1 leaves backwards
  subroutine test_pair_hexahedra()
    integer, parameter :: corner(3, 8) = reshape([0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, &
                                                   0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1], [3, 8])
    type(c_ptr) :: m, p
    real(c_double) :: x(3, 88), v(3, 88), mom(3), e, Wg, previous, rise, E0, active, t, first, last, mean
    integer(c_int64_t) :: cells(8, 20)
    integer :: b, i, j, k, c, n
    do b = 0, 1
      do k = 0, 1
        do j = 0, 1
          do i = 0, 10
            x(:, 1 + 44 * b + (k * 2 + j) * 11 + i) = [1.01_c_double * b + i / 10.0_c_double, 0.1_c_double * j, &
                                                       0.1_c_double * k]
          end do
        end do
      end do
      do i = 0, 9
        do c = 1, 8
          cells(c, 1 + 10 * b + i) = 44 * b + (corner(3, c) * 2 + corner(2, c)) * 11 + i + corner(1, c)
        end do
      end do
    end do
    call check(nd_mesh_create_cells(3_c_int, ND_CELL_HEXAHEDRON, 88_c_int64_t, x, 20_c_int64_t, cells, m) == ND_OK, &
               'two bars of hexahedra in one mesh')
    call check(nd_mesh_mark_boundary_box(m, 1_c_int, [1 - 1e-9_c_double, -1.0_c_double, -1.0_c_double], &
                                         [1.005_c_double, 1.0_c_double, 1.0_c_double]) == ND_OK, 'bar 1''s end face')
    call check(nd_mesh_mark_boundary_box(m, 2_c_int, [1.005_c_double, -1.0_c_double, -1.0_c_double], &
                                         [1.01_c_double + 1e-9_c_double, 1.0_c_double, 1.0_c_double]) == ND_OK, &
               'bar 2''s end face')
    call check(nd_problem_create(m, 1_c_int, p) == ND_OK, 'nd_problem_create (Q1)')
    call check(nd_mesh_destroy(m) == ND_OK, 'nd_mesh_destroy')
    call check(nd_problem_set_material(p, 1.0_c_double, 0.0_c_double, 1.0_c_double) == ND_OK, 'material')
    call check(nd_problem_set_contact_pair(p, 1_c_int, 2_c_int) == ND_OK, 'a pair on hexahedra')
    call check(nd_problem_set_nitsche(p, 1.0_c_double, 0.0_c_double) == ND_OK, 'nd_problem_set_nitsche')
    call check(nd_problem_set_scheme(p, ND_SCHEME_HYBRID) == ND_OK, 'the hybrid scheme')
    call check(nd_problem_set_timestep(p, 0.01_c_double) == ND_OK, 'nd_problem_set_timestep')
    v = 0
    v(1, :) = merge(0.1_c_double, -0.1_c_double, x(1, :) < 1.005_c_double)
    call check(nd_problem_set_initial_state(p, 88_c_int64_t, v0=v) == ND_OK, 'the bars at +-0.1')
    call check(nd_get_scalar(p, ND_ENERGY_AUGMENTED, E0) == ND_OK, 'ND_ENERGY_AUGMENTED')
    previous = E0
    rise = 0
    first = -1
    last = -1
    do k = 1, 300
      call check(nd_step(p) == ND_OK, 'a step of the hexahedral bars')
      call check(nd_get_scalar(p, ND_MOMENTUM_X, mom(1)) == ND_OK, 'ND_MOMENTUM_X')
      call check(nd_get_scalar(p, ND_MOMENTUM_Y, mom(2)) == ND_OK, 'ND_MOMENTUM_Y')
      call check(nd_get_scalar(p, ND_MOMENTUM_Z, mom(3)) == ND_OK, 'ND_MOMENTUM_Z')
      ! (300 steps of forces on 264 rows that cancel in the sum, momenta 1e-3:
      ! 300 x 264 x 2.2e-16 x 1e-3, and a factor of ten)
      call check(maxval(abs(mom)) <= 1.7e-13_c_double, 'the total momentum stays 0 to round-off (hexahedra)')
      call check(nd_get_scalar(p, ND_ENERGY_AUGMENTED, e) == ND_OK, 'ND_ENERGY_AUGMENTED')
      call check(nd_get_scalar(p, ND_WORK_GEOMETRY, Wg) == ND_OK, 'ND_WORK_GEOMETRY')
      rise = max(rise, (e - Wg) - previous)
      previous = e - Wg
      call check(nd_get_scalar(p, ND_ACTIVE_POINTS, active) == ND_OK, 'ND_ACTIVE_POINTS')
      call check(nd_get_scalar(p, ND_TIME, t) == ND_OK, 'ND_TIME')
      if (active > 0) then
        if (first < 0) first = t
        last = t
      end if
    end do
    call check(rise <= 1e-12_c_double * E0, 'E_Theta - W_geometry never rises (hexahedra, Theta = 1, hybrid)')
    call check(abs(last - first - 2) <= 0.05_c_double, &
               'the contact lasts 2L/c to the discretization''s error (hexahedra)')
    call check(nd_get_field(p, ND_FIELD_VELOCITY, 88_c_int64_t, v) == ND_OK, 'ND_FIELD_VELOCITY')
    n = count(x(1, :) < 1.005_c_double)
    mean = sum(v(1, :), mask=x(1, :) < 1.005_c_double) / n
    call check(mean < -0.09_c_double, 'bar 1 leaves backwards at about -v0 (hexahedra)')
    call check(nd_problem_destroy(p) == ND_OK, 'destroy')
  end subroutine test_pair_hexahedra

  ! ---- friction between two bodies (the twin of test_pairs.c's, of
  ! test_pairs.py's thrown block) ----------------------------------------
  ! the block [0.5, 1.5] x [1.001, 1.5] (4 x 2 cells) thrown at (1, -0.5)
  ! onto [0, 2] x [0, 1] (8 x 4), no load and no support, Coulomb F = 0.3 on
  ! the slave region: the total momentum stays to round-off, with Theta = 1
  ! the hybrid ledger E_Theta + D_f - W_geometry never rises, and D_f > 0
  subroutine test_pair_friction()
    integer, parameter :: nx(2) = [8, 4], ny(2) = [4, 2]
    real(c_double), parameter :: lo(2, 2) = reshape([0.0_c_double, 0.0_c_double, 0.5_c_double, 1.001_c_double], [2, 2])
    real(c_double), parameter :: hi(2, 2) = reshape([2.0_c_double, 1.0_c_double, 1.5_c_double, 1.5_c_double], [2, 2])
    type(c_ptr) :: m, p
    real(c_double) :: x(2, 60), v(2, 60), F(1) = [0.3_c_double], P0(2), mom(2), e, D, Wg, previous, rise, E0
    integer(c_int64_t) :: cells(3, 80), nv, nc, base
    integer :: b, i, j, k
    nv = 0
    nc = 0
    do b = 1, 2
      base = nv
      do j = 0, ny(b)
        do i = 0, nx(b)
          nv = nv + 1
          x(:, nv) = lo(:, b) + (hi(:, b) - lo(:, b)) * [real(i, c_double) / nx(b), real(j, c_double) / ny(b)]
        end do
      end do
      do j = 0, ny(b) - 1
        do i = 0, nx(b) - 1
          cells(:, nc + 1) = base + [j * (nx(b) + 1) + i, j * (nx(b) + 1) + i + 1, (j + 1) * (nx(b) + 1) + i + 1]
          cells(:, nc + 2) = base + [j * (nx(b) + 1) + i, (j + 1) * (nx(b) + 1) + i + 1, (j + 1) * (nx(b) + 1) + i]
          nc = nc + 2
        end do
      end do
    end do
    call check(nd_mesh_create(2_c_int, nv, x, nc, cells, m) == ND_OK, 'two blocks in one mesh')
    call check(nd_mesh_mark_boundary_box(m, 1_c_int, [-1.0_c_double, 1.0005_c_double], [3.0_c_double, 1.002_c_double]) &
               == ND_OK, 'the upper block''s bottom')
    call check(nd_mesh_mark_boundary_box(m, 2_c_int, [-1.0_c_double, 0.9995_c_double], [3.0_c_double, 1.0005_c_double]) &
               == ND_OK, 'the lower block''s top')
    call check(nd_problem_create(m, 1_c_int, p) == ND_OK, 'nd_problem_create')
    call check(nd_mesh_destroy(m) == ND_OK, 'nd_mesh_destroy')
    call check(nd_problem_set_material(p, 100.0_c_double, 0.3_c_double, 1.0_c_double) == ND_OK, 'material')
    call check(nd_problem_set_contact_pair(p, 1_c_int, 2_c_int) == ND_OK, 'nd_problem_set_contact_pair')
    call check(nd_problem_set_friction(p, 1_c_int, ND_FRICTION_COULOMB, F) == ND_OK, 'friction on the pair''s slave')
    call check(nd_problem_set_nitsche(p, 1.0_c_double, 0.0_c_double) == ND_OK, 'nd_problem_set_nitsche')
    call check(nd_problem_set_scheme(p, ND_SCHEME_HYBRID) == ND_OK, 'the hybrid scheme')
    call check(nd_problem_set_timestep(p, 0.01_c_double) == ND_OK, 'nd_problem_set_timestep')
    v = 0
    do i = 1, int(nv)
      if (x(2, i) > 1) v(:, i) = [1.0_c_double, -0.5_c_double]
    end do
    call check(nd_problem_set_initial_state(p, nv, v0=v) == ND_OK, 'the upper block thrown')
    call check(nd_get_scalar(p, ND_MOMENTUM_X, P0(1)) == ND_OK, 'ND_MOMENTUM_X')
    call check(nd_get_scalar(p, ND_MOMENTUM_Y, P0(2)) == ND_OK, 'ND_MOMENTUM_Y')
    call check(nd_get_scalar(p, ND_ENERGY_AUGMENTED, E0) == ND_OK, 'ND_ENERGY_AUGMENTED')
    previous = E0
    rise = 0
    do k = 1, 100
      call check(nd_step(p) == ND_OK, 'a step with friction between the bodies')
      call check(nd_get_scalar(p, ND_MOMENTUM_X, mom(1)) == ND_OK, 'ND_MOMENTUM_X')
      call check(nd_get_scalar(p, ND_MOMENTUM_Y, mom(2)) == ND_OK, 'ND_MOMENTUM_Y')
      ! (momenta of order 0.5, forces of order 1 on ~100 rows over 100 steps)
      call check(maxval(abs(mom - P0)) <= 1e-12_c_double, 'the total momentum is conserved, friction included')
      call check(nd_get_scalar(p, ND_ENERGY_AUGMENTED, e) == ND_OK, 'ND_ENERGY_AUGMENTED')
      call check(nd_get_scalar(p, ND_DISSIPATION_FRICTION, D) == ND_OK, 'ND_DISSIPATION_FRICTION')
      call check(nd_get_scalar(p, ND_WORK_GEOMETRY, Wg) == ND_OK, 'ND_WORK_GEOMETRY')
      rise = max(rise, (e + D - Wg) - previous)
      previous = e + D - Wg
    end do
    ! (a block far from where it started: E's terms cancel ~1e4 times E)
    call check(rise <= 1e-12_c_double * E0, 'E_Theta + D_f - W_geometry never rises (Theta = 1, hybrid)')
    call check(D > 0, 'friction between the bodies dissipates')
    ! the one contact region's D_f is the problem's, to the bit (the same sums)
    call check(nd_get_region_scalar(p, 1_c_int, ND_DISSIPATION_FRICTION, e) == ND_OK .and. .not. abs(e - D) > 0, &
               'nd_get_region_scalar: the pair''s D_f is the whole')
    call check(nd_problem_destroy(p) == ND_OK, 'destroy')
  end subroutine test_pair_friction

  ! ---- one region as its own master (the twin of tests/test_self_contact.c's
  ! whole boundary) ------------------------------------------------------------
  ! [0, 2.1] x [0, 2] in cells of 0.1 (each split in two triangles) without
  ! the slot [1, 1.1] x [0.5, 2], its whole boundary region 3 paired with
  ! itself; the arms thrown towards each other at up to 0.5: no point active
  ! at the first step (none pairs through the body, past a corner or with its
  ! own facets), the slot closes and opens, the total momentum stays to
  ! round-off, and with Theta = 1 the hybrid ledger E_Theta - W_geometry never
  ! rises
  subroutine test_self_pair()
    integer, parameter :: nx = 21, ny = 20
    type(c_ptr) :: m, p
    real(c_double) :: x(2, (nx + 1) * (ny + 1)), v(2, (nx + 1) * (ny + 1)), P0(2), mom(2), e, Wg, previous, rise, E0
    real(c_double) :: active
    integer(c_int64_t) :: cells(3, 2 * nx * ny), nc, a
    integer :: i, j, k, touched, first_active
    logical :: parted
    do j = 0, ny
      do i = 0, nx
        x(:, 1 + j * (nx + 1) + i) = [0.1_c_double * i, 0.1_c_double * j]
      end do
    end do
    nc = 0
    do j = 0, ny - 1
      do i = 0, nx - 1
        if (i == 10 .and. j >= 5) cycle
        a = j * (nx + 1) + i
        cells(:, nc + 1) = [a, a + 1, a + nx + 2]
        cells(:, nc + 2) = [a, a + nx + 2, a + nx + 1]
        nc = nc + 2
      end do
    end do
    call check(nd_mesh_create(2_c_int, int((nx + 1) * (ny + 1), c_int64_t), x, nc, cells, m) == ND_OK, &
               'the U-shaped body')
    call check(nd_mesh_mark_boundary_box(m, 3_c_int, [-1.0_c_double, -1.0_c_double], [3.0_c_double, 3.0_c_double]) &
               == ND_OK, 'its whole boundary')
    call check(nd_problem_create(m, 1_c_int, p) == ND_OK, 'nd_problem_create')
    call check(nd_mesh_destroy(m) == ND_OK, 'nd_mesh_destroy')
    call check(nd_problem_set_material(p, 100.0_c_double, 0.3_c_double, 1.0_c_double) == ND_OK, 'material')
    call check(nd_problem_set_contact_pair(p, 3_c_int, 3_c_int) == ND_OK, 'a region as its own master')
    call check(nd_problem_set_nitsche(p, 1.0_c_double, 0.0_c_double) == ND_OK, 'nd_problem_set_nitsche')
    call check(nd_problem_set_scheme(p, ND_SCHEME_HYBRID) == ND_OK, 'the hybrid scheme')
    call check(nd_problem_set_timestep(p, 0.005_c_double) == ND_OK, 'nd_problem_set_timestep')
    v = 0
    do i = 1, size(x, 2)
      if (x(2, i) > 0.5_c_double) v(1, i) = merge(0.5_c_double, -0.5_c_double, x(1, i) < 1.05_c_double) &
                                             * (x(2, i) - 0.5_c_double) / 1.5_c_double
    end do
    call check(nd_problem_set_initial_state(p, int(size(x, 2), c_int64_t), v0=v) == ND_OK, 'the arms thrown')
    call check(nd_get_scalar(p, ND_MOMENTUM_X, P0(1)) == ND_OK, 'ND_MOMENTUM_X')
    call check(nd_get_scalar(p, ND_MOMENTUM_Y, P0(2)) == ND_OK, 'ND_MOMENTUM_Y')
    call check(nd_get_scalar(p, ND_ENERGY_AUGMENTED, E0) == ND_OK, 'ND_ENERGY_AUGMENTED')
    previous = E0
    rise = 0
    touched = 0
    first_active = -1
    parted = .false.
    do k = 1, 150
      call check(nd_step(p) == ND_OK, 'a step of the body touching itself')
      call check(nd_get_scalar(p, ND_MOMENTUM_X, mom(1)) == ND_OK, 'ND_MOMENTUM_X')
      call check(nd_get_scalar(p, ND_MOMENTUM_Y, mom(2)) == ND_OK, 'ND_MOMENTUM_Y')
      ! (each arm's momentum 0.375, forces of order 3 on ~100 rows; the C twin
      ! measures 6.8e-14)
      call check(maxval(abs(mom - P0)) <= 1e-11_c_double * 0.375_c_double, 'the total momentum is conserved')
      call check(nd_get_scalar(p, ND_ENERGY_AUGMENTED, e) == ND_OK, 'ND_ENERGY_AUGMENTED')
      call check(nd_get_scalar(p, ND_WORK_GEOMETRY, Wg) == ND_OK, 'ND_WORK_GEOMETRY')
      rise = max(rise, (e - Wg) - previous)
      previous = e - Wg
      call check(nd_get_scalar(p, ND_ACTIVE_POINTS, active) == ND_OK, 'ND_ACTIVE_POINTS')
      if (k == 1) first_active = int(active)
      if (active > 0.5_c_double) touched = touched + 1
      if (touched > 0 .and. active < 0.5_c_double) parted = .true.
    end do
    call check(first_active == 0, 'no point active at the first step (the arms start 0.1 apart)')
    call check(touched > 0 .and. parted, 'the slot closes and opens')
    ! (the C twin: 8.1e-17 of the energy's terms, of the order of E0)
    call check(rise <= 1e-12_c_double * E0, 'E_Theta - W_geometry never rises (Theta = 1, hybrid)')
    call check(nd_problem_destroy(p) == ND_OK, 'destroy')
  end subroutine test_self_pair

  ! ---- adaptive time steps (the twin of tests/test_adaptive.c) ------------
  ! A free bar flying at -1 towards the plane x = -0.1037: a step ends at the
  ! first touch t = 0.1037 exactly, and the hybrid Theta = 1 ledger E_Theta - W
  ! - W_obstacle never rises past round-off through the impact.
  subroutine test_adaptive()
    type(c_ptr) :: m, p
    real(c_double) :: lo(1) = [-0.5_c_double], hi(1) = [0.5_c_double], plane(1) = [-0.1037_c_double]
    real(c_double) :: up(1) = [1.0_c_double], v(21), t, landed, e, w, wo, previous, rise, rejected
    integer :: k
    call check(nd_mesh_create_interval(20_c_int64_t, 0.0_c_double, 1.0_c_double, m) == ND_OK, 'a bar')
    call check(nd_mesh_mark_boundary_box(m, 1_c_int, lo, hi) == ND_OK, 'its end x = 0')
    call check(nd_problem_create(m, 1_c_int, p) == ND_OK, 'nd_problem_create')
    call check(nd_mesh_destroy(m) == ND_OK, 'nd_mesh_destroy')
    call check(nd_problem_set_material(p, 1.0_c_double, 0.0_c_double, 1.0_c_double) == ND_OK, 'material')
    call check(nd_problem_set_contact_plane(p, 1_c_int, plane, up) == ND_OK, 'the plane')
    call check(nd_problem_set_nitsche(p, 1.0_c_double, 0.2_c_double) == ND_OK, 'Nitsche')
    call check(nd_problem_set_scheme(p, ND_SCHEME_HYBRID) == ND_OK, 'the hybrid scheme')
    v = -1
    call check(nd_problem_set_initial_state(p, 21_c_int64_t, v0=v) == ND_OK, 'flying at -1')
    call check(nd_problem_set_adaptive_timestep(p, -1.0_c_double, 1e-6_c_double, 0.04_c_double) == ND_ERR_VALUE, &
               'a negative tolerance is refused')
    call check(nd_problem_set_adaptive_timestep(p, 1e-3_c_double, 0.05_c_double, 0.04_c_double) == ND_ERR_TIMESTEP, &
               'tau_max below tau_min is refused')
    call check(nd_problem_set_adaptive_timestep(p, 1e-3_c_double, 1e-6_c_double, 0.04_c_double) == ND_OK, &
               'nd_problem_set_adaptive_timestep')
    call check(nd_get_scalar(p, ND_ENERGY_AUGMENTED, previous) == ND_OK, 'ND_ENERGY_AUGMENTED')
    landed = huge(1.0_c_double)
    rise = 0
    do k = 1, 200
      call check(nd_step(p) == ND_OK, 'an adaptive step')
      call check(nd_get_scalar(p, ND_TIME, t) == ND_OK, 'ND_TIME')
      landed = min(landed, abs(t - 0.1037_c_double))
      call check(nd_get_scalar(p, ND_ENERGY_AUGMENTED, e) == ND_OK, 'ND_ENERGY_AUGMENTED')
      call check(nd_get_scalar(p, ND_WORK, w) == ND_OK, 'ND_WORK')
      call check(nd_get_scalar(p, ND_WORK_OBSTACLE, wo) == ND_OK, 'ND_WORK_OBSTACLE')
      rise = max(rise, e - w - wo - previous)
      previous = e - w - wo
    end do
    call check(landed <= 1e-12_c_double, 'a step ended at the first touch')
    call check(rise <= 1e-13_c_double * 0.5_c_double, 'the ledger never rose past round-off')
    call check(nd_get_scalar(p, ND_STAT_STEPS_REJECTED, rejected) == ND_OK .and. rejected >= 1, &
               'the step past the touch was rejected')
    call check(nd_problem_destroy(p) == ND_OK, 'destroy')
  end subroutine test_adaptive

  ! ---- checkpoint and restart, the way a legacy code holds its data --------
  subroutine test_checkpoint()
    integer(c_int), parameter :: CLAMPED = 1, CONTACT = 2  ! (make_bar's regions: x = 1, x = 0)
    type(c_ptr) :: p
    integer(c_int64_t) :: n, nbytes
    integer(c_signed_char), allocatable :: buf(:)
    real(c_double), allocatable :: u_ref(:), u(:), v(:)
    integer(c_int64_t), allocatable :: nodes(:)
    integer(c_int64_t) :: n_owned, i
    real(c_double) :: t, w0, w1
    integer :: k
    integer(c_int) :: status

    call check(make_bar(20_c_int64_t, 2_c_int, 0.025_c_double, p, n) == ND_OK, 'the bar is set up')
    allocate(u_ref(n), u(n), v(n))
    status = ND_OK
    do k = 1, 30
      if (status == ND_OK) status = nd_step(p)
    end do
    call check(status == ND_OK, '30 steps')
    call check(nd_problem_get_state_size(p, nbytes) == ND_OK, 'nd_problem_get_state_size')
    allocate(buf(nbytes))
    call check(nd_problem_save_state(p, nbytes, buf) == ND_OK, 'nd_problem_save_state into integer(c_signed_char) buf(:)')
    call check(nd_problem_save_state_file_f(p, 'nd_fortran_state.ndck  ') == ND_OK, 'nd_problem_save_state_file_f')
    do k = 1, 20
      if (status == ND_OK) status = nd_step(p)
    end do
    if (status == ND_OK) status = nd_get_field(p, ND_FIELD_DISPLACEMENT, n, u_ref)
    call check(status == ND_OK, '20 more steps')
    ! without a communicator the process owns every node, in order
    call check(nd_problem_get_owned_node_count(p, n_owned) == ND_OK .and. n_owned == n, &
               'nd_problem_get_owned_node_count: every node')
    allocate(nodes(n_owned))
    call check(nd_get_field_owned(p, ND_FIELD_DISPLACEMENT, n_owned, u, nodes) == ND_OK, 'nd_get_field_owned')
    call check(maxval(abs(u - u_ref)) <= 0 .and. all(nodes == [(i, i = 0, n - 1)]), &
               'nd_get_field_owned: the whole field and the node numbers 0 .. n-1')
    call check(nd_get_field_owned(p, ND_FIELD_VELOCITY, n_owned, v) == ND_OK, 'nd_get_field_owned with nodes absent')
    call check(nd_get_field_owned(p, ND_FIELD_VELOCITY, n_owned + 1, v) == ND_ERR_SIZE, &
               'nd_get_field_owned with a wrong count: ND_ERR_SIZE')
    call check(nd_get_field_gathered(p, ND_FIELD_VELOCITY, 0_c_int, n, u) == ND_OK, 'nd_get_field_gathered')
    call check(nd_get_field(p, ND_FIELD_VELOCITY, n, v) == ND_OK .and. maxval(abs(u - v)) <= 0, &
               'nd_get_field_gathered on rank 0 without a communicator: nd_get_field')
    call check(nd_get_field_gathered(p, ND_FIELD_VELOCITY, 1_c_int, n, u) == ND_ERR_VALUE, &
               'nd_get_field_gathered on rank 1 of 1: ND_ERR_VALUE')
    call check(nd_get_field_gathered(p, ND_FIELD_VELOCITY, 0_c_int, n) == ND_ERR_NULL, &
               'nd_get_field_gathered on its root without out: ND_ERR_NULL')
    call check(nd_get_field(p, ND_FIELD_CONTACT_FORCE, n, v) == ND_OK, 'nd_get_field(ND_FIELD_CONTACT_FORCE)')
    call check(nd_get_scalar(p, ND_CONTACT_FORCE, t) == ND_OK, 'nd_get_scalar(ND_CONTACT_FORCE)')
    call check(abs(sum(v) - t) <= 1e-13_c_double * sum(abs(v)), 'the nodal contact forces sum to ND_CONTACT_FORCE')
    call check(nd_get_field(p, ND_FIELD_REACTION, n, v) == ND_OK, 'nd_get_field(ND_FIELD_REACTION)')
    call check(nd_get_scalar(p, ND_WORK_OBSTACLE, t) == ND_OK, 'nd_get_scalar(ND_WORK_OBSTACLE)')
    call check(abs(t) <= 0, 'a fixed plane does no work')
    call check(nd_problem_load_state(p, nbytes, buf) == ND_OK, 'nd_problem_load_state')
    call check(nd_get_scalar(p, ND_TIME, t) == ND_OK, 'nd_get_scalar(ND_TIME)')
    call check(abs(t - 30 * 0.025_c_double) < 1e-12_c_double, 'the time is back at step 30')
    do k = 1, 20
      if (status == ND_OK) status = nd_step(p)
    end do
    if (status == ND_OK) status = nd_get_field(p, ND_FIELD_DISPLACEMENT, n, u)
    call check(status == ND_OK, 'the same 20 steps again')
    call check(maxval(abs(u - u_ref)) <= 0, 'the resumed run is bitwise the uninterrupted one')
    call check(nd_problem_load_state_file_f(p, 'nd_fortran_state.ndck') == ND_OK, 'nd_problem_load_state_file_f')
    do k = 1, 20
      if (status == ND_OK) status = nd_step(p)
    end do
    if (status == ND_OK) status = nd_get_field(p, ND_FIELD_DISPLACEMENT, n, u)
    call check(status == ND_OK .and. maxval(abs(u - u_ref)) <= 0, 'the run resumed from the file is bitwise the same')
    call check(nd_problem_load_state_file_f(p, 'nd_fortran_no_such.ndck') == ND_ERR_IO, 'a missing file: ND_ERR_IO')
    open(newunit=k, file='nd_fortran_state.ndck')
    close(k, status='delete')
    buf(nbytes / 2) = not(buf(nbytes / 2))
    call check(nd_problem_load_state(p, nbytes, buf) == ND_ERR_FORMAT, 'a corrupted checkpoint: ND_ERR_FORMAT')
    status = nd_get_scalar(p, ND_WORK, w0)
    if (status == ND_OK) status = nd_get_field(p, ND_FIELD_VELOCITY, n, v)
    call check(status == ND_OK, 'the state is readable')
    u = 0.9_c_double * u
    call check(nd_problem_set_state(p, n, u) == ND_OK, 'nd_problem_set_state with v absent (NULL)')
    call check(nd_get_scalar(p, ND_WORK, w1) == ND_OK, 'nd_get_scalar(ND_WORK)')
    call check(abs(w1 - w0) <= 0, 'the work is kept')
    call check(nd_problem_set_guard(p, ND_GUARD_ENERGY, 3.0_c_double) == ND_OK, 'nd_problem_set_guard from Fortran')
    call check(nd_step(p) == ND_OK, 'a step after set_state')
    ! prescribed motion: the clamped end moved by 1e-4, then every clamped DOF back to 0
    call check(nd_problem_set_dirichlet_value(p, CLAMPED, [1e-4_c_double]) == ND_OK, 'nd_problem_set_dirichlet_value')
    call check(nd_problem_set_dirichlet_value(p, CONTACT, [1e-4_c_double]) == ND_ERR_REGION, &
               'nd_problem_set_dirichlet_value on a region that is not clamped: ND_ERR_REGION')
    call check(nd_step(p) == ND_OK, 'a step with the clamped end moved')
    call check(nd_get_field(p, ND_FIELD_DISPLACEMENT, n, u) == ND_OK .and. abs(u(21) - 1e-4_c_double) <= 0, &
               'the clamped end (vertex 20 of 20 cells, x = 1) is where it was moved')
    call check(nd_get_scalar(p, ND_WORK_PRESCRIBED, t) == ND_OK .and. abs(t) > 0, 'nd_get_scalar(ND_WORK_PRESCRIBED)')
    u = 0
    call check(nd_problem_set_dirichlet_nodal(p, n, u) == ND_OK, 'nd_problem_set_dirichlet_nodal')
    call check(nd_problem_set_dirichlet_nodal(p, n + 1, u) == ND_ERR_SIZE, &
               'nd_problem_set_dirichlet_nodal with a wrong count: ND_ERR_SIZE')
    call check(nd_step(p) == ND_OK, 'a step with the clamped end back at 0')
    call check(nd_problem_destroy(p) == ND_OK, 'nd_problem_destroy')
  end subroutine test_checkpoint

  ! ---- constants, version, optional arguments, general mesh ----------------
  subroutine test_constants_and_api()
    type(c_ptr) :: p, m
    integer(c_int64_t) :: n, nc, nv, nf
    integer(c_int) :: major, minor, patch, dim, i, bad, status, regions(2)
    real(c_double), allocatable :: x(:), u(:), buf(:)
    real(c_double) :: s, w(1), xc(1), lam(1)
    character(len=16) :: version

    call check(nd_version(major, minor, patch) == ND_OK, 'nd_version')
    call check(major == ND_VERSION_MAJOR .and. minor == ND_VERSION_MINOR .and. patch == ND_VERSION_PATCH, &
               'nd_version agrees with the ND_VERSION_* parameters')
    write (version, '(i0, ".", i0, ".", i0)') major, minor, patch
    call check(trim(version) == ND_VERSION_STRING, 'ND_VERSION_STRING is ' // trim(version))

    ! the BLAS thread setting: default 1, round trip, a negative one refused
    status = nd_get_blas_threads(i)
    call check(status == ND_OK .and. i == 1, 'nd_get_blas_threads: default 1')
    status = nd_set_blas_threads(3_c_int)
    call check(status == ND_OK, 'nd_set_blas_threads(3)')
    status = nd_get_blas_threads(i)
    call check(status == ND_OK .and. i == 3, 'nd_set_blas_threads(3) round-trips')
    status = nd_set_blas_threads(-1_c_int)
    call check(status == ND_ERR_VALUE, 'nd_set_blas_threads(-1) is refused')
    status = nd_get_blas_threads(i)
    call check(status == ND_OK .and. i == 3, 'the setting unchanged')
    call check(nd_set_blas_threads(1_c_int) == ND_OK, 'nd_set_blas_threads(1)')

    ! every generated status code is one the library knows
    bad = 0
    do i = 1, size(ND_STATUS_VALUES)
      if (nd_strerror_f(ND_STATUS_VALUES(i)) == 'unknown status code') bad = bad + 1
    end do
    call check(bad == 0 .and. size(ND_STATUS_VALUES) >= 25, 'nd_strerror knows every ND_STATUS_VALUES code')
    call check(nd_strerror_f(12345_c_int) == 'unknown status code', 'and no other')
    call check(nd_strerror_f(ND_OK) == 'success' .and. ND_OK == 0, 'ND_OK is 0, "success"')

    call check(make_bar(8_c_int64_t, 2_c_int, 0.05_c_double, p, n) == ND_OK, 'a P2 bar is set up')
    call check(n == 17, 'it has 17 FE nodes')
    allocate(x(n), u(n), buf(n))
    bad = 0
    do i = 1, size(ND_FIELD_VALUES)
      if (nd_get_field(p, ND_FIELD_VALUES(i), n, buf) /= ND_OK) bad = bad + 1
    end do
    call check(bad == 0, 'every ND_FIELD_VALUES field can be read')
    bad = 0
    do i = 1, size(ND_SCALAR_VALUES)
      if (nd_get_scalar(p, ND_SCALAR_VALUES(i), s) /= ND_OK) bad = bad + 1
    end do
    call check(bad == 0, 'every ND_SCALAR_VALUES key can be read')
    bad = 0
    do i = 1, size(ND_SCHEME_VALUES)
      if (nd_problem_set_scheme(p, ND_SCHEME_VALUES(i), [0.25_c_double, 0.5_c_double]) /= ND_OK) bad = bad + 1
    end do
    call check(bad == 0, 'every ND_SCHEME_VALUES scheme is accepted')
    call check(size(ND_SOLVER_VALUES) >= 3 .and. ND_SOLVER_VALUES(1) == ND_SOLVER_AUTO, 'ND_SOLVER_VALUES')
    call check(nd_problem_set_linear_solver(p, ND_SOLVER_DENSE) == ND_OK, 'ND_SOLVER_DENSE is accepted')

    ! absent optional arguments are NULL pointers
    call check(nd_problem_get_node_coordinates(p, n, x) == ND_OK, 'node coordinates')
    u = 0.5_c_double * (1 - x)
    call check(nd_problem_set_initial_state(p, n, u) == ND_OK, 'nd_problem_set_initial_state with v0 absent')
    status = nd_get_field(p, ND_FIELD_VELOCITY, n, buf)
    call check(status == ND_OK .and. maxval(abs(buf)) <= 0, 'an absent v0 means zero velocity')
    status = nd_get_field(p, ND_FIELD_DISPLACEMENT, n, buf)
    call check(status == ND_OK .and. maxval(abs(buf - u)) <= 1e-15_c_double, 'the displacement is u0')
    call check(nd_problem_set_initial_state(p, n) == ND_OK, 'nd_problem_set_initial_state with u0, v0 absent')
    status = nd_get_field(p, ND_FIELD_DISPLACEMENT, n, buf)
    call check(status == ND_OK .and. maxval(abs(buf)) <= 0, 'absent u0 means zero displacement')
    status = nd_problem_get_contact_point_count(p, nc)
    call check(status == ND_OK .and. nc == 1, 'one contact point')
    w = -1
    status = nd_problem_get_contact_points(p, nc, weights=w)
    call check(status == ND_OK .and. abs(w(1) - 1) <= 1e-15_c_double, 'contact points with coords absent: weight 1')
    xc = -1
    status = nd_problem_get_contact_points(p, nc, coords=xc)
    call check(status == ND_OK .and. abs(xc(1)) <= 0, 'contact points with weights absent: at x = 0')
    call check(nd_problem_set_initial_state(p, n, u) == ND_OK, 'u0 again')
    call check(nd_step(p) == ND_OK, 'a step')
    status = nd_get_contact_pressure(p, nc, lam)
    call check(status == ND_OK .and. lam(1) <= 0, 'the contact pressure is <= 0')
    status = nd_get_contact_pressure_applied(p, nc, lam)
    call check(status == ND_OK .and. lam(1) <= 0, 'the applied contact pressure is <= 0')
    call check(nd_problem_set_mass_redistribution(p, 1_c_int) == ND_OK, 'nd_problem_set_mass_redistribution')
    call check(nd_problem_destroy(p) == ND_OK, 'nd_problem_destroy')

    ! quadrilaterals and hexahedra: a square in one cell, a box of 2 x 1 x 1
    call check(nd_mesh_create_cells(2_c_int, ND_CELL_QUADRILATERAL, 4_c_int64_t, &
                                    [0.0_c_double, 0.0_c_double, 1.0_c_double, 0.0_c_double, &
                                     1.0_c_double, 1.0_c_double, 0.0_c_double, 1.0_c_double], 1_c_int64_t, &
                                    [0_c_int64_t, 1_c_int64_t, 2_c_int64_t, 3_c_int64_t], m) == ND_OK, &
               'nd_mesh_create_cells')
    status = nd_mesh_get_cell_count(m, nc)
    call check(status == ND_OK .and. nc == 1, 'one quadrilateral')
    call check(nd_mesh_destroy(m) == ND_OK, 'nd_mesh_destroy')
    ! a quadrilateral and two triangles in one mesh (nd_mesh_create_mixed)
    call check(nd_mesh_create_mixed(2_c_int, 6_c_int64_t, &
                                    [0.0_c_double, 0.0_c_double, 1.0_c_double, 0.0_c_double, 2.0_c_double, &
                                     0.0_c_double, 0.0_c_double, 1.0_c_double, 1.0_c_double, 1.0_c_double, &
                                     2.0_c_double, 1.0_c_double], 3_c_int64_t, &
                                    [ND_CELL_QUADRILATERAL, ND_CELL_SIMPLEX, ND_CELL_SIMPLEX], &
                                    [0_c_int64_t, 1_c_int64_t, 4_c_int64_t, 3_c_int64_t, 1_c_int64_t, 2_c_int64_t, &
                                     5_c_int64_t, 1_c_int64_t, 5_c_int64_t, 4_c_int64_t], m) == ND_OK, &
               'nd_mesh_create_mixed')
    status = nd_mesh_get_cell_count(m, nc)
    call check(status == ND_OK .and. nc == 3, 'three mixed cells')
    call check(nd_mesh_destroy(m) == ND_OK, 'nd_mesh_destroy')
    call check(nd_mesh_create_box_cells(2_c_int64_t, 1_c_int64_t, 1_c_int64_t, [0.0_c_double, 0.0_c_double, &
                                        0.0_c_double], [2.0_c_double, 1.0_c_double, 1.0_c_double], &
                                        ND_CELL_HEXAHEDRON, m) == ND_OK, 'nd_mesh_create_box_cells')
    status = nd_mesh_get_vertex_count(m, nv)
    call check(status == ND_OK .and. nv == 12, '12 vertices')
    status = nd_mesh_get_cell_count(m, nc)
    call check(status == ND_OK .and. nc == 2, '2 hexahedra')
    call check(nd_mesh_destroy(m) == ND_OK, 'nd_mesh_destroy')
    status = nd_mesh_create_rectangle_cells(2_c_int64_t, 2_c_int64_t, [0.0_c_double, 0.0_c_double], &
                                            [1.0_c_double, 1.0_c_double], ND_CELL_HEXAHEDRON, m)
    call check(status == ND_ERR_VALUE, 'a hexahedral rectangle is refused')

    ! a general mesh: three vertices, two cells, 0-based indices, int64
    call check(nd_mesh_create(1_c_int, 3_c_int64_t, [0.0_c_double, 0.5_c_double, 1.0_c_double], 2_c_int64_t, &
                              [0_c_int64_t, 1_c_int64_t, 1_c_int64_t, 2_c_int64_t], m) == ND_OK, 'nd_mesh_create')
    status = nd_mesh_get_dimension(m, dim)
    call check(status == ND_OK .and. dim == 1, 'dimension 1')
    status = nd_mesh_get_vertex_count(m, nv)
    call check(status == ND_OK .and. nv == 3, '3 vertices')
    status = nd_mesh_get_cell_count(m, nc)
    call check(status == ND_OK .and. nc == 2, '2 cells')
    call check(nd_mesh_set_region(m, 7_c_int, 1_c_int64_t, [0_c_int64_t]) == ND_OK, 'nd_mesh_set_region')
    call check(nd_mesh_mark_boundary_box(m, 8_c_int, [0.9_c_double], [1.1_c_double]) == ND_OK, &
               'nd_mesh_mark_boundary_box')
    status = nd_mesh_get_region_size(m, 7_c_int, nf)
    call check(status == ND_OK .and. nf == 1, 'region 7 has 1 facet')
    status = nd_mesh_get_region_size(m, 8_c_int, nf)
    call check(status == ND_OK .and. nf == 1, 'region 8 has 1 facet')
    call check(nd_mesh_set_region(m, 7_c_int, 1_c_int64_t, [5_c_int64_t]) < 0, 'a facet vertex out of range fails')
    ! cell regions and a material per region: the second cell in region 3
    call check(nd_mesh_set_cell_region(m, 3_c_int, 1_c_int64_t, [1_c_int64_t]) == ND_OK, 'nd_mesh_set_cell_region')
    status = nd_mesh_get_cell_regions(m, 2_c_int64_t, regions)
    call check(status == ND_OK .and. regions(1) == 0 .and. regions(2) == 3, 'cell regions 0 and 3')
    call check(nd_mesh_set_cell_region(m, 3_c_int, 1_c_int64_t, [2_c_int64_t]) == ND_ERR_INDEX, 'a cell out of range fails')
    call check(nd_problem_create(m, 1_c_int, p) == ND_OK, 'a problem of two cell regions')
    call check(nd_problem_set_material(p, 1.0_c_double, 0.0_c_double, 1.0_c_double) == ND_OK, 'the default material')
    call check(nd_problem_set_material_region(p, 3_c_int, 4.0_c_double, 0.0_c_double, 2.0_c_double) == ND_OK, &
               'nd_problem_set_material_region')
    call check(nd_problem_set_material_region(p, 4_c_int, 4.0_c_double, 0.0_c_double, 2.0_c_double) == ND_ERR_REGION, &
               'a cell region without cells fails')
    call check(nd_problem_destroy(p) == ND_OK, 'nd_problem_destroy (two materials)')
    call check(nd_mesh_destroy(m) == ND_OK, 'nd_mesh_destroy')
  end subroutine test_constants_and_api

end program test_api

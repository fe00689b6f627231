! A minimal check harness for the Fortran tests: check() counts and reports,
! finish() prints "N passed, M failed" and stops with status 1 on a failure.
module nd_fortran_checks
  implicit none
  private
  public :: check, finish
  integer, save :: n_passed = 0, n_failed = 0

contains

  subroutine check(ok, what)
    logical, intent(in) :: ok
    character(len=*), intent(in) :: what
    if (ok) then
      n_passed = n_passed + 1
      write (*, '(a)') 'ok    ' // what
    else
      n_failed = n_failed + 1
      write (*, '(a)') 'FAIL  ' // what
    end if
  end subroutine check

  subroutine finish()
    write (*, '(i0, a, i0, a)') n_passed, ' passed, ', n_failed, ' failed'
    if (n_failed > 0 .or. n_passed == 0) stop 1, quiet=.true.
  end subroutine finish

end module nd_fortran_checks

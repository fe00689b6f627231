"""What the Python tests of the binding share. They live in this folder,
which holds no nitschedyn.py, so ``import nitschedyn`` finds the package
CMake assembled in the build tree (PYTHONPATH), not the source module.

check(ok, what) counts a check and prints a failure (with ``verbose``, a
success too); raises(code, fn) says whether fn() raises nd.Error with that
code; finish() prints "N passed, M failed" and returns the exit status."""
import nitschedyn as nd

passed = failed = 0
verbose = False


def check(ok, what):
    global passed, failed
    if ok:
        passed += 1
        if verbose:
            print("ok    " + what)
    else:
        failed += 1
        print("FAIL  " + what)


def raises(code, fn):
    try:
        fn()
    except nd.Error as e:
        return e.code == code
    return False


def finish():
    print("%d passed, %d failed" % (passed, failed))
    return 1 if failed else 0

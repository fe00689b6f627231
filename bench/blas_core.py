"""Prints the kernel set OpenBLAS chose for this CPU (openblas_get_corename:
Haswell, Zen, SkylakeX, Cooperlake, ...), as the library's BLAS loads it;
OPENBLAS_CORETYPE in the environment overrides the choice. Exit 1 where the
BLAS is not OpenBLAS."""
import ctypes
import ctypes.util
import sys

blas = ctypes.CDLL(ctypes.util.find_library("blas") or "libblas.so.3")
try:
    corename = blas.openblas_get_corename
except AttributeError:
    sys.exit(1)
corename.restype = ctypes.c_char_p
print(corename().decode())

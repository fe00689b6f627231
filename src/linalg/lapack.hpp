// LAPACK drivers through LAPACKE's _work interface with workspace the
// library allocates (std::vector: a failed allocation is a std::bad_alloc,
// ND_ERR_NOMEM at the C boundary). LAPACKE's high-level calls malloc their
// work arrays (and, row-major, transposed copies), print "Not enough
// memory" to stderr when that fails and return LAPACK_WORK_MEMORY_ERROR or
// LAPACK_TRANSPOSE_MEMORY_ERROR: the library calls only the _work variants,
// column-major (which call the Fortran routine directly), or these.
#pragma once
#include <lapacke.h>

namespace nd::lapack {

// LAPACKE_dsyev(LAPACK_ROW_MAJOR, jobz, 'U', m, A, m, w), the same bits
// (the same transposition, the same optimal workspace): the eigenvalues of
// the symmetric row-major m x m matrix A (upper triangle read) ascending in
// w, with jobz 'V' the eigenvectors in A's columns. A non-finite entry of
// the triangle returns -5, as LAPACKE's check would; else LAPACK's info.
lapack_int dsyev_row_major(char jobz, lapack_int m, double *A, double *w);

// LAPACKE_dsygv(LAPACK_ROW_MAJOR, itype, 'N', 'U', n, A, n, B, n, w), the
// same bits: the eigenvalues of A x = lambda B x (itype 1) ascending in w;
// A and B (row-major, upper triangles read) destroyed. A non-finite entry
// returns -6 (A) or -8 (B), as LAPACKE's check would; else LAPACK's info.
lapack_int dsygv_values_row_major(lapack_int itype, lapack_int n, double *A, double *B, double *w);

// LAPACKE_dstev(LAPACK_COL_MAJOR, jobz, n, d, e, z, ldz), the same bits
// (a non-finite d or e returns -4 or -5, as LAPACKE's check would).
lapack_int dstev(char jobz, lapack_int n, double *d, double *e, double *z, lapack_int ldz);

}  // namespace nd::lapack

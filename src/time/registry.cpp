// ND_SCHEME_* id -> scheme. A new scheme is one file, one line here and its
// line in ND_SCHEME_LIST (include/nitschedyn.h).
#include <string>

#include "common/error.hpp"
#include "common/format.hpp"
#include "common/simd.hpp"
#include "nitschedyn.h"
#include "parallel/share.hpp"
#include "time/scheme.hpp"

namespace nd {
namespace {

struct Entry {
  int id;
  int n_params;
  std::unique_ptr<TimeScheme> (*make)(const std::vector<double> &);
};

const Entry kSchemes[] = {
    {ND_SCHEME_THETA, 1, make_theta_scheme},
    {ND_SCHEME_NEWMARK, 2, make_newmark_scheme},
    {ND_SCHEME_HYBRID, 0, make_hybrid_scheme},
    {ND_SCHEME_GENERALIZED_ALPHA, 1, make_generalized_alpha_scheme},
};

const Entry &entry(int id) {
  for (const Entry &e : kSchemes)
    if (e.id == id) return e;
  fail(ND_ERR_SCHEME, "scheme " + std::to_string(id) + " is not an ND_SCHEME_* value");
}

}  // namespace

int scheme_parameter_count(int id) { return entry(id).n_params; }

std::unique_ptr<TimeScheme> make_scheme(int id, const std::vector<double> &params) {
  const Entry &e = entry(id);
  if (static_cast<int>(params.size()) != e.n_params)
    fail(ND_ERR_SCHEME, "the scheme takes " + std::to_string(e.n_params) + " parameters, not " +
                            std::to_string(params.size()));
  return e.make(params);
}

void require_parameter(double x, double lo, double hi, const char *what) {
  if (!(x >= lo && x <= hi))
    fail(ND_ERR_SCHEME, std::string(what) + " is " + num(x) + "; it must lie in [" + num(lo) + ", " + num(hi) + "]");
}

}  // namespace nd

namespace nd {

void predict_taylor(double tau, const State &old, double w, std::vector<double> &U) {
  U.resize(old.U.size());
  // U + tau V + w tau^2 A, or + 0.0 without A
  const bool acc = w != 0 && old.A_valid;
  combine(U.size(), 1.0, old.U.data(), tau, old.V.data(), w * tau * tau, acc ? old.A.data() : nullptr, true, U.data());
}

void constant_acceleration_update(double tau, const State &old, State &next) {
  next.A = old.A;
  next.A_valid = true;
  next.V.resize(old.V.size());
  for (size_t i = 0; i < next.V.size(); ++i) next.V[i] = old.V[i] + tau * old.A[i];
}

// Entry k of a product is row rows[k]: all rows, or this rank's when the
// products stay on them (Products::rows); the other rows of the result are
// zero there, and no solve reads them.
void StepInputs::mass_combination(double a, double b, double e, std::vector<double> &r) const {
  const RowSet rows = own_rows(old.rows.get());
  const int64_t m = rows.size(old.n);
  if (old.rows) r.assign(static_cast<size_t>(old.n), 0.0);
  else r.resize(static_cast<size_t>(old.n));
  const bool with_A = e != 0 && old.MA.size() == old.MU.size();
  if (!old.rows) {  // every row, in order
    combine(r.size(), a, old.MU.data(), b, old.MV.data(), e, with_A ? old.MA.data() : nullptr, false, r.data());
  } else if (with_A) {
    for (int64_t k = 0; k < m; ++k) r[rows[k]] = a * old.MU[k] + b * old.MV[k] + e * old.MA[k];
  } else {
    for (int64_t k = 0; k < m; ++k) r[rows[k]] = a * old.MU[k] + b * old.MV[k];
  }
}

void StepInputs::k_theta_u(const std::vector<double> &U, std::vector<double> &out) const {
  if (old.rows) {
    const RowSet rows = own_rows(old.rows.get());
    out.assign(static_cast<size_t>(old.n), 0.0);
    for (int64_t k = 0, m = rows.size(old.n); k < m; ++k) out[rows[k]] = old.KU[k];
  } else {
    out = old.KU;
  }
  if (theta == 0) return;  // K_Theta = K
  // out -= theta sum_q w_q gamma_q (s_q.U) s_q. A run's points (a facet's:
  // 9 on a tetrahedron's facet with P1, 16 with P2) have one index list, without
  // repeats (a cell's DOFs): each entry is read once, the points' terms
  // subtracted from it in their order, and written once, without their
  // chain of stores and loads through memory. A run that shares s_q (P1):
  // s_q.U once, and the points' coefficients summed first (the sum's
  // rounding, not one point's after the other), one product an entry, not
  // one a point; else per point; no runs: each point alone.
  const std::vector<int64_t> &runs = contact.runs;
  const bool by_runs = runs.size() == contact.run_shares_s.size() + 1 && runs.back() == int64_t(contact.size());
  constexpr size_t kMaxRun = 32;  // (a longer run, if any: point by point)
  double f[kMaxRun];
  for (size_t r = 0, q = 0; q < contact.size(); ++r) {
    const size_t first = q, end = by_runs ? static_cast<size_t>(runs[r + 1]) : q + 1;
    const bool shared = by_runs && contact.run_shares_s[r], whole = end - first <= kMaxRun;
    double sU = 0;
    for (; q < end; ++q) {
      const SparseRow &s = contact.s[q];
      if (q == first || !shared) sU = s.dot(U.data());
      const double fq = theta * contact.w[q] * contact.gamma[q] * sU;
      if (whole) f[q - first] = fq;
      else
        for (size_t k = 0; k < s.idx.size(); ++k) out[s.idx[k]] -= fq * s.val[k];
    }
    if (!whole) continue;
    const std::vector<int64_t> &idx = contact.s[first].idx;  // (every point's of the run)
    if (shared) {  // one s for the run: its terms are (sum_p f_p) s, one product per entry
      double F = 0;
      for (size_t p = first; p < end; ++p) F += f[p - first];
      const double *sv = contact.s[first].val.data();
      for (size_t k = 0; k < idx.size(); ++k) out[idx[k]] -= F * sv[k];
      continue;
    }
    for (size_t k = 0; k < idx.size(); ++k) {
      double o = out[idx[k]];
      for (size_t p = first; p < end; ++p) o -= f[p - first] * contact.s[p].val[k];
      out[idx[k]] = o;
    }
  }
  // friction: a frictional point's tangential tractions' terms too (K_Theta has them)
  for (size_t q = 0; contact.m > 1 && q < contact.size(); ++q) {
    if (!contact.friction[q]) continue;
    for (int v = 1; v < contact.m; ++v) {
      const SparseRow &t = contact.s_row(q, v);
      const double fq = theta * contact.w[q] * contact.gamma[q] * t.dot(U.data());
      for (size_t k = 0; k < t.idx.size(); ++k) out[t.idx[k]] -= fq * t.val[k];
    }
  }
}

}  // namespace nd

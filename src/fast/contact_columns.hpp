// The columns Z_q = A^{-1} b_q of the contact points and G = P^T Z over a set
// of them, shared by the two fast Newton paths (fast/newton_condensed.hpp,
// fast/tangent_lowrank.cpp). A column is one solve with A's factor, made the
// first time its point is in a set; its bits do not depend on which others
// were made with it, so a run resumed from a checkpoint, whose cache starts
// empty, is bitwise the uninterrupted one. At most max_columns are held:
// past that the columns of the points off the current set are dropped (and
// made again, with the same bits, when needed). Where it costs no more
// memory than the column, a column keeps every point's dot with it
// (keeps_dots): p_q . Z_j is then a read.
//
// With split operators over several ranks (rows: Discretization::rows) a
// column is held only at the rank's own rows and at the DOFs of the contact
// points' rows: G and the points' P read only the latter, and a sum of
// columns is right on the rank's rows, from which complete() gathers the
// rest. A solve then gathers those few values, not the whole solution. With
// a distributed state the columns are held at its rows instead, and a sum
// of them is left there.
//
// On one process, when A's factor solves for the contact points' DOFs at a
// small part of a solve's cost (Factorization::backward_share_at, supernodal
// CHOLMOD), a column is held at those DOFs alone: G and P read nothing
// else, and the sum of columns that would make a whole vector is then a
// solve instead (sums_whole() false).
#pragma once
#include <cstdint>
#include <vector>

#include "assembly/contact.hpp"
#include "linalg/factorization.hpp"
#include "parallel/share.hpp"

namespace nd {

// Where the columns are held on one process: at the points' DOFs when the
// factor's backward solve for them is at most kColumnsAtPointsShare of a
// whole one (Auto), whole, or at the points' DOFs whenever the factor
// solves for them alone (white-box: tests compare the two).
enum class ColumnRows { Auto, Whole, Points };

// Holding the columns at the points paid where the points' DOFs needed at
// most about a third of L's entries and cost more above; 3D meshes need
// most of L: whole there (docs/performance.md, "Columns at the points").
constexpr double kColumnsAtPointsShare = 0.375;

// Whether a column keeps every point's dot with it (keeps_dots): where that
// takes at most the column's memory (Auto), always, or never (white-box:
// tests compare the two).
enum class ColumnDots { Auto, Keep, Evaluate };

class ContactColumns {
 public:
  // state_rows (with rows): a distributed state's rows (Integrator::held, a
  // superset of those above): the columns are held there, and a sum of them
  // is then all a step reads (complete() does nothing)
  // at: on one process, where the columns are held (ColumnRows)
  ContactColumns(const Factorization &A_factor, int64_t n, int64_t max_columns, const Share *rows = nullptr,
                 const std::vector<int64_t> *state_rows = nullptr, ColumnRows at = ColumnRows::Auto,
                 ColumnDots dots = ColumnDots::Auto)
      : A_factor_(A_factor), n_(n), max_columns_(max_columns), rows_(rows), state_rows_(state_rows),
        at_rows_(at), dots_(dots) {}
  bool holds_state() const { return state_rows_ != nullptr; }
  // is a sum of columns, after complete(), right at every unknown? (not
  // when they are held at the points' DOFs alone: then b_q's sum is solved)
  bool sums_whole() const { return at_.empty() || rows_ != nullptr; }
  // for one set of contact rows and one Theta; true when that changed (the cache is then empty)
  bool bind(const ContactPoints &cp, double theta);
  // Z_q for every q of S
  void require(const std::vector<int64_t> &S);
  int64_t computed() const { return computed_; }  // columns made (each one solve)
  // p_q . Z_j (after require of a set with j): from the column's dots where
  // they are kept, else evaluated (the same bits)
  double dot(size_t q, int64_t j) const;
  // Are every point's dots with a column kept with it (P^T Z_j, made with
  // the column: p_q . Z_j then costs a read)? Where they take at most the
  // column's own memory: the points no more than a column's held rows
  // (typical in 2D; not in 3D, where the points can outnumber the unknowns).
  bool keeps_dots() const { return keeps_dots_; }
  // p_i . Z_j for every point i (after require of a set with j), where kept
  // (else null)
  const double *kept_dots(int64_t j) const {
    const std::vector<double> &D = D_[static_cast<size_t>(j)];
    return D.empty() ? nullptr : D.data();
  }
  // x -= sum_j f[j] Z_{S[j]} at the held rows, four columns at a time,
  // (f0 z0 + f1 z1) + (f2 z2 + f3 z3): each held row of x read and written
  // once per four columns, not once per column
  void subtract_blocked(const std::vector<int64_t> &S, const double *f, double *x) const;
  // x right at the held rows: its other rows from their ranks (collective
  // when columns are held on own rows; else nothing to do)
  void complete(double *x) const;
  // x <- A^{-1} x at the held rows (its other rows stale until complete());
  // true when only those were gathered (columns held on own rows). An
  // iterative solve starts from the guess (if any).
  bool solve_held(double *x, const double *guess = nullptr) const;
  // G_ij = p_i . Z_j for i, j in S (after require(S)); the entries of pairs of
  // the last S are kept
  const std::vector<double> &G(const std::vector<int64_t> &S);

 private:
  const double *column(int64_t q) const { return Z_[static_cast<size_t>(q)].data(); }
  int64_t held() const { return at_.empty() ? n_ : static_cast<int64_t>(at_.size()); }
  // f(row) with row(i) the unknown of a column's i-th value (the identity when whole)
  template <class F>
  void with_rows(F &&f) const;

  const Factorization &A_factor_;
  int64_t n_, max_columns_, held_ = 0, computed_ = 0;
  const Share *rows_;
  const std::vector<int64_t> *state_rows_;
  ColumnRows at_rows_;
  ColumnDots dots_;
  const ContactPoints *cp_ = nullptr;
  double theta_ = 0;
  std::vector<int64_t> at_;     // the unknowns a column holds, ascending (empty: all n)
  std::vector<int64_t> place_;  // an unknown's index in at_ (-1: not held); empty with at_
  std::vector<std::vector<double>> Z_;   // per point; empty until needed
  std::vector<std::vector<double>> D_;   // per point with its column where keeps_dots_: p_i . Z_q for every i
  bool keeps_dots_ = false;
  std::vector<int64_t> G_S_, position_;  // the S that G_ was built for; a point's place in it (-1: none)
  std::vector<double> G_;
  std::vector<int64_t> G_S_next_;  // G()'s workspaces: the next S and G
  std::vector<double> G_next_;
};

}  // namespace nd

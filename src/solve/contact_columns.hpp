// The columns Z_q = A^{-1} b_q of the contact points and G = P^T Z over a set
// of them, shared by the two fast Newton paths (solve/newton_condensed.hpp,
// solve/tangent_lowrank.cpp). A column is one solve with A's factor, made the
// first time its point is in a set; its bits do not depend on which others
// were made with it, so a run resumed from a checkpoint, whose cache starts
// empty, is bitwise the uninterrupted one. At most max_columns are held:
// past that the columns of the points off the current set are dropped (and
// made again, with the same bits, when needed).
#pragma once
#include <cstdint>
#include <vector>

#include "assembly/contact.hpp"
#include "linalg/factorization.hpp"

namespace nd {

class ContactColumns {
 public:
  ContactColumns(const Factorization &A_factor, int64_t n, int64_t max_columns)
      : A_factor_(A_factor), n_(n), max_columns_(max_columns) {}
  // for one set of contact rows and one Theta; true when that changed (the cache is then empty)
  bool bind(const ContactPoints &cp, double theta);
  // Z_q for every q of S
  void require(const std::vector<int64_t> &S);
  const double *column(int64_t q) const { return Z_[static_cast<size_t>(q)].data(); }
  int64_t computed() const { return computed_; }  // columns made (each one solve)
  // G_ij = p_i . Z_j for i, j in S (after require(S)); the entries of pairs of
  // the last S are kept
  const std::vector<double> &G(const std::vector<int64_t> &S);

 private:
  const Factorization &A_factor_;
  int64_t n_, max_columns_, held_ = 0, computed_ = 0;
  const ContactPoints *cp_ = nullptr;
  double theta_ = 0;
  std::vector<std::vector<double>> Z_;   // per point; empty until needed
  std::vector<int64_t> G_S_, position_;  // the S that G_ was built for; a point's place in it (-1: none)
  std::vector<double> G_;
};

}  // namespace nd

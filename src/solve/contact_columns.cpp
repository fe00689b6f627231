#include "solve/contact_columns.hpp"

#include "solve/contact_law.hpp"

namespace nd {

bool ContactColumns::bind(const ContactPoints &cp, double theta) {
  if (&cp == cp_ && theta == theta_) return false;
  std::vector<std::vector<double>> Z(cp.size());  // allocate first, commit after
  std::vector<int64_t> position(cp.size(), -1);
  Z_.swap(Z);
  position_.swap(position);
  held_ = 0;
  G_S_.clear();
  G_.clear();
  cp_ = &cp;
  theta_ = theta;
  return true;
}

void ContactColumns::require(const std::vector<int64_t> &S) {
  int64_t missing = 0;
  for (int64_t q : S) missing += Z_[q].empty();
  if (missing == 0) return;
  if (held_ + missing > max_columns_) {  // drop the columns of the points off S
    std::vector<char> keep(Z_.size(), 0);
    for (int64_t q : S) keep[q] = 1;
    for (size_t q = 0; q < Z_.size(); ++q)
      if (!keep[q] && !Z_[q].empty()) std::vector<double>().swap(Z_[q]), --held_;
    G_S_.clear();  // G's entries of dropped points go with them
  }
  for (int64_t q : S) {
    if (!Z_[q].empty()) continue;
    std::vector<double> z(static_cast<size_t>(n_), 0.0);
    add_b(*cp_, theta_, static_cast<size_t>(q), 1.0, z.data());
    A_factor_.solve(z.data());
    Z_[q].swap(z);
    ++held_;
    ++computed_;
  }
}

const std::vector<double> &ContactColumns::G(const std::vector<int64_t> &S) {
  if (S == G_S_) return G_;
  const int64_t k = static_cast<int64_t>(S.size()), k_old = static_cast<int64_t>(G_S_.size());
  std::vector<double> Gn(static_cast<size_t>(k * k));  // what may throw, before anything changes
  std::vector<int64_t> S_copy(S);
  for (int64_t i = 0; i < k_old; ++i) position_[G_S_[i]] = i;
  for (int64_t j = 0; j < k; ++j) {
    const int64_t oj = position_[S[j]];
    const double *z = column(S[j]);
    for (int64_t i = 0; i < k; ++i) {
      const int64_t oi = position_[S[i]];
      Gn[i + j * k] = oi >= 0 && oj >= 0 ? G_[oi + oj * k_old] : p_dot(*cp_, static_cast<size_t>(S[i]), z);
    }
  }
  for (int64_t q : G_S_) position_[q] = -1;
  G_.swap(Gn);
  G_S_.swap(S_copy);
  return G_;
}

}  // namespace nd

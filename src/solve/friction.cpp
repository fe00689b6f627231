#include "solve/friction.hpp"

#include <algorithm>

#include "common/error.hpp"
#include "nitschedyn.h"

namespace nd {

namespace {
size_t tangential_count(const ContactPoints &cp) { return cp.size() * static_cast<size_t>(cp.m - 1); }
// p_t . U = ta . U - gamma ts . U of every tangential value: the passes'
// tangential values with no slip reference
std::vector<double> tangential_dots(const ContactPoints &cp, const std::vector<double> &U) {
  ContactLaw law;
  law.cp = &cp;
  std::vector<double> P(law.values());
  law.tangential_values(U.data(), P.data());
  return std::vector<double>(P.begin() + static_cast<std::ptrdiff_t>(cp.size()), P.end());
}
}  // namespace

std::vector<int> friction_regions(const ContactPoints &cp) {
  std::vector<int> r;
  for (size_t q = 0; q < cp.size(); ++q)
    if (r.empty() || r.back() != cp.region[q]) r.push_back(cp.region[q]);
  return r;
}

void start_slip(const Discretization &d, State &s) {
  if (d.contact.m <= 1) return s.slip.clear(), s.by_region.clear();
  s.slip = tangential_dots(d.contact, s.U);
  s.phi_t.assign(s.slip.size(), 0.0);
  s.by_region.assign(3 * friction_regions(d.contact).size(), 0.0);
}

void carry_slip(const Discretization &d, const State &from, State &to) {
  if (d.contact.m <= 1 || from.slip.size() != tangential_count(d.contact)) return start_slip(d, to);
  const std::vector<double> p_to = tangential_dots(d.contact, to.U), p_from = tangential_dots(d.contact, from.U);
  to.slip.resize(p_to.size());
  for (size_t j = 0; j < p_to.size(); ++j) to.slip[j] = from.slip[j] + (p_to[j] - p_from[j]);
}

std::vector<double> transport_slip(const ContactPoints &from, const ContactPoints &to, const std::vector<double> &U,
                                   const std::vector<double> &slip) {
  if (to.m <= 1) return {};
  if (from.m != to.m || from.size() != to.size() || slip.size() != tangential_count(from))
    fail(ND_ERR_INTERNAL, "slip references carried between rows of other points");
  const size_t mt = static_cast<size_t>(to.m - 1);
  const std::vector<double> p_from = tangential_dots(from, U), p_to = tangential_dots(to, U);
  std::vector<double> out = slip;
  for (size_t q = 0; q < to.size(); ++q) {
    const bool normal = std::equal(&to.normal[3 * q], &to.normal[3 * q] + 3, &from.normal[3 * q]);
    const bool paired = to.pairing.empty() ||
                        (from.pairing.size() == to.pairing.size() &&
                         std::equal(&to.pairing[kPairingValues * q], &to.pairing[kPairingValues * q] + kPairingValues,
                                    &from.pairing[kPairingValues * q]));
    if (normal && paired) continue;  // the same rows: the same references
    double v[3] = {0, 0, 0};  // the tangential value vector at U in the old rows
    for (size_t k = 0; k < mt; ++k) {
      const size_t j = q * mt + k;
      for (int c = 0; c < 3; ++c) v[c] += (p_from[j] - slip[j]) * from.tangent[3 * j + static_cast<size_t>(c)];
    }
    for (size_t k = 0; k < mt; ++k) {
      const size_t j = q * mt + k;
      double vt = 0;
      for (int c = 0; c < 3; ++c) vt += to.tangent[3 * j + static_cast<size_t>(c)] * v[c];
      out[j] = p_to[j] - vt;
    }
  }
  return out;
}

std::vector<double> obstacle_slip(const ContactPoints &cp, int dim, const std::vector<double> &before,
                                  const std::vector<ContactPlane> &now) {
  if (cp.m <= 1 || before.size() < 3 * now.size()) return {};
  std::vector<double> moved(3 * now.size());
  bool any = false;
  for (size_t i = 0; i < moved.size(); ++i) {
    moved[i] = now[i / 3].point[i % 3] - before[i];
    any = any || moved[i] != 0;
  }
  if (!any) return {};
  const size_t mt = static_cast<size_t>(cp.m - 1);
  std::vector<double> shift(cp.size() * mt, 0.0);
  for (size_t q = 0; q < cp.size(); ++q) {
    if (cp.plane[q] < 0) continue;  // (a curved region: friction refuses it, Problem::prepare)
    const double *dx = &moved[3 * static_cast<size_t>(cp.plane[q])];
    for (size_t k = 0; k < mt; ++k)
      for (int c = 0; c < dim; ++c) shift[q * mt + k] += cp.tangent[3 * (q * mt + k) + static_cast<size_t>(c)] * dx[c];
  }
  return shift;
}

void end_friction_step(const ContactLaw &law, const Discretization &d, const std::vector<double> &phi,
                       const std::vector<double> *shift, State &next, std::vector<double> &P) {
  const ContactPoints &cp = d.contact;
  const size_t nq = cp.size(), mt = static_cast<size_t>(cp.m - 1);
  if (P.size() != nq * (mt + 1) || next.slip.size() != nq * mt)
    fail(ND_ERR_INTERNAL, "the end of a step with friction without the points' tangential values");
  next.phi_t.assign(nq * mt, 0.0);
  next.sliding = next.sticking = 0;
  // each region's sum (empty: unknown, a checkpoint of version < 12 with
  // several regions), the region's points consecutive: friction_regions'
  // slots, met in order (the sizes checked as the slots are met, without a
  // list made at every step)
  const bool regions = !next.by_region.empty();
  size_t slot = 0;
  double D_region = 0;
  auto close_region = [&] {
    next.by_region[3 * slot] += D_region;
    D_region = 0;
    ++slot;
  };
  auto mismatch = [] { fail(ND_ERR_INTERNAL, "the state's friction values per region do not match the regions"); };
  if (regions && next.by_region.size() % 3 != 0) mismatch();
  if (regions)
    for (size_t r = 0; r < next.by_region.size() / 3; ++r) next.by_region[3 * r + 1] = next.by_region[3 * r + 2] = 0;
  const double c = tangential_weight(law.rule());
  double value[3], J[9], D = 0, W = 0;
  for (size_t q = 0; q < nq; ++q) {
    if (regions && q > 0 && cp.region[q] != cp.region[q - 1]) {
      close_region();
      if (3 * slot >= next.by_region.size()) mismatch();
    }
    law.law_m(q, P, value, J);
    if (value[0] != phi[q]) fail(ND_ERR_INTERNAL, "the normal value of a frictional point differs from the step's");
    bool slides = false;
    for (size_t k = 0; k < mt; ++k) {
      const size_t j = q * mt + k;
      const double Y = c * P[nq + j] + (c == 1 ? 0.0 : (1 - c) * (*law.Pn)[nq + j]);
      const double e = Y - value[k + 1];
      next.phi_t[j] = value[k + 1];
      next.slip[j] += e;
      const double Dq = cp.w[q] / cp.gamma[q] * value[k + 1] * e;
      D += Dq;
      D_region += Dq;
      if (shift) W -= cp.w[q] / cp.gamma[q] * value[k + 1] * (*shift)[j];
      slides = slides || e != 0;
    }
    if (value[0] > 0 && cp.friction[q]) {
      (slides ? next.sliding : next.sticking) += 1;
      if (regions) next.by_region[3 * slot + (slides ? 1 : 2)] += 1;
    }
  }
  if (regions && nq > 0) close_region();
  if (regions && 3 * slot != next.by_region.size()) mismatch();
  next.D_friction += D;
  if (shift) next.W_obstacle += W;
  ContactLaw at_state = law;
  at_state.gap_t = next.slip.data();
  at_state.tangential_values(next.U.data(), P.data());
}

std::array<double, 3> tangential_resultant(const Discretization &d, const State &s, int region) {
  std::array<double, 3> f{0, 0, 0};
  const ContactPoints &cp = d.contact;
  if (cp.m <= 1 || s.phi_t.size() != tangential_count(cp)) return f;
  for (size_t j = 0; j < s.phi_t.size(); ++j) {
    const size_t q = j / static_cast<size_t>(cp.m - 1);
    if (region >= 0 && cp.region[q] != region) continue;
    const double lw = -cp.w[q] * s.phi_t[j] / cp.gamma[q];
    for (int k = 0; k < 3; ++k) f[k] += lw * cp.tangent[3 * j + k];
  }
  return f;
}

}  // namespace nd

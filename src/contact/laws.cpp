// The registry of contact laws: an id (ND_FRICTION_*) to its law. A new
// law: its file and one line in kLaws.
#include <algorithm>
#include <string>

#include "common/error.hpp"
#include "contact/law.hpp"
#include "nitschedyn.h"

namespace nd {
namespace {

struct Entry {
  int id;
  int n_params;
  std::shared_ptr<const PointLaw> (*make)(const double *params, int dim);
};
std::shared_ptr<const PointLaw> frictionless(const double *, int) { return make_frictionless_law(); }
const Entry kLaws[] = {
    {kFrictionNone, 0, frictionless},
    {ND_FRICTION_TRESCA, 1, make_tresca_law},
    {ND_FRICTION_COULOMB, 1, make_coulomb_law},
};

// The laws of the points, one per region, as one law: point q's is laws_[at_[q]]
class ByPoint final : public PointLaw {
 public:
  ByPoint(const LawTraits &t, std::vector<std::shared_ptr<const PointLaw>> laws, std::vector<int> at)
      : PointLaw(t), laws_(std::move(laws)), at_(std::move(at)) {}
  const char *name() const override { return "by region"; }
  // (the scalar form: the normal part, [x]_+ for every registered law)
  void at(double x, double &value, double &slope) const override { laws_[0]->at(x, value, slope); }
  void over_step(const TimeRule &r, double P, double Pn, double &value, double &slope) const override {
    laws_[0]->over_step(r, P, Pn, value, slope);
  }
  void over_step_m(const TimeRule &r, size_t q, double gamma, int m, const double *P, const double *Pn,
                   double *value, double *J) const override {
    laws_[at_[q]]->over_step_m(r, q, gamma, m, P, Pn, value, J);
  }

 private:
  std::vector<std::shared_ptr<const PointLaw>> laws_;
  std::vector<int> at_;
};

}  // namespace

bool law_registered(int id, int *n_params) {
  for (const Entry &e : kLaws)
    if (e.id == id) {
      if (n_params) *n_params = e.n_params;
      return true;
    }
  return false;
}

std::shared_ptr<const PointLaw> make_law(int id, const double *params, int dim) {
  for (const Entry &e : kLaws)
    if (e.id == id) return e.make(params, dim);
  fail(ND_ERR_VALUE, "contact law " + std::to_string(id) + " is not one of the registered laws");
}

std::shared_ptr<const PointLaw> laws_by_point(
    const std::vector<int> &regions, const std::vector<std::pair<int, std::shared_ptr<const PointLaw>>> &by_region) {
  std::vector<std::shared_ptr<const PointLaw>> laws{make_frictionless_law()};
  for (const auto &[region, law] : by_region) laws.push_back(law);
  std::vector<int> at(regions.size(), 0);
  for (size_t q = 0; q < regions.size(); ++q)
    for (size_t k = 0; k < by_region.size(); ++k)
      if (by_region[k].first == regions[q]) at[q] = static_cast<int>(k + 1);
  // the traits the points' laws share (a region without points adds none)
  std::vector<char> used(laws.size(), 0);
  for (int k : at) used[k] = 1;
  LawTraits t = laws[0]->traits();
  bool first = true;
  for (size_t k = 0; k < laws.size(); ++k) {
    if (!used[k]) continue;
    const LawTraits &u = laws[k]->traits();
    if (first) t = u, first = false;
    t.m = std::max(t.m, u.m);
    t.rank_one = t.rank_one && u.rank_one;
    t.symmetric = t.symmetric && u.symmetric;
    t.zero_when_free = t.zero_when_free && u.zero_when_free;
    t.nondecreasing = t.nondecreasing && u.nondecreasing;
    t.positive_part = t.positive_part && u.positive_part;
    t.max_slope = std::max(t.max_slope, u.max_slope);
  }
  if (t.m == 1) return laws[0];  // (every point frictionless)
  return std::make_shared<ByPoint>(t, std::move(laws), std::move(at));
}

const PointLaw &frictionless_law() {
  // (made once, never destroyed: no destructor at exit for a pass to outlive)
  static const std::shared_ptr<const PointLaw> *const law =
      new std::shared_ptr<const PointLaw>(make_frictionless_law());
  return **law;
}

}  // namespace nd

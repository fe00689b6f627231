// nd_step and the state getters.
#include <string>

#include "capi/guard.hpp"
#include "capi/handles.hpp"
#include "problem/exports.hpp"

namespace {
int64_t contact_count(nd::Problem &pr) { return static_cast<int64_t>(pr.discretization().contact.size()); }
void need_count(int64_t n, int64_t expected, const char *what) {
  if (n != expected)
    nd::fail(ND_ERR_SIZE, std::string(what) + ": n is " + std::to_string(n) + ", expected " + std::to_string(expected));
}
}  // namespace

extern "C" {

ND_EXPORT int nd_problem_setup(nd_problem p) {
  return nd::guarded("nd_problem_setup", [&] {
    nd::problem_of(p).setup();
    return ND_OK;
  });
}

ND_EXPORT int nd_step(nd_problem p) {
  const int status = nd::guarded("nd_step", [&] {
    nd::problem_of(p).step();
    return ND_OK;
  });
  if (status != ND_OK || !p->monitor) return status;
  const int stop = p->monitor(p, p->userdata);
  // the monitor's own calls (a failing getter, say) set and cleared the
  // thread's message: nd_step returns with the error state of its outcome
  nd::clear_last_error();
  return stop != 0 ? ND_MONITOR_STOP : ND_OK;
}

ND_EXPORT int nd_get_field(nd_problem p, int field, int64_t n, double *out) {
  return nd::guarded("nd_get_field", [&] {
    nd::Problem &pr = nd::problem_of(p);
    pr.check_whole_read("nd_get_field", [&] {
      nd::need_member(ND_IS_MEMBER_(ND_FIELD_LIST, field), ND_ERR_KEY, "field", field, "ND_FIELD_*");
      need_count(n, pr.space().n_nodes, "nodes");
      nd::need(out, "out");
    });
    pr.field(field, out);
    return ND_OK;
  });
}

ND_EXPORT int nd_get_field_gathered(nd_problem p, int field, int root, int64_t n, double *out) {
  return nd::guarded("nd_get_field_gathered", [&] {
    nd::Problem &pr = nd::problem_of(p);
    pr.collective("nd_get_field_gathered");  // every rank in this call (or all fail)
    // refused on one rank, refused on all: no rank is left waiting in the gather
    pr.on_every_rank([&] {
      nd::need_member(ND_IS_MEMBER_(ND_FIELD_LIST, field), ND_ERR_KEY, "field", field, "ND_FIELD_*");
      if (root < 0 || root >= pr.rank_count())
        nd::fail(ND_ERR_VALUE, "root is " + std::to_string(root) + "; the communicator has " +
                                   std::to_string(pr.rank_count()) + " rank(s)");
      if (pr.rank() != root) return;
      need_count(n, pr.space().n_nodes, "nodes");
      nd::need(out, "out");
    });
    pr.gathered_field(field, root, out);
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_get_owned_node_count(nd_problem p, int64_t *n_owned) {
  return nd::guarded("nd_problem_get_owned_node_count", [&] {
    nd::Problem &pr = nd::problem_of(p);
    nd::need(n_owned, "n_owned");
    *n_owned = pr.owned_node_count();
    return ND_OK;
  });
}

ND_EXPORT int nd_get_field_owned(nd_problem p, int field, int64_t n_owned, double *values, int64_t *nodes) {
  return nd::guarded("nd_get_field_owned", [&] {
    nd::Problem &pr = nd::problem_of(p);
    nd::need_member(ND_IS_MEMBER_(ND_FIELD_LIST, field), ND_ERR_KEY, "field", field, "ND_FIELD_*");
    need_count(n_owned, pr.owned_node_count(), "owned nodes (see nd_problem_get_owned_node_count)");
    pr.owned_field(field, values, nodes);
    return ND_OK;
  });
}

ND_EXPORT int nd_get_scalar(nd_problem p, int key, double *out) {
  return nd::guarded("nd_get_scalar", [&] {
    nd::Problem &pr = nd::problem_of(p);
    nd::need_member(ND_IS_MEMBER_(ND_SCALAR_LIST, key), ND_ERR_KEY, "key", key, "ND_* scalar key");
    nd::need(out, "out");
    *out = nd::is_momentum_key(key) ? nd::momentum(pr, key) : pr.scalar(key);
    return ND_OK;
  });
}

ND_EXPORT int nd_get_region_scalar(nd_problem p, int region, int key, double *out) {
  return nd::guarded("nd_get_region_scalar", [&] {
    nd::Problem &pr = nd::problem_of(p);
    nd::need_member(ND_IS_MEMBER_(ND_SCALAR_LIST, key), ND_ERR_KEY, "key", key, "ND_* scalar key");
    nd::need(out, "out");
    *out = pr.region_scalar(region, key);
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_get_contact_point_count(nd_problem p, int64_t *n_points) {
  return nd::guarded("nd_problem_get_contact_point_count", [&] {
    nd::Problem &pr = nd::problem_of(p);
    nd::need(n_points, "n_points");
    *n_points = contact_count(pr);
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_get_contact_points(nd_problem p, int64_t n, double *coords, double *weights) {
  return nd::guarded("nd_problem_get_contact_points", [&] {
    nd::Problem &pr = nd::problem_of(p);
    need_count(n, contact_count(pr), "contact points");
    const nd::ContactPoints &cp = pr.discretization().contact;
    if (coords) std::copy(cp.x.begin(), cp.x.end(), coords);
    if (weights) std::copy(cp.w.begin(), cp.w.end(), weights);
    return ND_OK;
  });
}

namespace {
// one value per contact point, from a Problem getter
int copy_pressure(const char *name, nd_problem p, int64_t n, double *out,
                  std::vector<double> (nd::Problem::*get)()) {
  return nd::guarded(name, [&] {
    nd::Problem &pr = nd::problem_of(p);
    pr.check_whole_read(name, [&] {  // (a distributed state's points are gathered first: collective)
      need_count(n, contact_count(pr), "contact points");
      nd::need(out, "out");
    });
    const std::vector<double> lam = (pr.*get)();
    std::copy(lam.begin(), lam.end(), out);
    return ND_OK;
  });
}
}  // namespace

ND_EXPORT int nd_get_contact_pressure(nd_problem p, int64_t n, double *out) {
  return copy_pressure("nd_get_contact_pressure", p, n, out, &nd::Problem::contact_pressure);
}

ND_EXPORT int nd_get_contact_pressure_applied(nd_problem p, int64_t n, double *out) {
  return copy_pressure("nd_get_contact_pressure_applied", p, n, out, &nd::Problem::contact_pressure_applied);
}

ND_EXPORT int nd_problem_estimate_critical_timestep(nd_problem p, double *tau_c) {
  return nd::guarded("nd_problem_estimate_critical_timestep", [&] {
    nd::Problem &pr = nd::problem_of(p);
    nd::need(tau_c, "tau_c");
    *tau_c = pr.critical_timestep();
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_get_state_size(nd_problem p, int64_t *nbytes) {
  return nd::guarded("nd_problem_get_state_size", [&] {
    nd::Problem &pr = nd::problem_of(p);
    pr.check_whole_read("nd_problem_get_state_size", [&] { nd::need(nbytes, "nbytes"); });
    *nbytes = static_cast<int64_t>(pr.save_state().size());
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_save_state(nd_problem p, int64_t nbytes, void *buf) {
  return nd::guarded("nd_problem_save_state", [&] {
    nd::Problem &pr = nd::problem_of(p);
    pr.check_whole_read("nd_problem_save_state", [&] { nd::need(buf, "buf"); });
    const std::vector<unsigned char> bytes = pr.save_state();  // (nbytes checked after: no rank waits then)
    need_count(nbytes, static_cast<int64_t>(bytes.size()), "buf (nbytes, see nd_problem_get_state_size)");
    std::copy(bytes.begin(), bytes.end(), static_cast<unsigned char *>(buf));
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_load_state(nd_problem p, int64_t nbytes, const void *buf) {
  return nd::guarded("nd_problem_load_state", [&] {
    nd::Problem &pr = nd::problem_of(p);
    nd::need(buf, "buf");
    if (nbytes <= 0) nd::fail(ND_ERR_SIZE, "nbytes is " + std::to_string(nbytes) + "; it must be positive");
    pr.load_state(static_cast<const unsigned char *>(buf), nbytes);
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_save_state_file(nd_problem p, const char *path) {
  return nd::guarded("nd_problem_save_state_file", [&] {
    nd::Problem &pr = nd::problem_of(p);
    pr.check_whole_read("nd_problem_save_state_file", [&] { nd::need(path, "path"); });
    pr.save_state_file(path);
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_load_state_file(nd_problem p, const char *path) {
  return nd::guarded("nd_problem_load_state_file", [&] {
    nd::Problem &pr = nd::problem_of(p);
    nd::need(path, "path");
    pr.load_state_file(path);
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_set_state(nd_problem p, int64_t n, const double *u, const double *v) {
  return nd::guarded("nd_problem_set_state", [&] {
    nd::Problem &pr = nd::problem_of(p);
    pr.collective("nd_problem_set_state");  // every rank in this call (or all fail)
    pr.on_every_rank([&] {                  // refused on one rank, refused on all
      need_count(n, pr.space().n_nodes, "nodes");
      if (u) nd::need_finite(u, n * pr.space().dim, "u");
      if (v) nd::need_finite(v, n * pr.space().dim, "v");
    });
    pr.overwrite_state(u, v);
    return ND_OK;
  });
}

}  // extern "C"

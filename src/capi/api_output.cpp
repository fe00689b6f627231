// nd_problem_write_vtu, nd_write_pvd.
#include "capi/guard.hpp"
#include "capi/handles.hpp"
#include "io/vtu.hpp"

extern "C" {

ND_EXPORT int nd_problem_write_vtu(nd_problem p, const char *path) {
  return nd::guarded("nd_problem_write_vtu", [&] {
    nd::need(p, "problem");
    p->problem.check_whole_read("nd_problem_write_vtu", [&] { nd::need(path, "path"); });  // (it reads the whole state)
    nd::Problem &pb = p->problem;
    nd::VtuSnapshot snap;
    snap.space = &pb.space();
    const nd::CellMaterials materials = pb.materials();
    snap.material = &materials;
    snap.U.resize(static_cast<size_t>(pb.space().n_dofs()));
    snap.V.resize(snap.U.size());
    pb.field(ND_FIELD_DISPLACEMENT, snap.U.data());
    pb.field(ND_FIELD_VELOCITY, snap.V.data());
    snap.pressure = pb.contact_pressure();
    snap.contact = &pb.discretization().contact;  // after the calls above, which may build it
    snap.time = pb.scalar(ND_TIME);
    snap.step = static_cast<int64_t>(pb.scalar(ND_STEP_INDEX));
    nd::write_vtu(snap, path);
    return ND_OK;
  });
}

ND_EXPORT int nd_write_pvd(const char *path, int64_t n, const char *const *vtu_files, const double *times) {
  return nd::guarded("nd_write_pvd", [&] {
    nd::need(path, "path");
    if (n <= 0) nd::fail(ND_ERR_SIZE, "n must be positive");
    nd::need(vtu_files, "vtu_files");
    nd::need(times, "times");
    nd::write_pvd(path, n, vtu_files, times);
    return ND_OK;
  });
}

}  // extern "C"

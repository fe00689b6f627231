// A problem: its definition (set through the C API), the operators derived
// from it (built on demand, rebuilt when the definition changes), and the
// state at t^n. A step builds the next state aside and commits it only when
// it succeeded, so a failed step leaves the state exactly as it was.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "assembly/bulk.hpp"
#include "assembly/contact.hpp"
#include "linalg/factorization.hpp"
#include "solve/newton.hpp"
#include "time/scheme.hpp"

namespace nd {

struct Operators {
  Operators(DofMap d, bool lump) : dofs(std::move(d)), lumped(lump) {}
  DofMap dofs;
  Csr M;        // the scheme's mass: consistent, or lumped (diagonal) on the same pattern
  bool lumped;
  std::vector<double> M_lumped;  // the lumped diagonal (empty when consistent)
  Csr K, K_theta;             // K and K_Theta = K - Theta sum_q w_q gamma_q s_q^T s_q
  std::vector<double> F_const;  // empty when there is no body force or traction
  ContactPoints contact;
  std::unique_ptr<Factorization> M_factor;  // consistent mass, factored on first use
  void mass_solve(double *x, int solver);
};

struct StepOperator {
  Csr A;  // c M + K_Theta
  Csr T;  // Newton tangent workspace, same pattern
  StepCoefficients coef;
  std::unique_ptr<Factorization> A_factor, T_factor;
};

bool is_scalar_key(int key);

class Problem {
 public:
  Problem(std::shared_ptr<const Mesh> mesh, int degree);

  // ---- definition (each setter invalidates what depends on it)
  void set_material(const Material &m);
  void add_dirichlet(int region);
  void set_body_force(const double *f);
  void add_neumann(int region, const double *g);
  void add_contact_plane(int region, const double *point, const double *normal);
  void set_nitsche(double theta, double gamma0);
  void set_scheme(const SchemeSpec &s);
  void set_nodal_forces(const double *f);  // n_dofs values
  void set_newton(const NewtonOptions &o) { newton_ = o; }
  void set_mass_lumping(bool lumped);
  void set_linear_solver(int solver);
  void set_timestep(double tau);
  void set_initial_state(const double *u0, const double *v0);  // n_dofs each, or nullptr

  // ---- queries
  const Space &space() const { return space_; }
  const State &state();
  const Operators &operators() { return build_operators(); }
  double theta() const { return theta_; }
  // the step operator once built (benchmarks time its solve: the floor of a step)
  const StepOperator *step_operator() const { return step_op_.get(); }
  void field(int which, double *full);  // n_dofs values
  double scalar(int key);
  std::vector<double> contact_pressure();  // lambda_q

  // Operators, factorization of the step operator, initial acceleration:
  // what the first step needs; done once until the definition changes.
  void setup();
  // Advances one step; throws nd::Error (state untouched) on failure.
  void step();

 private:
  Operators &build_operators();
  StepOperator &build_step_operator();
  void require_regions(int region, const char *what) const;
  std::vector<double> current_load();
  void equilibrium_acceleration(State &s);
  std::string missing() const;
  void definition_changed(bool operators);
  // The Newton tangent is symmetric (and positive definite with c M + K_Theta) iff Theta = 1.
  Structure tangent_structure() const {
    return theta_ == 1 ? Structure::SymmetricPositiveDefinite : Structure::General;
  }

  std::shared_ptr<const Mesh> mesh_;
  Space space_;
  bool has_material_ = false, has_nitsche_ = false, has_scheme_ = false, has_tau_ = false;
  Material material_;
  std::vector<int> dirichlet_;
  bool has_body_force_ = false;
  double body_force_[3] = {0, 0, 0};
  std::vector<NeumannLoad> neumann_;
  std::vector<ContactPlane> planes_;
  double theta_ = 1, gamma0_ = 0;
  SchemeSpec scheme_;
  double tau_ = 0;
  NewtonOptions newton_;
  bool lumped_ = false;
  int solver_ = 0;
  std::vector<double> nodal_, u0_, v0_;  // n_dofs each, or empty

  std::unique_ptr<Operators> ops_;
  std::unique_ptr<StepOperator> step_op_;
  State state_;
  bool state_ready_ = false;
};

}  // namespace nd

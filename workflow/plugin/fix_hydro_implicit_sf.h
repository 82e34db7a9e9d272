/* fix <ID> all hydro/implicit/sf [tol <t>] [maxiter <n>]
   Time integration with the hydrodynamic forces (Stokes drag + lubricate/sf) taken
   implicitly.  See fix_hydro_implicit_sf.cpp and README.md in this folder. */

#ifndef SUSPENSION_FABRIC_FIX_HYDRO_IMPLICIT_SF_H
#define SUSPENSION_FABRIC_FIX_HYDRO_IMPLICIT_SF_H

#include "fix.h"
#include "lmptype.h"

#include "imposed_flow.h"
#include "lubrication.h"

#include <vector>

namespace LAMMPS_NS {

class PairLubricateSF;

class FixHydroImplicitSF : public Fix {
 public:
  FixHydroImplicitSF(class LAMMPS *, int, char **);

  int setmask() override;
  void init() override;
  void setup(int) override;
  void initial_integrate(int) override;
  void final_integrate() override;
  void reset_dt() override;
  double compute_vector(int) override;

 private:
  struct LubricatedPair {
    int i, j;           // local indices; j is the owner of a ghost partner
    bool add_to_j;      // newton on, or j local: this pair also acts on j
    double del[3];      // x_i - x_j (image of j next to i)
    SuspensionFabric::PairResistance R;
  };

  double tolerance;    // largest velocity error |D^-1 r| allowed, in gammadot d
  int max_iterations;
  double dtv;
  PairLubricateSF *lubrication;

  std::vector<LubricatedPair> pairs;
  std::vector<double> block_factor;     // 36 per atom: the 6x6 diagonal block, then its Cholesky factor
  std::vector<double> block_inverse;    // 36 per atom: inverse of the 6x6 diagonal block
  std::vector<double> rhs, solution, residual, precond, direction, product;

  std::vector<tagint> preconditioner_tags;    // atom order the preconditioner was built for
  long long steps, total_iterations;
  int last_iterations;
  double last_error;

  void collect_pairs();
  void apply_operator(const std::vector<double> &in, std::vector<double> &out) const;
  void build_preconditioner();
  double apply_preconditioner(const std::vector<double> &r, std::vector<double> &z, double &largest) const;
  void tally_virial(const double E[3][3]);
  static void strain_rate(const SuspensionFabric::ImposedFlow &flow, double E[3][3]);
  void relative_velocities(const SuspensionFabric::ImposedFlow &flow);
};

}    // namespace LAMMPS_NS

#endif

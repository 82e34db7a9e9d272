/* fix <ID> all hydro/implicit/sf [tol <t>] [maxiter <n>] [precond dilu|jacobi] [local <f>] [verify yes|no]
   [contacts <kn> <kt> <mu>] [solve lagged|newton]
   Time integration with the hydrodynamic forces (Stokes drag + lubricate/sf) taken
   implicitly, and with `contacts` also the frictional contact springs.  See
   fix_hydro_implicit_sf.cpp and README.md in this folder. */

#ifndef SUSPENSION_FABRIC_FIX_HYDRO_IMPLICIT_SF_H
#define SUSPENSION_FABRIC_FIX_HYDRO_IMPLICIT_SF_H

#include "fix.h"
#include "lmptype.h"

#include "contact.h"
#include "imposed_flow.h"
#include "lubrication.h"

#include <unordered_map>
#include <vector>

namespace LAMMPS_NS {

class PairLubricateSF;

/* The fix's global vector, as an input script reads it: f_ID[i], i counted from 1 as LAMMPS does.
   Three-component and six-component entries start at the index given (virials and stresslets in
   LAMMPS's order xx yy zz xy xz yz, summed over pairs: divide by the volume for a pressure).
   forces_sf.lmp reads these; tests/simulation/test_fix_vector.py checks every index it uses against this list. */
namespace HydroVector {
  enum : int {
    LAST_ITERATIONS = 1,       // CG iterations of the last step
    MEAN_ITERATIONS = 2,       // mean CG iterations per step of the run
    LAST_ERROR = 3,            // largest velocity error of the last solve
    CONTACT_VIRIAL = 4,        // 6: sum dx_a F_b of the contact forces
    CONTACT_TORQUE = 10,       // 3: summed contact torque
    LUBRICATION_VIRIAL = 13,   // 6: symmetrised lubrication force dipoles
    MEAN_PASSES = 19,          // mean contact-state passes per step
    CONTACTS = 20,             // contacts of the last step
    SLIDING_CONTACTS = 21,     // of which sliding
    MEAN_RELEASED = 22,        // mean released contacts per step
    DILU_FALLBACKS = 23,       // dilu factorisations that fell back to Jacobi
    STRESSLET_VIRIAL = 24,     // 6: pair lubrication stresslets
    MEAN_LOCAL_WORK = 30,      // mean local-solve work per step, in sweeps over all atoms
    FRICTIONAL_CONTACTS = 31,  // contacts of the last step above the critical load (all with none)
    CRITICAL_LOAD = 32,        // the critical load of the last step (critical_load_stress: it follows the stress)
    SHEAR_STRESS = 33,         // critical_load_stress: the shear stress along the flow the critical load follows
    FLOORED_STEPS = 34,        // critical_load_stress: steps whose stress was below the solvent's (load at its floor)
    SIZE = 34
  };
}    // namespace HydroVector

class FixHydroImplicitSF : public Fix {
 public:
  FixHydroImplicitSF(class LAMMPS *, int, char **);
  ~FixHydroImplicitSF() override;

  int setmask() override;
  void init() override;
  void setup(int) override;
  void initial_integrate(int) override;
  void final_integrate() override;
  void reset_dt() override;
  double compute_vector(int) override;
  void write_restart(FILE *) override;
  void restart(char *) override;
  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;
  int pack_reverse_comm(int, int, double *) override;
  void unpack_reverse_comm(int, int *, double *) override;
  void grow_arrays(int) override;
  void copy_arrays(int, int, int) override;
  int pack_exchange(int, double *) override;
  int unpack_exchange(int, double *) override;
  double memory_usage() override;

 private:
  struct LubricatedPair {
    int i, j;           // i local; j local (the owner of a ghost image on this rank) or a ghost owned by another rank
    bool add_to_j;      // newton on, or j local: this pair also acts on j
    double del[3];      // x_i - x_j (image of j next to i)
    SuspensionFabric::PairResistance R;
  };

  struct Spring {
    double xi[3];
  };

  /* A lubricated pair as the operator sees it within one solve: the lubrication resistances
     plus those of the pair's implicit contact springs (a sticking spring c = kt dt adds
     YA += c, YBi -= c l_i, YBj -= c l_j, YCi += c l_i^2, YCj += c l_j^2, YCx += c l_i l_j, a
     pressed one X += kn dt; contact.h, lubrication.h), so the product takes one pass over the
     pairs.  Sliding contacts (their tangent depends on the trial spring) stay separate. */
  struct OperatorPair {
    int i, j;
    bool add_to_j;
    double n[3];
    double X, YA, YBi, YBj, YCi, YCj, YCx;
  };

  double tolerance;    // largest velocity error |D^-1 r| allowed, in gammadot d
  // keyword guess: the solve's first iterate, the old velocities (0) or their extrapolation over
  // the last 1 or 2 steps (1: linear, 2: quadratic)
  int guess_order;
  // per atom (moving with it): the old relative velocities of the last two steps, then how many
  // of them are this atom's (0-2)
  double **velocity_history;
  double local_fraction;    // keyword local: solve locally once fewer atoms than this fraction are above tol
  bool verify;              // keyword verify: stop if the recomputed residual of a solve misses tol
  int max_iterations;
  bool own_contacts;   // keyword contacts: the fix computes the contacts, springs implicit
  bool newton_contacts;    // solve newton: the contact law re-linearised about each pass's solution
  double kn, kt, mu;
  double critical_load;    // keyword critical_load: F_CL, contacts with kn o <= F_CL are frictionless
  // keyword critical_load_stress S a eta_b: F_CL follows the shear stress sigma of the step before,
  // F_CL = a^2 sigma / S, so that sigma / sigma_0 = S (sigma_0 = F_CL / a^2) at every step;
  // eta_b gammadot is the stress the particles' virial leaves out (solvent and Einstein parts)
  double controlled_stress, load_radius, background_viscosity;
  double shear_stress;    // the shear stress along the flow of the last tallied step (critical_load_stress)
  long floored_steps;     // steps whose stress was below eta_b gammadot (critical_load_stress)
  double dtv;
  PairLubricateSF *lubrication;

  std::vector<LubricatedPair> pairs;
  std::vector<SuspensionFabric::Contact> contacts;
  std::vector<OperatorPair> operator_pairs;    // per pair, rebuilt before each solve
  std::vector<int> separate_contacts;          // contacts in the operator not folded into their pair
  std::vector<double> self_resistances;        // per local atom, rebuilt with them: translation, rotation
  // tangential spring of each contact, by (smaller tag, larger tag): displacement of the atom
  // with the smaller tag relative to the other.  Each rank keeps the springs of the pairs it
  // lists; after a neighbour-list build, when a pair may move to another rank, all ranks
  // gather all springs and each keeps, after the step, those of its own pairs.
  std::unordered_map<unsigned long long, Spring> springs, next_springs;
  double contact_virial[6];       // sum (x_i - x_j)_a F_b, LAMMPS order xx yy zz xy xz yz
  double contact_torque[3];       // summed contact torques: -sum (x_i - x_j) x F
  double lubrication_virial[6];   // symmetrised lubrication virial
  double stresslet_virial[6];     // -sum of the pair stresslets (same sign as a virial)
  std::vector<double> block_factor;     // 36 per atom: the 6x6 diagonal block, then its Cholesky factor
  std::vector<double> block_inverse;    // 36 per atom: inverse of the 6x6 diagonal block
  std::vector<double> rhs, old_velocity, solution, residual, precond, direction, product;

  // preconditioner `dilu`: the off-diagonal 6x6 blocks A_lo,hi (lo < hi) of the operator, one
  // per lubricated pair with its sticking spring.  Each has the form
  //   [[-(alpha n n + beta P), gamma N], [delta N, epsilon P]],  P = I - n n, N w = n x w
  struct Coupling {
    int lo, hi;
    double n[3];
    double alpha, beta, gamma, delta, epsilon;
  };
  bool use_dilu;
  std::vector<Coupling> couplings;
  std::vector<int> pair_coupling;    // coupling of each lubricated pair (-1: none)
  // the couplings sorted by hi (forward sweep) and by lo (backward sweep and factorisation)
  std::vector<Coupling> by_hi, by_lo;
  std::vector<int> by_hi_start, by_lo_start;
  long long dilu_fallbacks;
  std::vector<tagint> preconditioner_tags;    // atom order the preconditioner was built for
  long long steps, total_iterations, total_passes, total_released;
  double total_local_work;
  // local solves: the atoms still above tol and their pair neighbours (the patch), the pairs and
  // contacts acting on them, and the atoms those reach
  std::vector<char> in_patch;
  std::vector<int> patch_atoms, patch_pairs, patch_contacts, reached_atoms;
  std::vector<double> local_step, local_product, local_residual, local_precond, local_direction;
  int last_iterations;
  double last_error;
  int sliding_contacts;
  int frictional_contacts;
  double reported[HydroVector::SIZE];    // the global vector of the last step, summed over the ranks

  // more than one MPI rank: partners owned by other ranks enter as ghosts, whose vector entries
  // are exchanged through the fix's forward and reverse communication
  bool distributed;
  std::vector<double> *comm_values;    // the vector being communicated, comm_stride entries per atom
  int comm_stride;
  // the last step's imposed strain rate, and the step whose virial and vector are tallied (-1: not yet)
  double step_strain[3][3];
  bigint tallied_step;
  int vector_atoms() const;
  void exchange_ghosts(std::vector<double> &values, int stride);
  void sum_ghosts(std::vector<double> &values, int stride);
  double global_sum(double local) const;
  double global_max(double local) const;
  std::vector<double> gathered_springs() const;
  void load_springs(const double *records, size_t count);
  void report_vector();

  void collect_pairs(const double E[3][3]);
  void classify_contacts();
  void assemble_rhs(const double E[3][3]);
  int conjugate_gradients();
  void build_operator();
  int release_violated_springs();
  int relinearise_contacts();
  void finish_contacts(bool update_springs);
  void apply_operator(std::vector<double> &in, std::vector<double> &out);
  void add_pair_products(const std::vector<double> &in, std::vector<double> &out, const std::vector<int> *pair_subset,
                         const std::vector<int> *contact_subset) const;
  void self_resistance(int i, double &translation, double &rotation) const;
  void set_self_product(int i, const std::vector<double> &in, std::vector<double> &out) const;
  int atoms_above_tolerance(const std::vector<double> &z) const;
  void collect_patch();
  void patch_product(const std::vector<double> &in, std::vector<double> &out);
  double patch_preconditioner(const std::vector<double> &r, std::vector<double> &z) const;
  double local_solve();
  void build_preconditioner();
  void collect_couplings();
  bool factor_dilu();
  double apply_preconditioner(const std::vector<double> &r, std::vector<double> &z, double &largest) const;
  void tally_virial(const double E[3][3]);
  void tally_step(const double E[3][3]);
  double flow_shear_stress(const double E[3][3]) const;
  void follow_stress(const double E[3][3]);
  void relative_velocities(const SuspensionFabric::ImposedFlow &flow);
  void extrapolate_first_iterate();
};

}    // namespace LAMMPS_NS

#endif

/* fix <ID> all hydro/implicit/sf [tol <t>] [maxiter <n>] [precond dilu|jacobi] [local <f>] [verify yes|no]
       [contacts <kn> <kt> <mu>] [critical_load <F_CL> | critical_load_stress <S> <a> <eta_b>]
       [solve lagged|newton]
       [guess previous|linear|quadratic]

   Time integration of spheres whose hydrodynamic forces, the one-body Stokes drag and the
   pairwise lubrication of pair_style lubricate/sf, are taken implicitly.  Replaces fix
   nve/sphere + fix stokes/sf; needs `pair_style lubricate/sf <eta_f> <delta> <h_out>
   implicit` (alone, or in hybrid/overlay), whose parameters and neighbour list it uses.

   With u, w the velocities relative to the imposed flow (u = v - u_inf(x), w = omega -
   Omega_inf) and E the imposed strain rate, the hydrodynamic force and torque are linear,
   F_h = -R (u, w) + F_E, with R = R_drag + sum over pairs R_pair symmetric positive
   semi-definite and F_E the lubrication force on particles that follow the imposed flow
   (the pair forces at du = E (x_i - x_j), w = 0).  Each step:
     x_{n+1} = x_n + dt v_n                                            (initial_integrate)
     F_c = contact forces at x_{n+1}
     (M/dt + R + dt K) (u, w)_{n+1} = (M/dt) (u, w)_old + F_c + F_E     (final_integrate)
   where (u, w)_old are the old velocities relative to the flow at x_{n+1}.

   Contacts.  Without `contacts`, F_c comes from another pair style (granular) and K = 0:
   symplectic Euler for the contact springs, whose stiffness then limits dt (for
   m x'' = -k x - c x' the scheme is stable iff k dt^2 < 4 m + 2 c dt).  With `contacts kn kt
   mu` the fix owns the contacts (contact.h: Hooke normal, linear-history tangential spring,
   Coulomb friction, with `critical_load F_CL` only above the critical load; no other contact
   pair style allowed) and takes their springs implicitly
   (backward Euler, stable for any k dt): the tangential spring of every sticking contact
   pushes with -kt (xi_n + dt s_{n+1}), stretched by the slip s of the solved velocities
   (K = kt B^T B), and the normal spring of every pressed contact with kn (o - dt s_n), the
   overlap at the end of the step (K = kn n n).  Sliding contacts (|kt xi| at the Coulomb
   bound mu kn o with the old velocities) carry the bound, explicit, along the trial spring;
   contacts that the old velocities open within the step push with kn o, explicit.  A
   sticking spring whose solved stretch exceeds the bound is released to sliding, a pressed
   contact that the solved velocities open becomes explicit, and the system is solved again
   (at most MAX_CONTACT_PASSES solves per step).  After the step each spring holds
   xi_{n+1} = xi_n + dt s_{n+1} (capped), the displacement the next position update makes.
   Stability no longer limits dt; accuracy does: with this `solve lagged` the contact
   relaxation time X(delta)/kn must be resolved, dt <= 0.025 of it (BENCHMARKS.md, "Engine
   speed II"), because a contact's sliding is decided with the old velocities and its Coulomb
   force stays explicit: at larger dt contacts keep sliding that should stick and the contact
   stress drains away.

   `solve newton` takes the whole contact law implicitly, by a semi-smooth Newton iteration
   over the passes.  After each solve every contact is classified again from the solved
   velocities: pressed iff the step leaves it overlapping, sticking iff its trial spring
   t = xi_n + dt s_{n+1} is within the Coulomb bound; a sliding contact carries the force
   -mu F_n t/|t| linearised about the solved t, i.e. the constant -mu F_n t^ plus the stiffness
   mu F_n / |t| across t^ (none along it) in the operator, the consistent tangent of the
   Coulomb law; a sliding contact whose slip reverses between passes sticks.  The passes end
   when no contact changes between sticking and sliding or pressed and open (at most
   MAX_CONTACT_PASSES_NEWTON; a contact changes at most MAX_CONTACT_CHANGES times a step,
   which stops cycling).  Then accuracy is no longer tied to X(delta)/kn: at phi = 0.53,
   mu = 0.5, dt = 10x and 25x the lagged limit keep the contact stress of dt -> 0 (BENCHMARKS.md,
   "Engine III").

   The linear system is solved matrix-free by conjugate gradients over the pair list with a
   6x6 block-Jacobi preconditioner (rebuilt every 10 steps and after the atoms are re-sorted),
   warm-started from the old velocities, until the largest component of D^-1 r (a velocity,
   in units of gammadot d) is below `tol` (default 1e-5).  A solve that does not converge
   within `maxiter` (default 1000) stops the run with an error.  `local f` finishes a solve
   by CG on the few atoms still above tol once they are at most f N (local_solve, below);
   `verify yes` recomputes each solve's residual and stops the run if it misses tol.
   `guess linear|quadratic` starts each step's solve from the old velocities extrapolated over
   the last one or two steps instead of from the old velocities themselves (extrapolate_first_iterate);
   the per-atom history is then the fix's per-atom array: u_n (1-6), u_{n-1} (7-12), the number of
   them known (13), relative velocities in LAMMPS's order vx vy vz wx wy wz.

   Virial: the symmetrised lubrication virial sum (x_i - x_j) F_ij of the solved velocities,
   plus with `contacts` the contact virial in LAMMPS's convention (sum (x_i - x_j)_a F_b, as
   pair granular tallies it), is the fix's virial (compute pressure ... fix, and the total
   pressure); the drag adds none (see README.md).  The parts are in the fix's vector, with
   the pairs' lubrication stresslets (lubrication.h), which the virial does not include.
   Both take a pass over the pairs, so they are made only on the steps LAMMPS tallies the virial
   for (thermo, stress output) and when the vector is read, from that step's solution.
   Stress control.  `critical_load_stress S a eta_b` holds sigma / sigma_0 = S, sigma_0 = F_CL / a^2,
   at a shear rate of 1: in these units (time = strain) a change of the physical shear rate
   changes no force but the critical load, which does not scale with the rate, so a run at fixed
   stress is a run whose F_CL follows the stress, F_CL = a^2 sigma / S.  sigma is the shear stress
   along the flow, sigma:E / gammadot with gammadot = sqrt(2 E:E): eta_b gammadot (the solvent and
   Einstein parts, which no force carries) plus the particles' contact and lubrication stress, the
   contact part symmetrised with the summed contact torque.  The step uses the stress of the step
   before (of the state itself at setup), so the physical stress is held to within its change over
   one step.  A stress below eta_b gammadot, the solvent's (after a reversal the contacts built by the
   old flow push against the new one), has no finite rate that holds it: the load then follows
   eta_b gammadot, the fastest flow the stress can drive, and vector entry 34 counts those steps; the physical rate is gammadot_0 (6 pi S / eta_r) at each step (gammadot_0 =
   F_CL / (6 pi eta_f a^2)), and the mean viscosity over time at fixed stress is the mean of eta_r
   over strain.  The stress is made at every step then: one more pass over the pairs per step.
   Vector entries 32 and 33 give the critical load a step used and the stress it ended with, so
   a^2 [33] / [32] / S - 1 is how far that step's physical stress was from its target.

   The springs are written to restart files (global fix state) and read back when a fix with
   the same ID and style is defined after read_restart.

   MPI: the system is the same on any number of ranks.  Each rank owns its atoms' rows; a pair
   whose partner is owned by another rank acts through the partner's ghost copy: the operator's
   input is copied to the ghosts (forward communication), the ghosts' results are added to
   their owners (reverse communication), and the dot products are summed over the ranks.  The
   preconditioner is block Jacobi across ranks (each rank factors its own rows, the pairs
   between ranks enter its diagonal blocks only), so the iterations, not the solution, depend
   on the number of ranks.  On one rank no ghost is used: the pairs act on their owners
   directly. */

#include "fix_hydro_implicit_sf.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "memory.h"
#include "modify.h"
#include "neighbor.h"
#include "neigh_list.h"
#include "update.h"
#include "utils.h"

#include "imposed_flow.h"
#include "pair_lubricate_sf.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

using namespace LAMMPS_NS;
using namespace FixConst;

namespace {
// Cholesky factorisation in place of a symmetric 6x6 (row-major); false if not positive definite.
bool cholesky6(double *a)
{
  for (int j = 0; j < 6; j++) {
    double d = a[6 * j + j];
    for (int k = 0; k < j; k++) d -= a[6 * j + k] * a[6 * j + k];
    if (!(d > 0.0)) return false;
    d = std::sqrt(d);
    a[6 * j + j] = d;
    for (int i = j + 1; i < 6; i++) {
      double s = a[6 * i + j];
      for (int k = 0; k < j; k++) s -= a[6 * i + k] * a[6 * j + k];
      a[6 * i + j] = s / d;
    }
  }
  return true;
}

// Inverse of a symmetric positive definite 6x6 from its Cholesky factor L (lower triangle,
// row-major): solves L L^T x = e_c for each column, dividing by precomputed reciprocals.
void inverse_from_cholesky6(const double *l, double *inv)
{
  double reciprocal[6];
  for (int i = 0; i < 6; i++) reciprocal[i] = 1.0 / l[6 * i + i];
  for (int c = 0; c < 6; c++) {
    double y[6];
    for (int i = 0; i < 6; i++) {
      double s = (i == c) ? 1.0 : 0.0;
      for (int k = 0; k < i; k++) s -= l[6 * i + k] * y[k];
      y[i] = s * reciprocal[i];
    }
    for (int i = 5; i >= 0; i--) {
      double s = y[i];
      for (int k = i + 1; k < 6; k++) s -= l[6 * k + i] * y[k];
      y[i] = s * reciprocal[i];
    }
    for (int i = 0; i < 6; i++) inv[6 * i + c] = y[i];
  }
}

// Adds to the diagonal 6x6 block of one particle the form every pair term here has:
// [[along n n + across P, pump N], [-pump N, rotation P]], P = I - n n, N w = n x w.
void add_diagonal_block(const double *n, double along, double across, double pump, double rotation,
                        double *block)
{
  const double N[3][3] = {{0.0, -n[2], n[1]}, {n[2], 0.0, -n[0]}, {-n[1], n[0], 0.0}};
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) {
      const double nn = n[a] * n[b];
      const double proj = (a == b ? 1.0 : 0.0) - nn;
      block[6 * a + b] += along * nn + across * proj;
      block[6 * a + 3 + b] += pump * N[a][b];
      block[6 * (3 + a) + b] -= pump * N[a][b];
      block[6 * (3 + a) + 3 + b] += rotation * proj;
    }
}

// sum over the first `size` entries (the local atoms' rows)
double local_dot(const std::vector<double> &a, const std::vector<double> &b, size_t size)
{
  double s = 0.0;
  for (size_t k = 0; k < size; k++) s += a[k] * b[k];
  return s;
}

constexpr int SPRING_RECORD = 5;    // smaller tag, larger tag, xi

constexpr double INERTIA = 0.4;    // moment of inertia of a solid sphere / (m a^2)
constexpr bigint PRECONDITIONER_AGE = 10;    // steps between preconditioner rebuilds at most
constexpr int MAX_CONTACT_PASSES = 4;        // solves per step while sticking springs are released
constexpr int MAX_CONTACT_PASSES_NEWTON = 8;    // solves per step of solve newton
constexpr int MAX_CONTACT_CHANGES = 2;          // changes of state of one contact per step (newton)
constexpr int MAX_LOCAL_ROUNDS = 4;             // local solves per CG solve at most
constexpr int MAX_LOCAL_ITERATIONS = 100;       // CG iterations of one local solve at most
constexpr double LOCAL_TOLERANCE = 0.3;         // a local solve stops at this fraction of tol
constexpr double VERIFY_MARGIN = 1.01;    // verify: CG's carried residual may drift this much
constexpr double LOCAL_GAIN = 2.0;    // solve locally only while the largest error exceeds this x tol
constexpr char PATCH = 1, REACHED = 2, CORE = 3;    // in_patch: in the patch, only reached by its pairs, above tol
constexpr int HISTORY_KNOWN = 12;    // velocity_history: two 6-vectors, then how many of them are known
constexpr int HISTORY_COLUMNS = 13;
}    // namespace

FixHydroImplicitSF::FixHydroImplicitSF(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), tolerance(1.0e-5), guess_order(0), velocity_history(nullptr), local_fraction(0.0), verify(false), max_iterations(1000), own_contacts(false), newton_contacts(false), kn(0.0),
    kt(0.0), mu(0.0), critical_load(0.0), controlled_stress(0.0), load_radius(0.0), background_viscosity(0.0),
    shear_stress(0.0), floored_steps(0), dtv(0.0), lubrication(nullptr), steps(0), total_iterations(0),
    total_passes(0), total_released(0), total_local_work(0.0), last_iterations(0), last_error(0.0), sliding_contacts(0), frictional_contacts(0),
    use_dilu(false), dilu_fallbacks(0), distributed(false), comm_values(nullptr), comm_stride(6), tallied_step(-1)
{
  int iarg = 3;
  while (iarg < narg) {
    if (strcmp(arg[iarg], "tol") == 0 && iarg + 1 < narg) {
      tolerance = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      if (!(tolerance > 0.0)) error->all(FLERR, "fix hydro/implicit/sf: tol must be > 0");
      iarg += 2;
    } else if (strcmp(arg[iarg], "local") == 0 && iarg + 1 < narg) {
      local_fraction = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      if (!(local_fraction >= 0.0 && local_fraction < 1.0))
        error->all(FLERR, "fix hydro/implicit/sf: local must be in [0, 1), got {}", local_fraction);
      iarg += 2;
    } else if (strcmp(arg[iarg], "verify") == 0 && iarg + 1 < narg) {
      verify = utils::logical(FLERR, arg[iarg + 1], false, lmp) == 1;
      iarg += 2;
    } else if (strcmp(arg[iarg], "maxiter") == 0 && iarg + 1 < narg) {
      max_iterations = utils::inumeric(FLERR, arg[iarg + 1], false, lmp);
      if (max_iterations < 1) error->all(FLERR, "fix hydro/implicit/sf: maxiter must be >= 1");
      iarg += 2;
    } else if (strcmp(arg[iarg], "precond") == 0 && iarg + 1 < narg) {
      if (strcmp(arg[iarg + 1], "dilu") == 0) use_dilu = true;
      else if (strcmp(arg[iarg + 1], "jacobi") == 0) use_dilu = false;
      else error->all(FLERR, "fix hydro/implicit/sf: precond must be dilu or jacobi, got '{}'", arg[iarg + 1]);
      iarg += 2;
    } else if (strcmp(arg[iarg], "solve") == 0 && iarg + 1 < narg) {
      if (strcmp(arg[iarg + 1], "newton") == 0) newton_contacts = true;
      else if (strcmp(arg[iarg + 1], "lagged") == 0) newton_contacts = false;
      else error->all(FLERR, "fix hydro/implicit/sf: solve must be lagged or newton, got '{}'", arg[iarg + 1]);
      iarg += 2;
    } else if (strcmp(arg[iarg], "guess") == 0 && iarg + 1 < narg) {
      if (strcmp(arg[iarg + 1], "previous") == 0) guess_order = 0;
      else if (strcmp(arg[iarg + 1], "linear") == 0) guess_order = 1;
      else if (strcmp(arg[iarg + 1], "quadratic") == 0) guess_order = 2;
      else error->all(FLERR, "fix hydro/implicit/sf: guess must be previous, linear or quadratic, got '{}'", arg[iarg + 1]);
      iarg += 2;
    } else if (strcmp(arg[iarg], "contacts") == 0 && iarg + 3 < narg) {
      own_contacts = true;
      kn = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      kt = utils::numeric(FLERR, arg[iarg + 2], false, lmp);
      mu = utils::numeric(FLERR, arg[iarg + 3], false, lmp);
      if (!(kn > 0.0) || !(kt > 0.0) || !(mu >= 0.0))
        error->all(FLERR, "fix hydro/implicit/sf: contacts needs kn > 0, kt > 0, mu >= 0");
      iarg += 4;
    } else if (strcmp(arg[iarg], "critical_load") == 0 && iarg + 1 < narg) {
      critical_load = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      if (!(critical_load >= 0.0))
        error->all(FLERR, "fix hydro/implicit/sf: critical_load must be >= 0, got {}", critical_load);
      iarg += 2;
    } else if (strcmp(arg[iarg], "critical_load_stress") == 0 && iarg + 3 < narg) {
      controlled_stress = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      load_radius = utils::numeric(FLERR, arg[iarg + 2], false, lmp);
      background_viscosity = utils::numeric(FLERR, arg[iarg + 3], false, lmp);
      if (!(controlled_stress > 0.0) || !(load_radius > 0.0) || !(background_viscosity > 0.0))
        error->all(FLERR, "fix hydro/implicit/sf: critical_load_stress needs S > 0, a > 0 and eta_b > 0, got {} {} {}",
                   controlled_stress, load_radius, background_viscosity);
      iarg += 4;
    } else {
      error->all(FLERR, "Illegal fix hydro/implicit/sf keyword '{}': expected tol <t>, maxiter <n>, "
                        "precond dilu|jacobi, local <fraction>, verify yes|no, contacts <kn> <kt> <mu>, critical_load <F_CL>, "
                        "critical_load_stress <S> <a> <eta_b>, "
                        "solve lagged|newton or guess previous|linear|quadratic",
                 arg[iarg]);
    }
  }
  if (controlled_stress > 0.0 && critical_load > 0.0)
    error->all(FLERR, "fix hydro/implicit/sf: critical_load and critical_load_stress exclude each other");
  time_integrate = 1;
  virial_global_flag = 1;
  thermo_virial = 1;
  restart_global = 1;
  vector_flag = 1;
  size_vector = HydroVector::SIZE;
  global_freq = 1;
  extvector = 0;
  comm_forward = 6;     // a velocity (u, w)
  comm_reverse = 36;    // a 6x6 diagonal block
  for (double &v : reported) v = 0.0;
  for (double &v : virial) v = 0.0;
  for (double &v : contact_virial) v = 0.0;
  for (double &v : contact_torque) v = 0.0;
  for (double &v : lubrication_virial) v = 0.0;
  for (double &v : stresslet_virial) v = 0.0;
  if (guess_order > 0) {    // the history moves with its atom (sorting, migration to another rank)
    maxexchange = HISTORY_COLUMNS;
    peratom_flag = 1;    // and is the fix's per-atom array, f_ID[1] to f_ID[13]
    size_peratom_cols = HISTORY_COLUMNS;
    peratom_freq = 1;
    grow_arrays(atom->nmax);
    atom->add_callback(Atom::GROW);
    for (int i = 0; i < atom->nlocal; i++) std::fill(velocity_history[i], velocity_history[i] + HISTORY_COLUMNS, 0.0);
  }
}

FixHydroImplicitSF::~FixHydroImplicitSF()
{
  if (velocity_history == nullptr) return;
  atom->delete_callback(id, Atom::GROW);
  memory->destroy(velocity_history);
}

int FixHydroImplicitSF::setmask()
{
  return INITIAL_INTEGRATE | FINAL_INTEGRATE;
}

void FixHydroImplicitSF::init()
{
  distributed = comm->nprocs > 1;
  if (igroup != 0) error->all(FLERR, "fix hydro/implicit/sf must act on group all");
  if (!atom->radius_flag || !atom->omega_flag || !atom->torque_flag || !atom->rmass_flag)
    error->all(FLERR, "fix hydro/implicit/sf requires atom style sphere");
  if (atom->map_style == Atom::MAP_NONE)
    error->all(FLERR, "fix hydro/implicit/sf requires an atom map (atom_modify map array)");
  Pair *pair = force->pair_match("lubricate/sf", 1, 0);
  if (pair == nullptr)
    error->all(FLERR, "fix hydro/implicit/sf needs pair_style lubricate/sf ... implicit");
  lubrication = static_cast<PairLubricateSF *>(pair);
  if (!lubrication->implicit)
    error->all(FLERR, "fix hydro/implicit/sf needs pair_style lubricate/sf with the keyword "
                      "'implicit' (else the lubrication would be applied twice)");
  if (!modify->get_fix_by_style("^stokes/sf$").empty())
    error->all(FLERR, "fix hydro/implicit/sf already includes the Stokes drag; remove fix stokes/sf");
  if (newton_contacts && !own_contacts)
    error->all(FLERR, "fix hydro/implicit/sf: solve newton needs the keyword contacts (the fix's own contacts)");
  if (critical_load > 0.0 && !own_contacts)
    error->all(FLERR, "fix hydro/implicit/sf: critical_load needs the keyword contacts (the fix's own contacts)");
  if (controlled_stress > 0.0 && !own_contacts)
    error->all(FLERR, "fix hydro/implicit/sf: critical_load_stress needs the keyword contacts (the fix's own contacts)");

  if (own_contacts) {
    if (force->pair_match("granular", 0, 0) != nullptr || force->pair_match("gran", 0, 0) != nullptr)
      error->all(FLERR, "fix hydro/implicit/sf ... contacts computes the contacts itself; remove the "
                        "granular pair style (else every contact would act twice)");
    if (!force->newton_pair)
      error->all(FLERR, "fix hydro/implicit/sf ... contacts needs newton_pair on (each contact listed once)");
    tagint largest_tag = 0;
    for (int i = 0; i < atom->nlocal; i++) largest_tag = std::max(largest_tag, atom->tag[i]);
    if (static_cast<long long>(largest_tag) >= (1LL << 31))
      error->all(FLERR, "fix hydro/implicit/sf ... contacts: atom IDs must stay below 2^31");
  }
  dtv = update->dt;
}

void FixHydroImplicitSF::reset_dt()
{
  dtv = update->dt;
}

void FixHydroImplicitSF::setup(int /*vflag*/)
{
  // forces and virial of the current state, for output at the first step; springs unchanged
  const SuspensionFabric::ImposedFlow flow(domain);
  const auto &E = flow.strain;
  if (distributed && own_contacts) {
    const std::vector<double> records = gathered_springs();
    load_springs(records.data(), records.size() / SPRING_RECORD);
  }
  collect_pairs(E);
  relative_velocities(flow);
  if (own_contacts) {
    for (SuspensionFabric::Contact &c : contacts) c.sticking = true;
    finish_contacts(false);
  }
  tally_step(E);
  if (controlled_stress > 0.0) follow_stress(E);
}

// E = (L + L^T)/2 of the imposed flow

// solution = (v - u_inf(x), omega - Omega_inf) of every local atom, copied to the ghosts
// (the relative velocity of a periodic image is its owner's)
void FixHydroImplicitSF::relative_velocities(const SuspensionFabric::ImposedFlow &flow)
{
  const int nlocal = atom->nlocal;
  solution.resize(6 * static_cast<size_t>(vector_atoms()));
  double u[3];
  for (int i = 0; i < nlocal; i++) {
    flow.velocity(atom->x[i], u);
    for (int k = 0; k < 3; k++) {
      solution[6 * i + k] = atom->v[i][k] - u[k];
      solution[6 * i + 3 + k] = atom->omega[i][k] - flow.omega[k];
    }
  }
  exchange_ghosts(solution, 6);
}

void FixHydroImplicitSF::initial_integrate(int /*vflag*/)
{
  double **x = atom->x;
  double **v = atom->v;
  const int nlocal = atom->nlocal;
  for (int i = 0; i < nlocal; i++)
    for (int k = 0; k < 3; k++) x[i][k] += dtv * v[i][k];
}

/* The lubricated pairs and, with `contacts`, the touching pairs with their geometry, normal
   force and last spring (projected onto the current tangent plane). */
void FixHydroImplicitSF::collect_pairs(const double E[3][3])
{
  pairs.clear();
  contacts.clear();
  const NeighList *list = lubrication->list;
  double **x = atom->x;
  const double *radius = atom->radius;
  const tagint *tag = atom->tag;
  const int nlocal = atom->nlocal;
  const int newton_pair = force->newton_pair;
  for (int ii = 0; ii < list->inum; ii++) {
    const int i = list->ilist[ii];
    const int *jlist = list->firstneigh[i];
    for (int jj = 0; jj < list->numneigh[i]; jj++) {
      const int j = jlist[jj] & NEIGHMASK;
      LubricatedPair p;
      for (int k = 0; k < 3; k++) p.del[k] = x[i][k] - x[j][k];
      if (!lubrication->resistance(i, j, p.del, p.R)) continue;
      p.i = i;
      p.j = j;
      if (j >= nlocal) {    // a periodic image of a local atom acts on the atom itself
        const int owner = atom->map(tag[j]);
        if (owner >= 0 && owner < nlocal) p.j = owner;
        else if (!distributed)
          error->one(FLERR, "fix hydro/implicit/sf: no local owner of ghost atom {}", tag[j]);
      }
      p.add_to_j = newton_pair || j < nlocal;
      pairs.push_back(p);
      if (!own_contacts) continue;

      const double rsq = SuspensionFabric::dot3(p.del, p.del);
      const double radsum = radius[i] + radius[j];
      if (rsq >= radsum * radsum) continue;
      SuspensionFabric::Contact c;
      c.i = p.i;
      c.j = p.j;
      c.pair = static_cast<int>(pairs.size()) - 1;
      const double r = std::sqrt(rsq);
      const double overlap = radsum - r;
      for (int k = 0; k < 3; k++) {
        c.del[k] = p.del[k];
        c.n[k] = p.del[k] / r;
      }
      c.li = radius[i] - 0.5 * overlap;
      c.lj = radius[j] - 0.5 * overlap;
      c.overlap = overlap;
      c.normal_force = kn * overlap;
      c.friction_bound = mu * std::max(c.normal_force - critical_load, 0.0);
      const tagint low = std::min(tag[i], tag[j]), high = std::max(tag[i], tag[j]);
      c.key = (static_cast<unsigned long long>(low) << 32) | static_cast<unsigned long long>(high);
      c.history_sign = tag[i] < tag[j] ? 1.0 : -1.0;
      const auto found = springs.find(c.key);
      for (int k = 0; k < 3; k++) c.spring[k] = found == springs.end() ? 0.0 : c.history_sign * found->second.xi[k];
      SuspensionFabric::project_spring(c.n, c.spring);
      // slip of the imposed flow: P E (x_i - x_j) (its rotation does not slip a touching pair)
      double edel[3];
      for (int a = 0; a < 3; a++) edel[a] = E[a][0] * p.del[0] + E[a][1] * p.del[1] + E[a][2] * p.del[2];
      const double along = SuspensionFabric::dot3(edel, c.n);
      for (int k = 0; k < 3; k++) c.flow_slip[k] = edel[k] - along * c.n[k];
      c.flow_approach = along;
      c.sticking = true;
      c.pressed = false;
      c.solved_normal = c.normal_force;
      contacts.push_back(c);
    }
  }
}

namespace {
// trial spring xi + dt s, with s the whole slip (imposed flow and the velocities in `u`)
void trial_spring(const SuspensionFabric::Contact &c, const std::vector<double> &u, double dt,
                  double *trial)
{
  const double *ui = &u[6 * c.i], *uj = &u[6 * c.j];
  const double du[3] = {ui[0] - uj[0], ui[1] - uj[1], ui[2] - uj[2]};
  double s[3];
  SuspensionFabric::contact_slip(c, du, ui + 3, uj + 3, s);
  for (int k = 0; k < 3; k++) trial[k] = c.spring[k] + dt * (c.flow_slip[k] + s[k]);
}

// overlap at the end of the step, o - dt (n . (u_i - u_j) + n . E (x_i - x_j)), for the velocities in `u`
double predicted_overlap(const SuspensionFabric::Contact &c, const std::vector<double> &u, double dt)
{
  const double *ui = &u[6 * c.i], *uj = &u[6 * c.j];
  const double du[3] = {ui[0] - uj[0], ui[1] - uj[1], ui[2] - uj[2]};
  return c.overlap - dt * (SuspensionFabric::dot3(du, c.n) + c.flow_approach);
}

// a sliding contact along its trial spring t: the force -bound t^ and the stiffness bound/|t| across t^
void set_sliding(SuspensionFabric::Contact &c, const double *trial, double bound)
{
  const double length = std::sqrt(SuspensionFabric::dot3(trial, trial));
  for (int k = 0; k < 3; k++) {
    c.sliding_direction[k] = length > 0.0 ? trial[k] / length : 0.0;
    c.sliding_force[k] = -bound * c.sliding_direction[k];
  }
  c.sliding_stiffness = length > 0.0 ? bound / length : 0.0;
}

// the Coulomb force mu F_n against the trial spring direction
void coulomb_force(const double *trial, double bound, double *f)
{
  const double length = std::sqrt(SuspensionFabric::dot3(trial, trial));
  for (int k = 0; k < 3; k++) f[k] = length > 0.0 ? -bound * trial[k] / length : 0.0;
}
}    // namespace

/* Sticking or sliding, from the trial spring of the old velocities (in `solution`), and the
   normal spring implicit while the old velocities keep the pair overlapping to the end of the
   step. */
void FixHydroImplicitSF::classify_contacts()
{
  double trial[3];
  for (SuspensionFabric::Contact &c : contacts) {
    c.pressed = predicted_overlap(c, solution, dtv) > 0.0;
    trial_spring(c, solution, dtv, trial);
    const double bound = c.friction_bound;
    c.sticking = bound > 0.0 && kt * std::sqrt(SuspensionFabric::dot3(trial, trial)) <= bound;
    if (!c.sticking) set_sliding(c, trial, bound);
    c.changes = 0;
  }
}

/* solve newton: every contact classified again from the solved velocities (see the header
   comment); returns how many contacts changed between sticking and sliding or pressed and open. */
int FixHydroImplicitSF::relinearise_contacts()
{
  int changed = 0;
  double trial[3];
  for (SuspensionFabric::Contact &c : contacts) {
    const bool may_change = c.changes < MAX_CONTACT_CHANGES;
    const bool pressed = predicted_overlap(c, solution, dtv) > 0.0;
    trial_spring(c, solution, dtv, trial);
    const double bound = c.friction_bound;
    const double stretch = kt * std::sqrt(SuspensionFabric::dot3(trial, trial));
    bool sticking = bound > 0.0 && stretch <= bound * (1.0 + 1.0e-9);
    // the linearised sliding law has no stiffness along the sliding direction: a slip that
    // reversed within the step is taken by the spring
    // (a frictionless contact has no spring to take it)
    if (!c.sticking && bound > 0.0 && SuspensionFabric::dot3(trial, c.sliding_direction) < 0.0) sticking = true;
    if (may_change && (pressed != c.pressed || sticking != c.sticking)) {
      c.pressed = pressed;
      c.sticking = sticking;
      c.changes++;
      changed++;
    }
    if (!c.sticking) set_sliding(c, trial, bound);
  }
  return changed;
}

/* Sticking springs stretched beyond the Coulomb bound by the solved velocities slide, and
   implicit normal springs whose pair the solved velocities separate within the step become
   explicit (kn o): returns how many contacts changed. */
int FixHydroImplicitSF::release_violated_springs()
{
  int released = 0;
  double trial[3];
  for (SuspensionFabric::Contact &c : contacts) {
    if (c.pressed && predicted_overlap(c, solution, dtv) < 0.0) {
      c.pressed = false;
      released++;
    }
    if (!c.sticking) continue;
    trial_spring(c, solution, dtv, trial);
    const double bound = c.friction_bound;
    if (kt * std::sqrt(SuspensionFabric::dot3(trial, trial)) > bound * (1.0 + 1.0e-9)) {
      c.sticking = false;
      coulomb_force(trial, bound, c.sliding_force);
      released++;
    }
  }
  return released;
}

/* Tangential forces of the solved step, the contact virial and torque and, if update_springs,
   the springs xi_{n+1} (capped at the Coulomb bound) for the next step. */
void FixHydroImplicitSF::finish_contacts(bool update_springs)
{
  for (double &v : contact_virial) v = 0.0;
  for (double &v : contact_torque) v = 0.0;
  if (update_springs) next_springs.clear();
  sliding_contacts = 0;
  frictional_contacts = 0;
  double trial[3], ti[3], tj[3];
  for (SuspensionFabric::Contact &c : contacts) {
    const double bound = c.friction_bound;
    if (bound > 0.0) frictional_contacts++;
    if (update_springs) {
      trial_spring(c, solution, dtv, trial);
    } else {
      for (int k = 0; k < 3; k++) trial[k] = c.spring[k];
    }
    if (c.sticking && update_springs) {
      for (int k = 0; k < 3; k++) c.force[k] = -kt * trial[k];    // the force the solve used
    } else if (c.sticking) {
      const double magnitude = kt * std::sqrt(SuspensionFabric::dot3(trial, trial));
      const double scale = magnitude > bound ? bound / magnitude : 1.0;
      for (int k = 0; k < 3; k++) c.force[k] = -kt * scale * trial[k];
    } else if (newton_contacts && update_springs) {
      // the Coulomb force along the solved trial spring
      const double magnitude = kt * std::sqrt(SuspensionFabric::dot3(trial, trial));
      const double scale = magnitude > bound ? bound / magnitude : 1.0;
      for (int k = 0; k < 3; k++) c.force[k] = -kt * scale * trial[k];
      sliding_contacts++;
    } else {
      for (int k = 0; k < 3; k++) c.force[k] = c.sliding_force[k];
      sliding_contacts++;
    }
    if (update_springs) {
      const double magnitude = kt * std::sqrt(SuspensionFabric::dot3(trial, trial));
      const double scale = magnitude > bound ? bound / magnitude : 1.0;
      Spring &stored = next_springs[c.key];
      for (int k = 0; k < 3; k++) stored.xi[k] = c.history_sign * scale * trial[k];
    }
    c.solved_normal = c.pressed && update_springs ? kn * predicted_overlap(c, solution, dtv) : c.normal_force;
    double F[3];
    for (int k = 0; k < 3; k++) F[k] = c.solved_normal * c.n[k] + c.force[k];
    contact_virial[0] += c.del[0] * F[0];
    contact_virial[1] += c.del[1] * F[1];
    contact_virial[2] += c.del[2] * F[2];
    contact_virial[3] += c.del[0] * F[1];
    contact_virial[4] += c.del[0] * F[2];
    contact_virial[5] += c.del[1] * F[2];
    SuspensionFabric::contact_torques(c, c.force, ti, tj);
    for (int k = 0; k < 3; k++) contact_torque[k] += ti[k] + tj[k];
  }
  if (update_springs) springs.swap(next_springs);
}

// the diagonal of the one-body terms (mass / dt and Stokes drag) of atom i: translation and rotation
void FixHydroImplicitSF::self_resistance(int i, double &translation, double &rotation) const
{
  const double a = atom->radius[i];
  const double pi_eta = M_PI * lubrication->eta_f;
  translation = atom->rmass[i] / dtv + 6.0 * pi_eta * a;
  rotation = INERTIA * atom->rmass[i] * a * a / dtv + 8.0 * pi_eta * a * a * a;
}

// out_i = the one-body terms times in_i (the start of row i of A in)
void FixHydroImplicitSF::set_self_product(int i, const std::vector<double> &in, std::vector<double> &out) const
{
  const double translation = self_resistances[2 * i], rotation = self_resistances[2 * i + 1];
  for (int k = 0; k < 3; k++) {
    out[6 * i + k] = translation * in[6 * i + k];
    out[6 * i + 3 + k] = rotation * in[6 * i + 3 + k];
  }
}

// out = A in for the local rows; in's ghost entries are refreshed first
void FixHydroImplicitSF::apply_operator(std::vector<double> &in, std::vector<double> &out)
{
  const int nlocal = atom->nlocal;
  exchange_ghosts(in, 6);
  std::fill(out.begin() + 6 * static_cast<size_t>(nlocal), out.end(), 0.0);
  for (int i = 0; i < nlocal; i++) set_self_product(i, in, out);
  add_pair_products(in, out, nullptr, nullptr);
  sum_ghosts(out, 6);
}

/* out += the pair terms of the operator times in: every lubricated pair and implicit contact
   spring, or only those listed in the subsets (indices into pairs and contacts). */
void FixHydroImplicitSF::add_pair_products(const std::vector<double> &in, std::vector<double> &out,
                                           const std::vector<int> *pair_subset,
                                           const std::vector<int> *contact_subset) const
{
  double fi[3], ti[3], tj[3];
  const size_t pair_count = pair_subset ? pair_subset->size() : operator_pairs.size();
  for (size_t q = 0; q < pair_count; q++) {
    const OperatorPair &p = operator_pairs[pair_subset ? (*pair_subset)[q] : q];
    const double *ui = &in[6 * p.i], *uj = &in[6 * p.j];
    const double du[3] = {ui[0] - uj[0], ui[1] - uj[1], ui[2] - uj[2]};
    SuspensionFabric::lubrication_forces(p, du, ui + 3, uj + 3, fi, ti, tj);
    double *oi = &out[6 * p.i];
    for (int k = 0; k < 3; k++) {    // resistance = minus the force
      oi[k] -= fi[k];
      oi[3 + k] -= ti[k];
    }
    if (p.add_to_j) {
      double *oj = &out[6 * p.j];
      for (int k = 0; k < 3; k++) {
        oj[k] += fi[k];
        oj[3 + k] -= tj[k];
      }
    }
  }
  // the contacts not folded into their pair: sliding ones with the consistent tangent, kt dt
  // times the slip's part across the sliding direction, and those of pairs acting on i only;
  // a sticking spring is minus the force -kt dt s of the slip s, a pressed normal one kn dt n n
  const double stiffness = kt * dtv;
  const double normal_stiffness = kn * dtv;
  const size_t contact_count = contact_subset ? contact_subset->size() : separate_contacts.size();
  for (size_t q = 0; q < contact_count; q++) {
    const SuspensionFabric::Contact &c = contacts[contact_subset ? (*contact_subset)[q] : separate_contacts[q]];
    const bool sliding_tangent = newton_contacts && !c.sticking;
    const double *ui = &in[6 * c.i], *uj = &in[6 * c.j];
    const double du[3] = {ui[0] - uj[0], ui[1] - uj[1], ui[2] - uj[2]};
    double s[3] = {0.0, 0.0, 0.0};
    if (c.sticking || sliding_tangent) SuspensionFabric::contact_slip(c, du, ui + 3, uj + 3, s);
    if (sliding_tangent) {    // the consistent tangent: stiffness across the sliding direction only
      const double along = SuspensionFabric::dot3(s, c.sliding_direction);
      for (int k = 0; k < 3; k++) fi[k] = -c.sliding_stiffness * dtv * (s[k] - along * c.sliding_direction[k]);
    } else {
      for (int k = 0; k < 3; k++) fi[k] = -stiffness * s[k];
    }
    if (c.pressed) {
      const double separation = SuspensionFabric::dot3(du, c.n);
      for (int k = 0; k < 3; k++) fi[k] -= normal_stiffness * separation * c.n[k];
    }
    SuspensionFabric::contact_torques(c, fi, ti, tj);
    double *oi = &out[6 * c.i], *oj = &out[6 * c.j];
    for (int k = 0; k < 3; k++) {
      oi[k] -= fi[k];
      oi[3 + k] -= ti[k];
      oj[k] += fi[k];
      oj[3 + k] -= tj[k];
    }
  }
}

namespace {
// a sticking spring c = kt dt between i and j (lever arms li, lj) in a pair's coupling coefficients
// (lubrication.h's form in the pair's n): YA += c, YBi -= c li, YBj -= c lj, YCx += c li lj
inline void add_spring_coupling(double c, double li, double lj, double &YA, double &YBi, double &YBj, double &YCx)
{
  YA += c;
  YBi -= c * li;
  YBj -= c * lj;
  YCx += c * li * lj;
}
}    // namespace

/* The operator for the contacts' current states: each atom's self resistances, and each pair's
   (OperatorPair) lubrication resistances plus the springs of its sticking or pressed contact when
   the pair acts on both atoms; the other contacts in the operator go to separate_contacts. */
void FixHydroImplicitSF::build_operator()
{
  const int nlocal = atom->nlocal;
  self_resistances.resize(2 * static_cast<size_t>(nlocal));
  for (int i = 0; i < nlocal; i++) self_resistance(i, self_resistances[2 * i], self_resistances[2 * i + 1]);
  operator_pairs.resize(pairs.size());
  for (size_t k = 0; k < pairs.size(); k++) {
    const LubricatedPair &p = pairs[k];
    OperatorPair &o = operator_pairs[k];
    o.i = p.i;
    o.j = p.j;
    o.add_to_j = p.add_to_j;
    for (int a = 0; a < 3; a++) o.n[a] = p.R.n[a];
    o.X = p.R.X;
    o.YA = p.R.YA;
    o.YBi = p.R.YBi;
    o.YBj = p.R.YBj;
    o.YCi = p.R.YCi;
    o.YCj = p.R.YCj;
    o.YCx = p.R.YCx;
  }
  separate_contacts.clear();
  const double stiffness = kt * dtv;
  for (size_t q = 0; q < contacts.size(); q++) {
    const SuspensionFabric::Contact &c = contacts[q];
    const bool sliding_tangent = newton_contacts && !c.sticking;
    if (!c.sticking && !c.pressed && !sliding_tangent) continue;
    OperatorPair &o = operator_pairs[c.pair];
    if (sliding_tangent || !o.add_to_j) {
      separate_contacts.push_back(static_cast<int>(q));
      continue;
    }
    // the contact's n is the pair's reversed (from j to i), which the coefficients absorb
    if (c.sticking) {
      add_spring_coupling(stiffness, c.li, c.lj, o.YA, o.YBi, o.YBj, o.YCx);
      o.YCi += stiffness * c.li * c.li;
      o.YCj += stiffness * c.lj * c.lj;
    }
    if (c.pressed) o.X += kn * dtv;
  }
}

void FixHydroImplicitSF::build_preconditioner()
{
  const int nlocal = atom->nlocal;
  block_factor.assign(36 * static_cast<size_t>(vector_atoms()), 0.0);
  double translation, rotation;
  for (int i = 0; i < nlocal; i++) {
    self_resistance(i, translation, rotation);
    double *b = &block_factor[36 * i];
    for (int k = 0; k < 3; k++) {
      b[7 * k] = translation;
      b[7 * (k + 3)] = rotation;
    }
  }
  // lubrication (n from i to j): the pump YBi for i and -YBj for j (lubrication_forces)
  for (const LubricatedPair &p : pairs) {
    add_diagonal_block(p.R.n, p.R.X, p.R.YA, p.R.YBi, p.R.YCi, &block_factor[36 * p.i]);
    if (p.add_to_j) add_diagonal_block(p.R.n, p.R.X, p.R.YA, -p.R.YBj, p.R.YCj, &block_factor[36 * p.j]);
  }
  // implicit springs (n from j to i): c B^T B of a sticking spring, c = kt dt, with B = [P, l N]
  // for i and [-P, l N] for j, i.e. c [[P, +-l N], [-+l N, l^2 P]]; kn dt n n of a pressed one
  for (const SuspensionFabric::Contact &c : contacts) {
    const double along = c.pressed ? kn * dtv : 0.0;
    const double across = c.sticking ? kt * dtv : 0.0;
    add_diagonal_block(c.n, along, across, across * c.li, across * c.li * c.li, &block_factor[36 * c.i]);
    add_diagonal_block(c.n, along, across, -across * c.lj, across * c.lj * c.lj, &block_factor[36 * c.j]);
  }
  sum_ghosts(block_factor, 36);
  block_inverse.resize(block_factor.size());
  if (use_dilu) {
    const std::vector<double> diagonal = block_factor;
    collect_couplings();
    if (factor_dilu()) return;
    // not positive definite after the elimination: block Jacobi for this rebuild
    dilu_fallbacks++;
    couplings.clear();
    by_lo.clear();
    by_hi.clear();
    block_factor = diagonal;
  }
  for (int i = 0; i < nlocal; i++) {
    if (!cholesky6(&block_factor[36 * i]))
      error->one(FLERR, "fix hydro/implicit/sf: the resistance block of atom {} is not positive "
                        "definite at step {}",
                 atom->tag[i], update->ntimestep);
    inverse_from_cholesky6(&block_factor[36 * i], &block_inverse[36 * i]);
  }
}

namespace {
// out = A x for a coupling block (transpose: A^T x = [[T, -delta N], [-gamma N, epsilon P]] x)
template <class C>
inline void apply_coupling(const C &c, const double *__restrict x, double *__restrict out, bool transpose)
{
  const double *n = c.n;
  const double *u = x, *w = x + 3;
  const double un = n[0] * u[0] + n[1] * u[1] + n[2] * u[2];
  const double wn = n[0] * w[0] + n[1] * w[1] + n[2] * w[2];
  const double nxu[3] = {n[1] * u[2] - n[2] * u[1], n[2] * u[0] - n[0] * u[2], n[0] * u[1] - n[1] * u[0]};
  const double nxw[3] = {n[1] * w[2] - n[2] * w[1], n[2] * w[0] - n[0] * w[2], n[0] * w[1] - n[1] * w[0]};
  const double tr = transpose ? -c.delta : c.gamma;
  const double rt = transpose ? -c.gamma : c.delta;
  for (int k = 0; k < 3; k++) {
    out[k] = -c.alpha * un * n[k] - c.beta * (u[k] - un * n[k]) + tr * nxw[k];
    out[3 + k] = rt * nxu[k] + c.epsilon * (w[k] - wn * n[k]);
  }
}

// the dense row-major 6x6 block of a coupling
template <class C>
void dense_coupling(const C &c, double *block)
{
  const double *n = c.n;
  const double N[3][3] = {{0.0, -n[2], n[1]}, {n[2], 0.0, -n[0]}, {-n[1], n[0], 0.0}};
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) {
      const double nn = n[a] * n[b];
      const double proj = (a == b ? 1.0 : 0.0) - nn;
      block[6 * a + b] = -(c.alpha * nn + c.beta * proj);
      block[6 * a + 3 + b] = c.gamma * N[a][b];
      block[6 * (3 + a) + b] = c.delta * N[a][b];
      block[6 * (3 + a) + 3 + b] = c.epsilon * proj;
    }
}

// out = A in for a row-major 6x6 A
inline void multiply6(const double *__restrict A, const double *__restrict in, double *__restrict out)
{
  for (int a = 0; a < 6; a++) {
    double s = 0.0;
    for (int b = 0; b < 6; b++) s += A[6 * a + b] * in[b];
    out[a] = s;
  }
}

// start[k] .. start[k + 1]: the entries with key k, in `sorted` (a stable counting sort)
template <class C, class Key>
void sort_by(const std::vector<C> &entries, int n, Key key, std::vector<C> &sorted, std::vector<int> &start)
{
  start.assign(n + 1, 0);
  for (const C &c : entries) start[key(c) + 1]++;
  for (int k = 0; k < n; k++) start[k + 1] += start[k];
  sorted.resize(entries.size());
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (const C &c : entries) sorted[fill[key(c)]++] = c;
}
}    // namespace

/* The off-diagonal blocks of the operator, one per lubricated pair (lubrication and, if the
   pair is a sticking contact, its spring), each stored for lo < hi.  In the lubrication's
   n (from i to j): alpha = X, beta = YA, gamma = YBj, delta = YBi, epsilon = YCx
   (lubrication_forces), and a spring c = kt dt adds beta += c, gamma -= c l_j,
   delta -= c l_i, epsilon += c l_i l_j (c B_i^T B_j, contact.h).  A_ji = A_ij^T is the same
   form with n -> -n and gamma <-> delta. */
void FixHydroImplicitSF::collect_couplings()
{
  couplings.clear();
  pair_coupling.assign(pairs.size(), -1);
  for (size_t k = 0; k < pairs.size(); k++) {
    const LubricatedPair &p = pairs[k];
    // acts on i only, a pair with its own image, or a partner on another rank (block Jacobi there)
    if (!p.add_to_j || p.i == p.j || p.j >= atom->nlocal) continue;
    Coupling c;
    c.lo = p.i;
    c.hi = p.j;
    for (int a = 0; a < 3; a++) c.n[a] = p.R.n[a];
    c.alpha = p.R.X;
    c.beta = p.R.YA;
    c.gamma = p.R.YBj;
    c.delta = p.R.YBi;
    c.epsilon = p.R.YCx;
    pair_coupling[k] = static_cast<int>(couplings.size());
    couplings.push_back(c);
  }
  const double stiffness = kt * dtv;
  for (const SuspensionFabric::Contact &contact : contacts) {
    if (pair_coupling[contact.pair] < 0) continue;
    Coupling &c = couplings[pair_coupling[contact.pair]];
    if (contact.sticking) add_spring_coupling(stiffness, contact.li, contact.lj, c.beta, c.delta, c.gamma, c.epsilon);
    if (contact.pressed) c.alpha += kn * dtv;
  }
  for (Coupling &c : couplings)
    if (c.lo > c.hi) {
      std::swap(c.lo, c.hi);
      std::swap(c.gamma, c.delta);
      for (double &component : c.n) component = -component;
    }
  const int nlocal = atom->nlocal;
  sort_by(couplings, nlocal, [](const Coupling &c) { return c.lo; }, by_lo, by_lo_start);
  sort_by(couplings, nlocal, [](const Coupling &c) { return c.hi; }, by_hi, by_hi_start);
}

/* Diagonal-modified incomplete factorisation M = (D + L) D^-1 (D + L^T), L the strictly lower
   blocks of the operator and D_k = A_kk - sum_{m<k} A_km D_m^-1 A_mk over the pairs (m, k):
   the block incomplete Cholesky without fill-in, exact on a tree of pairs.  False if a D_k is
   not positive definite. */
bool FixHydroImplicitSF::factor_dilu()
{
  const int nlocal = atom->nlocal;
  double A[36], scaled[36];
  for (int k = 0; k < nlocal; k++) {
    if (!cholesky6(&block_factor[36 * k])) return false;
    const double *inverse = &block_inverse[36 * k];
    inverse_from_cholesky6(&block_factor[36 * k], &block_inverse[36 * k]);
    for (int q = by_lo_start[k]; q < by_lo_start[k + 1]; q++) {
      dense_coupling(by_lo[q], A);
      // scaled = D_k^-1 A, then D_hi -= A^T scaled
      for (int a = 0; a < 6; a++)
        for (int b = 0; b < 6; b++) {
          double sum = 0.0;
          for (int m = 0; m < 6; m++) sum += inverse[6 * a + m] * A[6 * m + b];
          scaled[6 * a + b] = sum;
        }
      double *D = &block_factor[36 * static_cast<size_t>(by_lo[q].hi)];
      for (int a = 0; a < 6; a++)
        for (int b = 0; b < 6; b++) {
          double sum = 0.0;
          for (int m = 0; m < 6; m++) sum += A[6 * m + a] * scaled[6 * m + b];
          D[6 * a + b] -= sum;
        }
    }
  }
  return true;
}

/* z = M^-1 r: block Jacobi (z = D^-1 r) or, with couplings, the dilu sweeps
   (D + L) y = r, then z = y - D^-1 L^T z from the last atom back.  Returns r.z and sets
   largest = max |z_k|, the velocity error estimate the solve stops on (both over all ranks). */
double FixHydroImplicitSF::apply_preconditioner(const std::vector<double> &r, std::vector<double> &z,
                                               double &largest) const
{
  const int nlocal = atom->nlocal;
  const bool sweeps = !by_lo.empty();
  double acc[6], term[6];
  for (int i = 0; i < nlocal; i++) {
    const double *ri = &r[6 * i];
    for (int a = 0; a < 6; a++) acc[a] = ri[a];
    if (sweeps)
      for (int q = by_hi_start[i]; q < by_hi_start[i + 1]; q++) {
        apply_coupling(by_hi[q], &z[6 * by_hi[q].lo], term, true);
        for (int a = 0; a < 6; a++) acc[a] -= term[a];
      }
    multiply6(&block_inverse[36 * i], acc, &z[6 * i]);
  }
  if (sweeps)
    for (int i = nlocal - 1; i >= 0; i--) {
      for (int a = 0; a < 6; a++) acc[a] = 0.0;
      for (int q = by_lo_start[i]; q < by_lo_start[i + 1]; q++) {
        apply_coupling(by_lo[q], &z[6 * by_lo[q].hi], term, false);
        for (int a = 0; a < 6; a++) acc[a] += term[a];
      }
      // z_i = y_i - D_i^-1 (L^T z)_i
      multiply6(&block_inverse[36 * i], acc, term);
      for (int a = 0; a < 6; a++) z[6 * i + a] -= term[a];
    }
  double rz = 0.0;
  largest = 0.0;
  const size_t size = 6 * static_cast<size_t>(nlocal);
  for (size_t k = 0; k < size; k++) {
    rz += r[k] * z[k];
    largest = std::max(largest, std::fabs(z[k]));
  }
  largest = global_max(largest);
  return global_sum(rz);
}

/* Local solves.  With the block preconditioner the error of a step's solve is, after a few
   iterations, left on a few atoms around a contact event (a contact made or broken): global
   iterations would go on over every atom for them.  Once at most `local` x N atoms have
   |z_i| > tol and the largest is above LOCAL_GAIN x tol (below it one more global iteration
   costs less than a local solve's passes over the pairs), the system restricted to those atoms and their pair neighbours (the patch),
   A_PP d = r_P with the other atoms held, is solved by CG on the patch (the preconditioner
   restricted to it: its diagonal blocks and the couplings within the patch, still symmetric
   positive definite) to LOCAL_TOLERANCE x tol; the solution moves by d, the residual by -A d,
   and the global CG restarts from there.  The stopping rule (|z| <= tol everywhere) is
   unchanged; only where the work is done changes.  Each rank solves its own patch; the
   patch's partners on other ranks are held. */

// atoms with a component of z above tol
int FixHydroImplicitSF::atoms_above_tolerance(const std::vector<double> &z) const
{
  int count = 0;
  for (int i = 0; i < atom->nlocal; i++) {
    const double *zi = &z[6 * i];
    double largest = 0.0;
    for (int k = 0; k < 6; k++) largest = std::max(largest, std::fabs(zi[k]));
    if (largest > tolerance) count++;
  }
  return count;
}

// the patch: the local atoms above tol in `precond` and their local pair partners, its pairs
// and contacts, and every atom those reach
void FixHydroImplicitSF::collect_patch()
{
  const int nlocal = atom->nlocal;
  in_patch.assign(static_cast<size_t>(vector_atoms()), 0);
  for (int i = 0; i < nlocal; i++) {
    const double *zi = &precond[6 * i];
    for (int k = 0; k < 6; k++)
      if (std::fabs(zi[k]) > tolerance) {
        in_patch[i] = CORE;
        break;
      }
  }
  for (const LubricatedPair &p : pairs) {
    if (p.j >= nlocal) continue;
    if (in_patch[p.i] == CORE && !in_patch[p.j]) in_patch[p.j] = PATCH;
    if (in_patch[p.j] == CORE && !in_patch[p.i]) in_patch[p.i] = PATCH;
  }
  patch_atoms.clear();
  for (int i = 0; i < nlocal; i++)
    if (in_patch[i]) {
      in_patch[i] = PATCH;
      patch_atoms.push_back(i);
    }
  const auto member = [this](int i) { return in_patch[i] == PATCH; };
  patch_pairs.clear();
  reached_atoms = patch_atoms;
  const auto reach = [this](int i) {
    if (!in_patch[i]) {
      in_patch[i] = REACHED;
      reached_atoms.push_back(i);
    }
  };
  for (size_t q = 0; q < pairs.size(); q++)
    if (member(pairs[q].i) || member(pairs[q].j)) {
      patch_pairs.push_back(static_cast<int>(q));
      reach(pairs[q].i);
      reach(pairs[q].j);
    }
  patch_contacts.clear();
  for (int q : separate_contacts)
    if (member(contacts[q].i) || member(contacts[q].j)) patch_contacts.push_back(q);
}

// out = A in on the reached atoms, for `in` zero outside the patch (out elsewhere untouched)
void FixHydroImplicitSF::patch_product(const std::vector<double> &in, std::vector<double> &out)
{
  for (int i : reached_atoms)
    for (int k = 0; k < 6; k++) out[6 * static_cast<size_t>(i) + k] = 0.0;
  for (int i : patch_atoms) set_self_product(i, in, out);
  add_pair_products(in, out, &patch_pairs, &patch_contacts);
}

/* z = M_P^-1 r on the patch: the preconditioner's sweeps over the patch atoms and the couplings
   within it; returns max |z| over the patch. */
double FixHydroImplicitSF::patch_preconditioner(const std::vector<double> &r, std::vector<double> &z) const
{
  const bool sweeps = !by_lo.empty();
  double acc[6], term[6];
  for (int i : patch_atoms) {
    for (int a = 0; a < 6; a++) acc[a] = r[6 * i + a];
    if (sweeps)
      for (int q = by_hi_start[i]; q < by_hi_start[i + 1]; q++) {
        if (in_patch[by_hi[q].lo] != PATCH) continue;
        apply_coupling(by_hi[q], &z[6 * by_hi[q].lo], term, true);
        for (int a = 0; a < 6; a++) acc[a] -= term[a];
      }
    multiply6(&block_inverse[36 * i], acc, &z[6 * i]);
  }
  if (sweeps)
    for (auto it = patch_atoms.rbegin(); it != patch_atoms.rend(); ++it) {
      const int i = *it;
      for (int a = 0; a < 6; a++) acc[a] = 0.0;
      for (int q = by_lo_start[i]; q < by_lo_start[i + 1]; q++) {
        if (in_patch[by_lo[q].hi] != PATCH) continue;
        apply_coupling(by_lo[q], &z[6 * by_lo[q].hi], term, false);
        for (int a = 0; a < 6; a++) acc[a] += term[a];
      }
      multiply6(&block_inverse[36 * i], acc, term);
      for (int a = 0; a < 6; a++) z[6 * i + a] -= term[a];
    }
  double largest = 0.0;
  for (int i : patch_atoms)
    for (int a = 0; a < 6; a++) largest = std::max(largest, std::fabs(z[6 * i + a]));
  return largest;
}

/* One local solve (see above): moves `solution` and `residual`; returns its work, patch atoms
   times iterations.  On several ranks each solves its own patch (a pair with a partner on
   another rank is then not in its local operator) and only the final product A d is collective. */
double FixHydroImplicitSF::local_solve()
{
  collect_patch();
  const size_t size = 6 * static_cast<size_t>(vector_atoms());
  for (std::vector<double> *v : {&local_step, &local_product, &local_residual, &local_precond, &local_direction})
    if (v->size() != size) v->assign(size, 0.0);
  const auto patch_dot = [this](const std::vector<double> &a, const std::vector<double> &b) {
    double sum = 0.0;
    for (int i : patch_atoms)
      for (int k = 0; k < 6; k++) sum += a[6 * i + k] * b[6 * i + k];
    return sum;
  };
  for (int i : patch_atoms)
    for (int k = 0; k < 6; k++) local_residual[6 * i + k] = residual[6 * i + k];
  double largest = patch_preconditioner(local_residual, local_precond);
  for (int i : patch_atoms)
    for (int k = 0; k < 6; k++) local_direction[6 * i + k] = local_precond[6 * i + k];
  double rz = patch_dot(local_residual, local_precond);
  int iterations = 0;
  while (largest > LOCAL_TOLERANCE * tolerance && iterations < MAX_LOCAL_ITERATIONS && rz > 0.0) {
    patch_product(local_direction, local_product);
    const double alpha = rz / patch_dot(local_direction, local_product);
    for (int i : patch_atoms)
      for (int k = 0; k < 6; k++) {
        local_step[6 * i + k] += alpha * local_direction[6 * i + k];
        local_residual[6 * i + k] -= alpha * local_product[6 * i + k];
      }
    largest = patch_preconditioner(local_residual, local_precond);
    const double rz_new = patch_dot(local_residual, local_precond);
    const double beta = rz_new / rz;
    rz = rz_new;
    for (int i : patch_atoms)
      for (int k = 0; k < 6; k++)
        local_direction[6 * i + k] = local_precond[6 * i + k] + beta * local_direction[6 * i + k];
    iterations++;
  }
  // solution += d, residual -= A d: on one rank over the reached atoms; on several with every
  // pair, since a pair between ranks is listed on one of them only and the other rank's d
  // reaches it through the ghosts
  for (int i : patch_atoms)
    for (int k = 0; k < 6; k++) solution[6 * i + k] += local_step[6 * i + k];
  if (distributed) {
    apply_operator(local_step, local_product);
    for (size_t k = 0; k < 6 * static_cast<size_t>(atom->nlocal); k++) residual[k] -= local_product[k];
    std::fill(local_product.begin(), local_product.end(), 0.0);
    std::fill(local_step.begin(), local_step.end(), 0.0);
  } else {
    patch_product(local_step, local_product);
    for (int i : reached_atoms)
      for (int k = 0; k < 6; k++) residual[6 * i + k] -= local_product[6 * i + k];
  }
  // leave the local vectors zero for the next patch
  for (std::vector<double> *v : {&local_step, &local_product, &local_residual, &local_precond, &local_direction})
    for (int i : reached_atoms)
      for (int k = 0; k < 6; k++) (*v)[6 * static_cast<size_t>(i) + k] = 0.0;
  return static_cast<double>(iterations) * static_cast<double>(patch_atoms.size());
}

/* Right-hand side: inertia of the old velocities (relative to the flow here, in
   `old_velocity`), external forces and torques, the lubrication forcing of the imposed strain
   and, with `contacts`, the explicit contact forces (normal springs, sticking springs at
   their last stretch plus the imposed flow's slip over the step, sliding contacts' Coulomb
   forces). */
void FixHydroImplicitSF::assemble_rhs(const double E[3][3])
{
  const int nlocal = atom->nlocal;
  double **f = atom->f;
  double **torque = atom->torque;
  const double *radius = atom->radius;
  const double *rmass = atom->rmass;
  std::fill(rhs.begin() + 6 * static_cast<size_t>(nlocal), rhs.end(), 0.0);
  for (int i = 0; i < nlocal; i++) {
    const double a = radius[i];
    const double m_dt = rmass[i] / dtv;
    const double i_dt = INERTIA * rmass[i] * a * a / dtv;
    for (int k = 0; k < 3; k++) {
      rhs[6 * i + k] = m_dt * old_velocity[6 * i + k] + f[i][k];
      rhs[6 * i + 3 + k] = i_dt * old_velocity[6 * i + 3 + k] + torque[i][k];
    }
  }
  const double zero[3] = {0.0, 0.0, 0.0};
  double fi[3], ti[3], tj[3];
  for (const LubricatedPair &p : pairs) {
    double du[3];
    for (int a = 0; a < 3; a++) du[a] = E[a][0] * p.del[0] + E[a][1] * p.del[1] + E[a][2] * p.del[2];
    SuspensionFabric::lubrication_forces(p.R, du, zero, zero, fi, ti, tj);
    for (int k = 0; k < 3; k++) {
      rhs[6 * p.i + k] += fi[k];
      rhs[6 * p.i + 3 + k] += ti[k];
    }
    if (p.add_to_j)
      for (int k = 0; k < 3; k++) {
        rhs[6 * p.j + k] -= fi[k];
        rhs[6 * p.j + 3 + k] += tj[k];
      }
  }
  for (const SuspensionFabric::Contact &c : contacts) {
    double ft[3];
    if (c.sticking) {
      for (int k = 0; k < 3; k++) ft[k] = -kt * (c.spring[k] + dtv * c.flow_slip[k]);
    } else if (newton_contacts) {
      // the linearised Coulomb force at zero relative velocity: -bound t^ less the stiffness
      // across t^ times the trial spring without the solved slip
      double t[3];
      for (int k = 0; k < 3; k++) t[k] = c.spring[k] + dtv * c.flow_slip[k];
      const double along = SuspensionFabric::dot3(t, c.sliding_direction);
      for (int k = 0; k < 3; k++)
        ft[k] = c.sliding_force[k] - c.sliding_stiffness * (t[k] - along * c.sliding_direction[k]);
    } else {
      for (int k = 0; k < 3; k++) ft[k] = c.sliding_force[k];
    }
    // the normal spring at its current overlap, or (implicit) less the imposed flow's separation
    const double normal = c.pressed ? kn * (c.overlap - dtv * c.flow_approach) : c.normal_force;
    SuspensionFabric::contact_torques(c, ft, ti, tj);
    for (int k = 0; k < 3; k++) {
      const double F = normal * c.n[k] + ft[k];
      rhs[6 * c.i + k] += F;
      rhs[6 * c.i + 3 + k] += ti[k];
      rhs[6 * c.j + k] -= F;
      rhs[6 * c.j + 3 + k] += tj[k];
    }
  }
  sum_ghosts(rhs, 6);
}

/* guess linear|quadratic: the first iterate of the step's solve, from each atom's old relative
   velocities u_n (old_velocity) and those of the steps before, u_{n-1} and u_{n-2}:
   u_n + (u_n - u_{n-1}) (linear) or 3 u_n - 3 u_{n-1} + u_{n-2} (quadratic), as far back as the
   atom's history reaches (a fresh fix, or one continued from a restart file, starts from u_n);
   then the history moves on by one step.  At a step short against the time over which the
   velocities change (the stiff contacts' small dt) this starts CG much nearer the solution.
   Only the start moves: the contact states are still classified from u_n, the right-hand side
   keeps the inertia of u_n, and the solve stops at the same tol. */
void FixHydroImplicitSF::extrapolate_first_iterate()
{
  for (int i = 0; i < atom->nlocal; i++) {
    double *history = velocity_history[i];
    const int known = std::min(guess_order, static_cast<int>(history[HISTORY_KNOWN]));
    const double *now = &old_velocity[6 * i];
    double *first = &solution[6 * i];
    for (int k = 0; k < 6; k++) {
      if (known == 2) first[k] = 3.0 * now[k] - 3.0 * history[k] + history[6 + k];
      else if (known == 1) first[k] = now[k] + (now[k] - history[k]);
      history[6 + k] = history[k];
      history[k] = now[k];
    }
    history[HISTORY_KNOWN] = std::min(2.0, history[HISTORY_KNOWN] + 1.0);
  }
}

/* Preconditioned conjugate gradients from the current `solution`; returns the iterations. */
int FixHydroImplicitSF::conjugate_gradients()
{
  const size_t size = 6 * static_cast<size_t>(atom->nlocal);
  build_operator();
  apply_operator(solution, product);
  for (size_t k = 0; k < size; k++) residual[k] = rhs[k] - product[k];
  double error_now;
  double rz = apply_preconditioner(residual, precond, error_now);
  direction = precond;
  int iteration = 0, local_rounds = 0;
  while (error_now > tolerance) {
    if (iteration == max_iterations || !std::isfinite(error_now))
      error->all(FLERR,
                 "fix hydro/implicit/sf: conjugate gradients did not converge at step {}: velocity "
                 "error {:.3g} > tol {:.3g} after {} iterations; reduce dt or raise maxiter",
                 update->ntimestep, error_now, tolerance, iteration);
    // the error left sits on a few atoms (a contact event): solve there, then restart CG
    if (local_fraction > 0.0 && local_rounds < MAX_LOCAL_ROUNDS && error_now > LOCAL_GAIN * tolerance &&
        global_sum(atoms_above_tolerance(precond)) <= local_fraction * static_cast<double>(atom->natoms)) {
      total_local_work += local_solve();
      local_rounds++;
      rz = apply_preconditioner(residual, precond, error_now);
      direction = precond;
      continue;
    }
    apply_operator(direction, product);
    const double alpha = rz / global_sum(local_dot(direction, product, size));
    for (size_t k = 0; k < size; k++) {
      solution[k] += alpha * direction[k];
      residual[k] -= alpha * product[k];
    }
    const double rz_new = apply_preconditioner(residual, precond, error_now);
    const double beta = rz_new / rz;
    rz = rz_new;
    for (size_t k = 0; k < size; k++) direction[k] = precond[k] + beta * direction[k];
    iteration++;
  }
  if (verify) {    // the residual recomputed from the solution, not the one CG carried
    apply_operator(solution, product);
    for (size_t k = 0; k < size; k++) residual[k] = rhs[k] - product[k];
    double true_error;
    apply_preconditioner(residual, precond, true_error);
    if (true_error > VERIFY_MARGIN * tolerance)
      error->all(FLERR, "fix hydro/implicit/sf: verify: the recomputed velocity error {:.3g} of the solve at "
                        "step {} exceeds tol {:.3g}",
                 true_error, update->ntimestep, tolerance);
  }
  exchange_ghosts(solution, 6);
  last_error = error_now;
  return iteration;
}

void FixHydroImplicitSF::final_integrate()
{
  const int nlocal = atom->nlocal;
  double **x = atom->x;
  double **v = atom->v;
  double **omega = atom->omega;

  const SuspensionFabric::ImposedFlow flow(domain);
  const double *W = flow.omega;
  const auto &E = flow.strain;

  // a new neighbour list may give a pair to another rank: every rank gets every spring
  if (distributed && own_contacts && neighbor->ago == 0) {
    const std::vector<double> records = gathered_springs();
    load_springs(records.data(), records.size() / SPRING_RECORD);
  }
  collect_pairs(E);
  const size_t size = 6 * static_cast<size_t>(vector_atoms());
  // every entry of these buffers is written before it is read
  rhs.resize(size);
  residual.resize(size);
  precond.resize(size);
  direction.resize(size);
  product.resize(size);

  // the old relative velocities: inertia on the right-hand side, and the first guess
  relative_velocities(flow);
  old_velocity = solution;
  if (own_contacts) classify_contacts();
  assemble_rhs(E);
  if (guess_order > 0) extrapolate_first_iterate();

  // the block-Jacobi preconditioner is rebuilt every PRECONDITIONER_AGE steps and whenever the
  // local atoms were reordered (sorting): it only steers the convergence, the solution is that
  // of the current operator to within tol
  bool reordered = preconditioner_tags.size() != static_cast<size_t>(nlocal);
  for (int i = 0; i < nlocal && !reordered; i++) reordered = preconditioner_tags[i] != atom->tag[i];
  // the rebuild communicates: all ranks rebuild when one must
  if (global_max(reordered ? 1.0 : 0.0) > 0.0 || update->ntimestep % PRECONDITIONER_AGE == 0) {
    build_preconditioner();
    preconditioner_tags.assign(atom->tag, atom->tag + nlocal);
  }
  int iterations = conjugate_gradients();
  int passes = 1;
  if (own_contacts) {
    const int max_passes = newton_contacts ? MAX_CONTACT_PASSES_NEWTON : MAX_CONTACT_PASSES;
    while (passes < max_passes) {
      const int released = static_cast<int>(
          global_sum(newton_contacts ? relinearise_contacts() : release_violated_springs()));
      if (released == 0) break;
      total_released += released;
      assemble_rhs(E);
      iterations += conjugate_gradients();
      passes++;
    }
    finish_contacts(true);
  }

  double u[3];
  for (int i = 0; i < nlocal; i++) {
    flow.velocity(x[i], u);
    for (int k = 0; k < 3; k++) {
      v[i][k] = solution[6 * i + k] + u[k];
      omega[i][k] = solution[6 * i + 3 + k] + W[k];
    }
  }
  steps++;
  total_iterations += iterations;
  total_passes += passes;
  last_iterations = iterations;
  // the lubrication virial and the fix's vector take a pass over the pairs and a global sum: made
  // on the steps LAMMPS tallies the virial for (output), else when the vector is read
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) step_strain[a][b] = E[a][b];
  tallied_step = -1;
  if (update->vflag_global == update->ntimestep || controlled_stress > 0.0) tally_step(step_strain);
  if (controlled_stress > 0.0) follow_stress(step_strain);
}

/* The shear stress along the imposed flow of the tallied step, sigma:E / gammadot (stress
   control above): eta_b gammadot plus minus the particles' pressure tensor (contact part
   symmetrised with the summed torque, as suspension_fabric.analysis.stress does) contracted
   with E / gammadot; summed over the ranks. */
double FixHydroImplicitSF::flow_shear_stress(const double E[3][3]) const
{
  double local[9];
  for (int k = 0; k < 6; k++) local[k] = contact_virial[k] + lubrication_virial[k];
  for (int k = 0; k < 3; k++) local[6 + k] = contact_torque[k];
  double total[9];
  MPI_Allreduce(local, total, 9, MPI_DOUBLE, MPI_SUM, world);
  // symmetric off-diagonals xy, xz, yz of the contact virial: + T_z / 2, - T_y / 2, + T_x / 2
  total[3] += 0.5 * total[8];
  total[4] -= 0.5 * total[7];
  total[5] += 0.5 * total[6];
  const double volume = domain->xprd * domain->yprd * domain->zprd;
  const double pressure_e = (total[0] * E[0][0] + total[1] * E[1][1] + total[2] * E[2][2] +
                             2.0 * (total[3] * E[0][1] + total[4] * E[0][2] + total[5] * E[1][2])) / volume;
  double ee = 0.0;
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) ee += E[a][b] * E[a][b];
  const double rate = std::sqrt(2.0 * ee);
  if (!(rate > 0.0)) error->all(FLERR, "fix hydro/implicit/sf: critical_load_stress needs an imposed shear");
  return background_viscosity * rate - pressure_e / rate;
}

// critical_load_stress: the critical load of the next step from the stress of this one
void FixHydroImplicitSF::follow_stress(const double E[3][3])
{
  shear_stress = flow_shear_stress(E);
  reported[HydroVector::SHEAR_STRESS - 1] = shear_stress;    // entry 32 keeps the load this step used
  // a stress below the solvent's (the contacts pushing against a reversed flow) has no finite rate
  // to hold it: the load follows the solvent's stress, the largest rate the stress can drive
  double ee = 0.0;
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) ee += E[a][b] * E[a][b];
  const double floor = background_viscosity * std::sqrt(2.0 * ee);
  if (shear_stress < floor) floored_steps++;
  critical_load = load_radius * load_radius * std::max(shear_stress, floor) / controlled_stress;
}

// the virial and the fix's vector of the step just solved (E: its imposed strain rate)
void FixHydroImplicitSF::tally_step(const double E[3][3])
{
  tally_virial(E);
  report_vector();
  tallied_step = update->ntimestep;
}

/* Virial of the lubrication forces at the velocities in `solution`: sum over pairs of
   (x_i - x_j) F_ij, symmetrised (the tangential forces make it asymmetric), in LAMMPS order
   xx yy zz xy xz yz, half of it for a pair seen from both sides (newton off across a
   periodic boundary).  The fix's virial adds the contact virial of finish_contacts.  Beside
   it, minus the summed pair stresslets (stresslet_virial: divided by the volume, a pressure
   tensor like the virial's). */
void FixHydroImplicitSF::tally_virial(const double E[3][3])
{
  for (double &value : lubrication_virial) value = 0.0;
  for (double &value : stresslet_virial) value = 0.0;
  double fi[3], ti[3], tj[3], S[6];
  for (const LubricatedPair &p : pairs) {
    const double *ui = &solution[6 * p.i], *uj = &solution[6 * p.j];
    double du[3];
    for (int a = 0; a < 3; a++)
      du[a] = ui[a] - uj[a] + E[a][0] * p.del[0] + E[a][1] * p.del[1] + E[a][2] * p.del[2];
    SuspensionFabric::lubrication_forces(p.R, du, ui + 3, uj + 3, fi, ti, tj);
    const double weight = p.add_to_j ? 1.0 : 0.5;
    lubrication_virial[0] += weight * p.del[0] * fi[0];
    lubrication_virial[1] += weight * p.del[1] * fi[1];
    lubrication_virial[2] += weight * p.del[2] * fi[2];
    lubrication_virial[3] += weight * 0.5 * (p.del[0] * fi[1] + p.del[1] * fi[0]);
    lubrication_virial[4] += weight * 0.5 * (p.del[0] * fi[2] + p.del[2] * fi[0]);
    lubrication_virial[5] += weight * 0.5 * (p.del[1] * fi[2] + p.del[2] * fi[1]);
    const double du_na[3] = {ui[0] - uj[0], ui[1] - uj[1], ui[2] - uj[2]};
    SuspensionFabric::lubrication_stresslet(p.R, lubrication->eta_f, du_na, E, ui + 3, uj + 3, S);
    for (int k = 0; k < 6; k++) stresslet_virial[k] -= weight * S[k];
  }
  for (int k = 0; k < 6; k++) virial[k] = lubrication_virial[k] + (own_contacts ? contact_virial[k] : 0.0);
}

/* 1: CG iterations of the last step (all its solves), 2: mean iterations per step since the
   fix was created, 3: velocity error |D^-1 r|_max reached in the last solve, 4-9: contact
   virial (LAMMPS order xx yy zz xy xz yz, sum (x_i - x_j)_a F_b), 10-12: summed contact torque,
   13-18: lubrication virial (symmetrised), 19: mean solves per step, 20: contacts, 21: sliding
   contacts, 22: springs released to sliding per step (mean), 23: dilu rebuilds that fell back
   to block Jacobi (not positive definite), 24-29: minus the summed pair stresslets (LAMMPS order;
   /vol is their pressure tensor), 30: local solves' work per step (mean, patch atoms x
   iterations / N), 31: frictional contacts, 32: the critical load of the last step, 33: with
   critical_load_stress the shear stress it follows (else 0), 34: the steps whose stress was below
   the solvent's (critical_load_stress).  4-12 and 20-22 are zero without
   `contacts`. */
double FixHydroImplicitSF::compute_vector(int n)
{
  if (tallied_step != update->ntimestep) tally_step(step_strain);
  return reported[n];
}

/* The global vector of the step (compute_vector's list), the same on every rank. */
void FixHydroImplicitSF::report_vector()
{
  using namespace HydroVector;
  double local[SIZE] = {};    // entry i - 1 for the vector index i
  for (int k = 0; k < 6; k++) {
    local[CONTACT_VIRIAL - 1 + k] = contact_virial[k];
    local[LUBRICATION_VIRIAL - 1 + k] = lubrication_virial[k];
    local[STRESSLET_VIRIAL - 1 + k] = stresslet_virial[k];
  }
  for (int k = 0; k < 3; k++) local[CONTACT_TORQUE - 1 + k] = contact_torque[k];
  local[CONTACTS - 1] = static_cast<double>(contacts.size());
  local[SLIDING_CONTACTS - 1] = sliding_contacts;
  local[FRICTIONAL_CONTACTS - 1] = frictional_contacts;
  local[DILU_FALLBACKS - 1] = static_cast<double>(dilu_fallbacks);
  local[MEAN_LOCAL_WORK - 1] = steps > 0 ? total_local_work / (static_cast<double>(atom->natoms) * steps) : 0.0;
  MPI_Allreduce(local, reported, SIZE, MPI_DOUBLE, MPI_SUM, world);
  // already global: the solve's figures
  const auto per_step = [this](double total) { return steps > 0 ? total / steps : 0.0; };
  reported[LAST_ITERATIONS - 1] = last_iterations;
  reported[MEAN_ITERATIONS - 1] = per_step(static_cast<double>(total_iterations));
  reported[LAST_ERROR - 1] = last_error;
  reported[MEAN_PASSES - 1] = per_step(static_cast<double>(total_passes));
  reported[MEAN_RELEASED - 1] = per_step(static_cast<double>(total_released));
  reported[CRITICAL_LOAD - 1] = critical_load;
  reported[SHEAR_STRESS - 1] = shear_stress;
  reported[FLOORED_STEPS - 1] = static_cast<double>(floored_steps);
}

/* The springs of all ranks as (smaller tag, larger tag, xi) records, on every rank. */
std::vector<double> FixHydroImplicitSF::gathered_springs() const
{
  std::vector<double> mine;
  mine.reserve(SPRING_RECORD * springs.size());
  for (const auto &entry : springs) {
    mine.push_back(static_cast<double>(entry.first >> 32));
    mine.push_back(static_cast<double>(entry.first & 0xffffffffULL));
    for (int k = 0; k < 3; k++) mine.push_back(entry.second.xi[k]);
  }
  if (!distributed) return mine;
  const int nprocs = comm->nprocs;
  const int count = static_cast<int>(mine.size());
  std::vector<int> counts(nprocs), offsets(nprocs, 0);
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, world);
  for (int p = 1; p < nprocs; p++) offsets[p] = offsets[p - 1] + counts[p - 1];
  std::vector<double> all(static_cast<size_t>(offsets[nprocs - 1] + counts[nprocs - 1]));
  MPI_Allgatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), offsets.data(), MPI_DOUBLE, world);
  return all;
}

void FixHydroImplicitSF::load_springs(const double *records, size_t count)
{
  springs.clear();
  springs.reserve(count);
  for (size_t e = 0; e < count; e++) {
    const double *record = &records[SPRING_RECORD * e];
    const auto key = (static_cast<unsigned long long>(record[0]) << 32) |
        static_cast<unsigned long long>(record[1]);
    Spring &stored = springs[key];
    for (int k = 0; k < 3; k++) stored.xi[k] = record[2 + k];
  }
}

/* Global restart state: the springs of all ranks, their count then their records, so that a
   run written on any number of ranks continues on any other. */
void FixHydroImplicitSF::write_restart(FILE *fp)
{
  const std::vector<double> records = gathered_springs();
  if (comm->me == 0) {
    const double count = static_cast<double>(records.size() / SPRING_RECORD);
    const int size = static_cast<int>((records.size() + 1) * sizeof(double));
    fwrite(&size, sizeof(int), 1, fp);
    fwrite(&count, sizeof(double), 1, fp);
    fwrite(records.data(), sizeof(double), records.size(), fp);
  }
}

void FixHydroImplicitSF::restart(char *buf)
{
  const double *list = reinterpret_cast<const double *>(buf);
  load_springs(list + 1, static_cast<size_t>(list[0]));
}

/* Atoms with entries in the solver's vectors: the local ones and, on several ranks, the ghosts
   (on one rank every pair acts on its partner's owner, so the vectors stop at the local atoms). */
int FixHydroImplicitSF::vector_atoms() const
{
  return atom->nlocal + (distributed ? atom->nghost : 0);
}

/* Ghost communication of a vector with `stride` entries per atom (6: a velocity; 36: a block).
   On one rank no pair refers to a ghost, and nothing is communicated. */
void FixHydroImplicitSF::exchange_ghosts(std::vector<double> &values, int stride)
{
  if (!distributed) return;
  comm_values = &values;
  comm_stride = stride;
  comm->forward_comm(this, stride);
}

void FixHydroImplicitSF::sum_ghosts(std::vector<double> &values, int stride)
{
  if (!distributed) return;
  comm_values = &values;
  comm_stride = stride;
  comm->reverse_comm(this, stride);
}

int FixHydroImplicitSF::pack_forward_comm(int n, int *list, double *buf, int /*pbc_flag*/, int * /*pbc*/)
{
  const double *values = comm_values->data();
  int m = 0;
  for (int q = 0; q < n; q++)
    for (int k = 0; k < comm_stride; k++) buf[m++] = values[comm_stride * static_cast<size_t>(list[q]) + k];
  return m;
}

void FixHydroImplicitSF::unpack_forward_comm(int n, int first, double *buf)
{
  double *values = comm_values->data();
  int m = 0;
  for (int i = first; i < first + n; i++)
    for (int k = 0; k < comm_stride; k++) values[comm_stride * static_cast<size_t>(i) + k] = buf[m++];
}

int FixHydroImplicitSF::pack_reverse_comm(int n, int first, double *buf)
{
  const double *values = comm_values->data();
  int m = 0;
  for (int i = first; i < first + n; i++)
    for (int k = 0; k < comm_stride; k++) buf[m++] = values[comm_stride * static_cast<size_t>(i) + k];
  return m;
}

void FixHydroImplicitSF::unpack_reverse_comm(int n, int *list, double *buf)
{
  double *values = comm_values->data();
  int m = 0;
  for (int q = 0; q < n; q++)
    for (int k = 0; k < comm_stride; k++) values[comm_stride * static_cast<size_t>(list[q]) + k] += buf[m++];
}

// guess linear|quadratic: the per-atom history (velocity_history), moved as LAMMPS moves the atoms
void FixHydroImplicitSF::grow_arrays(int nmax)
{
  memory->grow(velocity_history, nmax, HISTORY_COLUMNS, "hydro/implicit/sf:velocity_history");
  array_atom = velocity_history;
}

void FixHydroImplicitSF::copy_arrays(int i, int j, int /*delflag*/)
{
  std::copy(velocity_history[i], velocity_history[i] + HISTORY_COLUMNS, velocity_history[j]);
}

int FixHydroImplicitSF::pack_exchange(int i, double *buf)
{
  std::copy(velocity_history[i], velocity_history[i] + HISTORY_COLUMNS, buf);
  return HISTORY_COLUMNS;
}

int FixHydroImplicitSF::unpack_exchange(int nlocal, double *buf)
{
  std::copy(buf, buf + HISTORY_COLUMNS, velocity_history[nlocal]);
  return HISTORY_COLUMNS;
}

double FixHydroImplicitSF::memory_usage()
{
  return velocity_history ? static_cast<double>(atom->nmax) * HISTORY_COLUMNS * sizeof(double) : 0.0;
}

double FixHydroImplicitSF::global_sum(double local) const
{
  if (!distributed) return local;
  double total;
  MPI_Allreduce(&local, &total, 1, MPI_DOUBLE, MPI_SUM, world);
  return total;
}

double FixHydroImplicitSF::global_max(double local) const
{
  if (!distributed) return local;
  double largest;
  MPI_Allreduce(&local, &largest, 1, MPI_DOUBLE, MPI_MAX, world);
  return largest;
}

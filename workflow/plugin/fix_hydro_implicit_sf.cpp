/* fix <ID> all hydro/implicit/sf [tol <t>] [maxiter <n>]

   Time integration of spheres whose hydrodynamic forces, the one-body Stokes drag and the
   pairwise lubrication of pair_style lubricate/sf, are taken implicitly; every other force
   (the granular contacts) is explicit.  Replaces fix nve/sphere + fix stokes/sf; needs
   `pair_style hybrid/overlay granular lubricate/sf <eta_f> <delta> <h_out> implicit`, whose
   parameters and neighbour list it uses.

   With u, w the velocities relative to the imposed flow (u = v - u_inf(x), w = omega -
   Omega_inf) and E the imposed strain rate, the hydrodynamic force and torque are linear,
   F_h = -R (u, w) + F_E, with R = R_drag + sum over pairs R_pair symmetric positive
   semi-definite and F_E the lubrication force on particles that follow the imposed flow
   (the pair forces at du = E (x_i - x_j), w = 0).  Each step (symplectic Euler for the
   contacts, backward Euler for the hydrodynamics):
     x_{n+1} = x_n + dt v_n                                       (initial_integrate)
     F_c = contact forces at x_{n+1}                              (pair granular)
     (M/dt + R) (u, w)_{n+1} = (M/dt) (u, w)_old + F_c + F_E      (final_integrate)
   where (u, w)_old are the old velocities relative to the flow at x_{n+1}.  The resistance
   no longer limits dt (any dt is stable for it); the contact springs do (explicit).
   The linear system is solved matrix-free by conjugate gradients over the pair list with a
   6x6 block-Jacobi preconditioner (rebuilt every 10 steps and after the atoms are re-sorted),
   warm-started from the old velocities, until the largest
   component of D^-1 r (a velocity, in units of gammadot d) is below `tol` (default 1e-5).
   A solve that does not converge within `maxiter` (default 1000) stops the run with an error.

   The symmetrised lubrication virial sum (x_i - x_j) F_ij of the solved velocities is the fix's virial
   (compute pressure ... fix, and the total pressure); the drag adds none (see README.md).
   One MPI rank only: parallelism comes from running seeds and angles side by side. */

#include "fix_hydro_implicit_sf.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "modify.h"
#include "neigh_list.h"
#include "update.h"
#include "utils.h"

#include "imposed_flow.h"
#include "pair_lubricate_sf.h"

#include <cmath>
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

// Resistance blocks a pair adds to the diagonal 6x6 block of one of its particles:
// sign_b = +1 for i (pump YBi), -1 for j (pump YBj).
void add_pair_block(const SuspensionFabric::PairResistance &R, double yb, double yc,
                    double sign_b, double *block)
{
  const double *n = R.n;
  const double N[3][3] = {{0.0, -n[2], n[1]}, {n[2], 0.0, -n[0]}, {-n[1], n[0], 0.0}};
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) {
      const double nn = n[a] * n[b];
      const double proj = (a == b ? 1.0 : 0.0) - nn;
      block[6 * a + b] += R.X * nn + R.YA * proj;
      block[6 * a + 3 + b] += sign_b * yb * N[a][b];
      block[6 * (3 + a) + b] -= sign_b * yb * N[a][b];
      block[6 * (3 + a) + 3 + b] += yc * proj;
    }
}

double dot(const std::vector<double> &a, const std::vector<double> &b)
{
  double s = 0.0;
  for (size_t k = 0; k < a.size(); k++) s += a[k] * b[k];
  return s;
}

constexpr double INERTIA = 0.4;    // moment of inertia of a solid sphere / (m a^2)
constexpr bigint PRECONDITIONER_AGE = 10;    // steps between preconditioner rebuilds at most
}    // namespace

FixHydroImplicitSF::FixHydroImplicitSF(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), tolerance(1.0e-5), max_iterations(1000), dtv(0.0),
    lubrication(nullptr), steps(0), total_iterations(0), last_iterations(0), last_error(0.0)
{
  int iarg = 3;
  while (iarg < narg) {
    if (strcmp(arg[iarg], "tol") == 0 && iarg + 1 < narg) {
      tolerance = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      if (!(tolerance > 0.0)) error->all(FLERR, "fix hydro/implicit/sf: tol must be > 0");
    } else if (strcmp(arg[iarg], "maxiter") == 0 && iarg + 1 < narg) {
      max_iterations = utils::inumeric(FLERR, arg[iarg + 1], false, lmp);
      if (max_iterations < 1) error->all(FLERR, "fix hydro/implicit/sf: maxiter must be >= 1");
    } else {
      error->all(FLERR, "Illegal fix hydro/implicit/sf keyword '{}': expected tol <t> or maxiter <n>",
                 arg[iarg]);
    }
    iarg += 2;
  }
  time_integrate = 1;
  virial_global_flag = 1;
  thermo_virial = 1;
  vector_flag = 1;
  size_vector = 3;
  global_freq = 1;
  extvector = 0;
  for (double &v : virial) v = 0.0;
}

int FixHydroImplicitSF::setmask()
{
  return INITIAL_INTEGRATE | FINAL_INTEGRATE;
}

void FixHydroImplicitSF::init()
{
  if (comm->nprocs > 1)
    error->all(FLERR, "fix hydro/implicit/sf runs on one MPI rank only ({} requested); run seeds "
                      "and angles side by side for parallelism",
               comm->nprocs);
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
  dtv = update->dt;
}

void FixHydroImplicitSF::reset_dt()
{
  dtv = update->dt;
}

void FixHydroImplicitSF::setup(int /*vflag*/)
{
  // the virial of the current velocities, for output at the first step
  const SuspensionFabric::ImposedFlow flow(domain);
  double E[3][3];
  strain_rate(flow, E);
  collect_pairs();
  relative_velocities(flow);
  tally_virial(E);
}

// E = (L + L^T)/2 of the imposed flow
void FixHydroImplicitSF::strain_rate(const SuspensionFabric::ImposedFlow &flow, double E[3][3])
{
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) E[a][b] = 0.5 * (flow.grad[a][b] + flow.grad[b][a]);
}

// solution = (v - u_inf(x), omega - Omega_inf) of every local atom
void FixHydroImplicitSF::relative_velocities(const SuspensionFabric::ImposedFlow &flow)
{
  const int nlocal = atom->nlocal;
  solution.resize(6 * static_cast<size_t>(nlocal));
  double u[3];
  for (int i = 0; i < nlocal; i++) {
    flow.velocity(atom->x[i], u);
    for (int k = 0; k < 3; k++) {
      solution[6 * i + k] = atom->v[i][k] - u[k];
      solution[6 * i + 3 + k] = atom->omega[i][k] - flow.omega[k];
    }
  }
}

void FixHydroImplicitSF::initial_integrate(int /*vflag*/)
{
  double **x = atom->x;
  double **v = atom->v;
  const int nlocal = atom->nlocal;
  for (int i = 0; i < nlocal; i++)
    for (int k = 0; k < 3; k++) x[i][k] += dtv * v[i][k];
}

void FixHydroImplicitSF::collect_pairs()
{
  pairs.clear();
  const NeighList *list = lubrication->list;
  double **x = atom->x;
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
      p.j = (j < nlocal) ? j : atom->map(tag[j]);
      if (p.j < 0 || p.j >= nlocal)
        error->one(FLERR, "fix hydro/implicit/sf: no local owner of ghost atom {}", tag[j]);
      p.add_to_j = newton_pair || j < nlocal;
      pairs.push_back(p);
    }
  }
}

void FixHydroImplicitSF::apply_operator(const std::vector<double> &in, std::vector<double> &out) const
{
  const int nlocal = atom->nlocal;
  const double *radius = atom->radius;
  const double *rmass = atom->rmass;
  const double pi_eta = M_PI * lubrication->eta_f;
  for (int i = 0; i < nlocal; i++) {
    const double a = radius[i];
    const double translation = rmass[i] / dtv + 6.0 * pi_eta * a;
    const double rotation = INERTIA * rmass[i] * a * a / dtv + 8.0 * pi_eta * a * a * a;
    for (int k = 0; k < 3; k++) {
      out[6 * i + k] = translation * in[6 * i + k];
      out[6 * i + 3 + k] = rotation * in[6 * i + 3 + k];
    }
  }
  double fi[3], ti[3], tj[3];
  for (const LubricatedPair &p : pairs) {
    const double *ui = &in[6 * p.i], *uj = &in[6 * p.j];
    const double du[3] = {ui[0] - uj[0], ui[1] - uj[1], ui[2] - uj[2]};
    SuspensionFabric::lubrication_forces(p.R, du, ui + 3, uj + 3, fi, ti, tj);
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
}

void FixHydroImplicitSF::build_preconditioner()
{
  const int nlocal = atom->nlocal;
  const double *radius = atom->radius;
  const double *rmass = atom->rmass;
  const double pi_eta = M_PI * lubrication->eta_f;
  block_factor.assign(36 * static_cast<size_t>(nlocal), 0.0);
  for (int i = 0; i < nlocal; i++) {
    const double a = radius[i];
    double *b = &block_factor[36 * i];
    for (int k = 0; k < 3; k++) {
      b[7 * k] = rmass[i] / dtv + 6.0 * pi_eta * a;
      b[7 * (k + 3)] = INERTIA * rmass[i] * a * a / dtv + 8.0 * pi_eta * a * a * a;
    }
  }
  for (const LubricatedPair &p : pairs) {
    add_pair_block(p.R, p.R.YBi, p.R.YCi, 1.0, &block_factor[36 * p.i]);
    if (p.add_to_j) add_pair_block(p.R, p.R.YBj, p.R.YCj, -1.0, &block_factor[36 * p.j]);
  }
  block_inverse.resize(block_factor.size());
  for (int i = 0; i < nlocal; i++) {
    if (!cholesky6(&block_factor[36 * i]))
      error->one(FLERR, "fix hydro/implicit/sf: the resistance block of atom {} is not positive "
                        "definite at step {}",
                 atom->tag[i], update->ntimestep);
    inverse_from_cholesky6(&block_factor[36 * i], &block_inverse[36 * i]);
  }
}

/* z = D^-1 r with the inverted diagonal blocks; returns r.z and sets largest = max |z_k|. */
double FixHydroImplicitSF::apply_preconditioner(const std::vector<double> &r, std::vector<double> &z,
                                               double &largest) const
{
  const int nlocal = atom->nlocal;
  double rz = 0.0;
  largest = 0.0;
  for (int i = 0; i < nlocal; i++) {
    const double *m = &block_inverse[36 * i];
    const double *ri = &r[6 * i];
    double *zi = &z[6 * i];
    for (int a = 0; a < 6; a++) {
      double s = 0.0;
      for (int b = 0; b < 6; b++) s += m[6 * a + b] * ri[b];
      zi[a] = s;
    }
  }
  const size_t size = 6 * static_cast<size_t>(nlocal);
  for (size_t k = 0; k < size; k++) {
    rz += r[k] * z[k];
    largest = std::max(largest, std::fabs(z[k]));
  }
  return rz;
}

void FixHydroImplicitSF::final_integrate()
{
  const int nlocal = atom->nlocal;
  double **x = atom->x;
  double **v = atom->v;
  double **omega = atom->omega;
  double **f = atom->f;
  double **torque = atom->torque;
  const double *radius = atom->radius;
  const double *rmass = atom->rmass;

  const SuspensionFabric::ImposedFlow flow(domain);
  const double *W = flow.omega;
  double E[3][3];
  strain_rate(flow, E);

  collect_pairs();
  const size_t size = 6 * static_cast<size_t>(nlocal);
  // every entry of these buffers is written before it is read
  rhs.resize(size);
  residual.resize(size);
  precond.resize(size);
  direction.resize(size);
  product.resize(size);

  // right-hand side: inertia of the old velocities (relative to the flow here), contact
  // forces and torques, and the lubrication forcing of the imposed strain; the old
  // relative velocities are the first guess
  relative_velocities(flow);
  for (int i = 0; i < nlocal; i++) {
    const double a = radius[i];
    const double m_dt = rmass[i] / dtv;
    const double i_dt = INERTIA * rmass[i] * a * a / dtv;
    for (int k = 0; k < 3; k++) {
      rhs[6 * i + k] = m_dt * solution[6 * i + k] + f[i][k];
      rhs[6 * i + 3 + k] = i_dt * solution[6 * i + 3 + k] + torque[i][k];
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

  // preconditioned conjugate gradients; the block-Jacobi preconditioner is rebuilt every
  // PRECONDITIONER_AGE steps and whenever the local atoms were reordered (sorting): it only
  // steers the convergence, the solution is that of the current resistance to within tol
  bool reordered = preconditioner_tags.size() != static_cast<size_t>(nlocal);
  for (int i = 0; i < nlocal && !reordered; i++) reordered = preconditioner_tags[i] != atom->tag[i];
  if (reordered || update->ntimestep % PRECONDITIONER_AGE == 0) {
    build_preconditioner();
    preconditioner_tags.assign(atom->tag, atom->tag + nlocal);
  }
  apply_operator(solution, product);
  for (size_t k = 0; k < size; k++) residual[k] = rhs[k] - product[k];
  double error_now;
  double rz = apply_preconditioner(residual, precond, error_now);
  direction = precond;
  int iteration = 0;
  while (error_now > tolerance) {
    if (iteration == max_iterations || !std::isfinite(error_now))
      error->one(FLERR,
                 "fix hydro/implicit/sf: conjugate gradients did not converge at step {}: velocity "
                 "error {:.3g} > tol {:.3g} after {} iterations; reduce dt or raise maxiter",
                 update->ntimestep, error_now, tolerance, iteration);
    apply_operator(direction, product);
    const double alpha = rz / dot(direction, product);
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

  double u[3];
  for (int i = 0; i < nlocal; i++) {
    flow.velocity(x[i], u);
    for (int k = 0; k < 3; k++) {
      v[i][k] = solution[6 * i + k] + u[k];
      omega[i][k] = solution[6 * i + 3 + k] + W[k];
    }
  }
  tally_virial(E);
  steps++;
  total_iterations += iteration;
  last_iterations = iteration;
  last_error = error_now;
}

/* Virial of the lubrication forces at the velocities in `solution`: sum over pairs of
   (x_i - x_j) F_ij, symmetrised (the tangential forces make it asymmetric), in LAMMPS order
   xx yy zz xy xz yz, half of it for a pair seen from both
   sides (newton off across a periodic boundary). */
void FixHydroImplicitSF::tally_virial(const double E[3][3])
{
  for (double &value : virial) value = 0.0;
  double fi[3], ti[3], tj[3];
  for (const LubricatedPair &p : pairs) {
    const double *ui = &solution[6 * p.i], *uj = &solution[6 * p.j];
    double du[3];
    for (int a = 0; a < 3; a++)
      du[a] = ui[a] - uj[a] + E[a][0] * p.del[0] + E[a][1] * p.del[1] + E[a][2] * p.del[2];
    SuspensionFabric::lubrication_forces(p.R, du, ui + 3, uj + 3, fi, ti, tj);
    const double weight = p.add_to_j ? 1.0 : 0.5;
    virial[0] += weight * p.del[0] * fi[0];
    virial[1] += weight * p.del[1] * fi[1];
    virial[2] += weight * p.del[2] * fi[2];
    virial[3] += weight * 0.5 * (p.del[0] * fi[1] + p.del[1] * fi[0]);
    virial[4] += weight * 0.5 * (p.del[0] * fi[2] + p.del[2] * fi[0]);
    virial[5] += weight * 0.5 * (p.del[1] * fi[2] + p.del[2] * fi[1]);
  }
}

/* 1: CG iterations of the last step, 2: mean iterations per step since the fix was
   created, 3: velocity error |D^-1 r|_max reached in the last step. */
double FixHydroImplicitSF::compute_vector(int n)
{
  if (n == 0) return last_iterations;
  if (n == 1) return steps > 0 ? static_cast<double>(total_iterations) / steps : 0.0;
  return last_error;
}

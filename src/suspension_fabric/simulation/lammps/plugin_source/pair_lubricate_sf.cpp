/* pair_style lubricate/sf: leading-order lubrication between two spheres of radii
   a_i, a_j (Jeffrey & Onishi 1984, J. Fluid Mech. 139, 261; Kim & Karrila 1991 ch. 11),
   the near-field model of Mari, Seto, Morris & Denn, J. Rheol. 58, 1693 (2014).

   Geometry: r = |x_j - x_i|, n = (x_j - x_i)/r (from i to j), surface gap h = r - a_i - a_j,
   reduced gap xi = 2h/(a_i + a_j), lambda = a_j/a_i.  Regularised gap: xi_r = max(xi, 0) + delta,
   so an overlapping (contact) pair keeps the resistance of h = 0.  Pairs with xi >= h_out feel
   nothing.  With L = log(1/xi_r) and eta = eta_f, the dimensional resistances are
     squeeze  X   = 6 pi eta a_i g1(l) / xi_r,       g1(l)   = 2 l^2 / (1+l)^3
     shear    YA  = 6 pi eta a_i gYA(l) L,           gYA(l)  = (4/15) l (2 + l + 2 l^2) / (1+l)^3
     pump     YBi = 4 pi eta a_i^2 gYB(l) L,         gYB(l)  = -(1/5) l (4 + l) / (1+l)^2
              YBj = 4 pi eta a_j^2 gYB(1/l) L
     rotation YCi = 8 pi eta a_i^3 gYC(l) L,         gYC(l)  = (2/5) l / (1+l)
              YCj = 8 pi eta a_j^3 gYC(1/l) L
              YCx = pi eta (a_i + a_j)^3 g4(l) L,    g4(l)   = (4/5) l^2 / (1+l)^4
   and, with du = v_i - v_j - Omega_inf x (x_i - x_j), w_k = omega_k - Omega_inf,
   P = I - nn (tangential projector):
     F_i = -X (n.du) n - YA P du - YBi n x w_i - YBj n x w_j,          F_j = -F_i
     T_i = -YBi du x n - P (YCi w_i + YCx w_j)
     T_j = -YBj du x n - P (YCx w_i + YCj w_j)
   This is -R_FU (U - U_inf) + R_FE : E_inf at leading order: the singular strain terms cancel
   the strain part of the imposed relative velocity, so only the rotational part is removed.
   Forces obey F_i + F_j = 0 exactly; T_i + T_j + (x_i - x_j) x F_i = 0 holds at h = 0 (the
   resistance functions satisfy it identically there) and is O(h log h) otherwise. */

#include "pair_lubricate_sf.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "memory.h"
#include "modify.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "utils.h"

#include "imposed_flow.h"
#include "lubrication.h"

#include <cmath>
#include <cstring>
#include <vector>

using namespace LAMMPS_NS;

PairLubricateSF::PairLubricateSF(LAMMPS *lmp) :
    Pair(lmp), eta_f(0.0), delta(0.0), gap_out(0.0), implicit(false), maxrad_type(nullptr)
{
  single_enable = 1;
  single_extra = 3;
  svector = new double[single_extra];
  // compute pair lubricate/sf: the summed torque of the contacts (see compute()), then minus
  // the summed pair stresslets (explicit forces only; the implicit fix reports its own)
  nextra = 9;
  pvector = new double[nextra];
  for (int k = 0; k < nextra; k++) pvector[k] = 0.0;
  restartinfo = 0;    // re-issue pair_style/pair_coeff after read_restart
  finitecutflag = 1;
  // the virial must come from the symmetrised tally, never from sum x_i f_i (newton on)
  no_virial_fdotr_compute = 1;
}

PairLubricateSF::~PairLubricateSF()
{
  if (allocated) {
    memory->destroy(setflag);
    memory->destroy(cutsq);
  }
  memory->destroy(maxrad_type);
  delete[] svector;
  delete[] pvector;
}

void PairLubricateSF::allocate()
{
  allocated = 1;
  const int n = atom->ntypes + 1;
  memory->create(setflag, n, n, "pair:setflag");
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++) setflag[i][j] = 0;
  memory->create(cutsq, n, n, "pair:cutsq");
  memory->create(maxrad_type, n, "pair:maxrad_type");
}

void PairLubricateSF::settings(int narg, char **arg)
{
  if (narg != 3 && !(narg == 4 && strcmp(arg[3], "implicit") == 0))
    error->all(FLERR, "Illegal pair_style lubricate/sf command: expected <eta_f> <delta> <h_out> [implicit]");
  implicit = (narg == 4);
  eta_f = utils::numeric(FLERR, arg[0], false, lmp);
  delta = utils::numeric(FLERR, arg[1], false, lmp);
  gap_out = utils::numeric(FLERR, arg[2], false, lmp);
  if (eta_f < 0.0) error->all(FLERR, "pair_style lubricate/sf: eta_f must be >= 0");
  if (delta <= 0.0) error->all(FLERR, "pair_style lubricate/sf: delta must be > 0");
  // log(1/xi) must stay positive inside the cutoff
  if (gap_out <= 0.0 || gap_out + delta >= 1.0)
    error->all(FLERR, "pair_style lubricate/sf: need 0 < h_out and h_out + delta < 1 (reduced gaps)");
}

void PairLubricateSF::coeff(int narg, char **arg)
{
  if (narg != 2)
    error->all(FLERR, "Illegal pair_coeff command for lubricate/sf: takes no coefficients");
  if (!allocated) allocate();
  int ilo, ihi, jlo, jhi;
  utils::bounds(FLERR, arg[0], 1, atom->ntypes, ilo, ihi, error);
  utils::bounds(FLERR, arg[1], 1, atom->ntypes, jlo, jhi, error);
  int count = 0;
  for (int i = ilo; i <= ihi; i++)
    for (int j = MAX(jlo, i); j <= jhi; j++) {
      setflag[i][j] = 1;
      count++;
    }
  if (count == 0) error->all(FLERR, "Incorrect args for pair coefficients");
}

void PairLubricateSF::update_type_radii()
{
  const int n = atom->ntypes + 1;
  std::vector<double> local(n, 0.0);
  const double *radius = atom->radius;
  const int *type = atom->type;
  for (int i = 0; i < atom->nlocal; i++) local[type[i]] = MAX(local[type[i]], radius[i]);
  MPI_Allreduce(local.data(), maxrad_type, n, MPI_DOUBLE, MPI_MAX, world);
}

void PairLubricateSF::init_style()
{
  if (!atom->radius_flag || !atom->omega_flag || !atom->torque_flag)
    error->all(FLERR, "Pair lubricate/sf requires atom style sphere");
  if (comm->ghost_velocity == 0)
    error->all(FLERR, "Pair lubricate/sf requires ghost atoms store velocity: comm_modify vel yes");

  if (implicit && modify->get_fix_by_style("^hydro/implicit/sf$").empty())
    error->all(FLERR, "pair_style lubricate/sf ... implicit needs fix hydro/implicit/sf, which "
                      "computes its forces");

  update_type_radii();
  // A per-type list (cutoff from init_one plus the skin) holds every pair that can enter the
  // lubrication range before the next rebuild. A size list (r < a_i + a_j + skin) would not:
  // two atoms may close by a whole skin between rebuilds, so a pair listed as out of range
  // could reach a lubricated gap and feel nothing.
  neighbor->add_request(this);
}

void PairLubricateSF::setup()
{
  // domain->deform_* are only current once the run is set up
  if (domain->deform_flag && !domain->deform_vremap)
    error->all(FLERR, "Pair lubricate/sf needs fix deform with 'remap v' (ghost velocities)");
}

double PairLubricateSF::init_one(int i, int j)
{
  if (setflag[i][j] == 0) error->all(FLERR, "All pair lubricate/sf coeffs are not set");
  return (maxrad_type[i] + maxrad_type[j]) * (1.0 + 0.5 * gap_out);
}

/* Lubrication force on i (fi, with -fi on j) and torques on i and j for the pair (i, j).
   Returns false if the pair is beyond the outer cutoff. */
bool PairLubricateSF::pair_interaction(int i, int j, const SuspensionFabric::ImposedFlow &flow,
                                       double *fi, double *ti, double *tj, double *S) const
{
  double **x = atom->x;
  double **v = atom->v;
  double **omega = atom->omega;
  const double del[3] = {x[i][0] - x[j][0], x[i][1] - x[j][1], x[i][2] - x[j][2]};
  SuspensionFabric::PairResistance R;
  if (!resistance(i, j, del, R)) return false;

  // relative velocity without the rigid rotation of the imposed flow
  const double *W = flow.omega;
  const double du[3] = {v[i][0] - v[j][0] - (W[1] * del[2] - W[2] * del[1]),
                        v[i][1] - v[j][1] - (W[2] * del[0] - W[0] * del[2]),
                        v[i][2] - v[j][2] - (W[0] * del[1] - W[1] * del[0])};
  const double wi[3] = {omega[i][0] - W[0], omega[i][1] - W[1], omega[i][2] - W[2]};
  const double wj[3] = {omega[j][0] - W[0], omega[j][1] - W[1], omega[j][2] - W[2]};
  SuspensionFabric::lubrication_forces(R, du, wi, wj, fi, ti, tj);
  if (S) {
    // velocity relative to the imposed flow: take the strain part E.del out of du
    const auto &E = flow.strain;
    double du_na[3];
    for (int a = 0; a < 3; a++) du_na[a] = du[a] - (E[a][0] * del[0] + E[a][1] * del[1] + E[a][2] * del[2]);
    SuspensionFabric::lubrication_stresslet(R, eta_f, du_na, E, wi, wj, S);
  }
  return true;
}

bool PairLubricateSF::resistance(int i, int j, const double *del,
                                 SuspensionFabric::PairResistance &R) const
{
  return SuspensionFabric::lubrication_resistance(del, atom->radius[i], atom->radius[j], eta_f,
                                                  delta, gap_out, R);
}

void PairLubricateSF::compute(int eflag, int vflag)
{
  ev_init(eflag, vflag);
  double **torque = atom->torque;
  const int nlocal = atom->nlocal;
  const int newton_pair = force->newton_pair;

  // The torques present now are those of the sub-styles listed before this one in
  // pair_style hybrid/overlay, i.e. the granular contacts (torques are cleared each step and
  // no fix adds any before the pair forces).  Their sum T_c = -sum_pairs (x_i - x_j) x F_ij
  // gives the antisymmetric part of the contact virial, which LAMMPS tallies unsymmetrised
  // (dx F_z, not (dx F_z + dz F_x)/2).  With newton on, ghost atoms still hold their share.
  const int counted = newton_pair ? nlocal + atom->nghost : nlocal;
  for (int k = 0; k < nextra; k++) pvector[k] = 0.0;
  for (int i = 0; i < counted; i++)
    for (int k = 0; k < 3; k++) pvector[k] += torque[i][k];

  // implicit: fix hydro/implicit/sf solves for the velocities and owns the forces and virial
  if (implicit) return;

  double **x = atom->x;
  double **f = atom->f;

  const SuspensionFabric::ImposedFlow flow(domain);

  const int inum = list->inum;
  const int *ilist = list->ilist;
  const int *numneigh = list->numneigh;
  int **firstneigh = list->firstneigh;
  double fi[3], ti[3], tj[3], S[6];

  for (int ii = 0; ii < inum; ii++) {
    const int i = ilist[ii];
    const int *jlist = firstneigh[i];
    const int jnum = numneigh[i];

    for (int jj = 0; jj < jnum; jj++) {
      const int j = jlist[jj] & NEIGHMASK;
      if (!pair_interaction(i, j, flow, fi, ti, tj, S)) continue;

      f[i][0] += fi[0];
      f[i][1] += fi[1];
      f[i][2] += fi[2];
      torque[i][0] += ti[0];
      torque[i][1] += ti[1];
      torque[i][2] += ti[2];
      if (newton_pair || j < nlocal) {
        f[j][0] -= fi[0];
        f[j][1] -= fi[1];
        f[j][2] -= fi[2];
        torque[j][0] += tj[0];
        torque[j][1] += tj[1];
        torque[j][2] += tj[2];
      }

      // a pair with a ghost partner is seen from both sides when newton is off: half each time
      const double weight = (newton_pair || j < nlocal) ? 1.0 : 0.5;
      for (int k = 0; k < 6; k++) pvector[3 + k] -= weight * S[k];

      if (vflag_either) {
        // symmetrised virial (x_i - x_j) F_ij: the tangential forces make it asymmetric
        const double d[3] = {x[i][0] - x[j][0], x[i][1] - x[j][1], x[i][2] - x[j][2]};
        v_tally_tensor(i, j, nlocal, newton_pair, d[0] * fi[0], d[1] * fi[1], d[2] * fi[2],
                       0.5 * (d[0] * fi[1] + d[1] * fi[0]), 0.5 * (d[0] * fi[2] + d[2] * fi[0]),
                       0.5 * (d[1] * fi[2] + d[2] * fi[1]));
      }
    }
  }

  if (vflag_fdotr) virial_fdotr_compute();
}

/* For compute pair/local: fforce * (x_i - x_j) is the normal (line-of-centres) part of the
   lubrication force on i; svector holds its full force on i (x, y, z). Energy is 0. */
double PairLubricateSF::single(int i, int j, int /*itype*/, int /*jtype*/, double rsq,
                               double /*factor_coul*/, double /*factor_lj*/, double &fforce)
{
  fforce = 0.0;
  svector[0] = svector[1] = svector[2] = 0.0;
  const SuspensionFabric::ImposedFlow flow(domain);
  double fi[3], ti[3], tj[3];
  if (!pair_interaction(i, j, flow, fi, ti, tj, nullptr)) return 0.0;
  double **x = atom->x;
  const double fdel = fi[0] * (x[i][0] - x[j][0]) + fi[1] * (x[i][1] - x[j][1]) +
      fi[2] * (x[i][2] - x[j][2]);
  fforce = fdel / rsq;
  for (int k = 0; k < 3; k++) svector[k] = fi[k];
  return 0.0;
}

/* fix stokes/sf: one-body Stokes drag relative to the imposed flow,
     F_i = -3 pi eta_f d_i (v_i - u_inf(x_i)),   T_i = -pi eta_f d_i^3 (omega_i - Omega_inf),
   d_i = 2 radius_i, u_inf and Omega_inf from the box deformation rate (imposed_flow.h).
   The drag does not enter the virial: it is the momentum exchange with the imposed flow,
   and in the overdamped limit its first moment sum x_i F_i just mirrors the pair virial
   (see README.md). */

#include "fix_stokes_sf.h"

#include "atom.h"
#include "domain.h"
#include "error.h"
#include "update.h"
#include "utils.h"

#include "imposed_flow.h"

#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;
using namespace FixConst;

FixStokesSF::FixStokesSF(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg), eta_f(0.0)
{
  if (narg != 4) error->all(FLERR, "Illegal fix stokes/sf command: expected fix ID group stokes/sf <eta_f>");
  eta_f = utils::numeric(FLERR, arg[3], false, lmp);
  if (eta_f < 0.0) error->all(FLERR, "fix stokes/sf: eta_f must be >= 0");
}

int FixStokesSF::setmask()
{
  return POST_FORCE | MIN_POST_FORCE;
}

void FixStokesSF::init()
{
  if (!atom->radius_flag || !atom->omega_flag || !atom->torque_flag)
    error->all(FLERR, "Fix stokes/sf requires atom style sphere");
  if (strcmp(update->integrate_style, "verlet") != 0)
    error->all(FLERR, "Fix stokes/sf supports run_style verlet only");
}

void FixStokesSF::setup(int vflag)
{
  post_force(vflag);
}

void FixStokesSF::min_setup(int vflag)
{
  post_force(vflag);
}

void FixStokesSF::min_post_force(int vflag)
{
  post_force(vflag);
}

void FixStokesSF::post_force(int /*vflag*/)
{
  double **x = atom->x;
  double **v = atom->v;
  double **f = atom->f;
  double **omega = atom->omega;
  double **torque = atom->torque;
  const double *radius = atom->radius;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;

  const SuspensionFabric::ImposedFlow flow(domain);
  const double *W = flow.omega;
  const double pi_eta = M_PI * eta_f;

  double u[3];
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    const double d = 2.0 * radius[i];
    const double zeta_t = 3.0 * pi_eta * d;
    const double zeta_r = pi_eta * d * d * d;
    flow.velocity(x[i], u);
    for (int k = 0; k < 3; k++) {
      f[i][k] -= zeta_t * (v[i][k] - u[k]);
      torque[i][k] -= zeta_r * (omega[i][k] - W[k]);
    }
  }
}

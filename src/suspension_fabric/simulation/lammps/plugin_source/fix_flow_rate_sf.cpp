/* fix flow_rate/sf: the box's tilt rates, and so the imposed flow, right from the first step of a
   run when fix deform varies the tilts through variables (rotary shear, segment.lmp).

   fix deform sets domain->h_rate (the box deformation rate that imposed_flow.h turns into the
   velocity gradient, and that compute temp/deform reads) to zero in its init() for a tilt of style
   variable, and first evaluates the rate variable at the end of the first step: that step would
   see no imposed flow, at every launch of a run, a resumed one included. This fix, defined after
   fix deform, evaluates the same rate variables in its init(), which runs after fix deform's, so
   that the first step sees the flow of the strain it starts at; from the end of the first step on,
   fix deform sets the rates itself.

   fix ID group flow_rate/sf v_XZ v_YZ   XZ, YZ: equal-style variables, the xz and yz tilt rates
                                         (distance per time) given to fix deform. */

#include "fix_flow_rate_sf.h"

#include "domain.h"
#include "error.h"
#include "input.h"
#include "variable.h"

using namespace LAMMPS_NS;

FixFlowRateSF::FixFlowRateSF(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  if (narg != 5)
    error->all(FLERR, "Illegal fix flow_rate/sf command: expected fix ID group flow_rate/sf v_xz v_yz");
  for (int k = 3; k < 5; k++)
    if (std::string(arg[k]).rfind("v_", 0) != 0)
      error->all(FLERR, "fix flow_rate/sf: {} is not a variable reference v_<name>", arg[k]);
  xz_rate = std::string(arg[3]).substr(2);
  yz_rate = std::string(arg[4]).substr(2);
}

int FixFlowRateSF::setmask()
{
  return 0;    // acts only in init()
}

void FixFlowRateSF::init()
{
  if (!domain->triclinic) error->all(FLERR, "fix flow_rate/sf needs a triclinic box (fix deform tilts)");
  // Voigt order of h_rate: xx yy zz yz xz xy
  const std::pair<const std::string *, int> rates[2] = {{&xz_rate, 4}, {&yz_rate, 3}};
  for (const auto &[name, index] : rates) {
    const int ivar = input->variable->find(name->c_str());
    if (ivar < 0) error->all(FLERR, "fix flow_rate/sf: variable {} does not exist", *name);
    if (!input->variable->equalstyle(ivar))
      error->all(FLERR, "fix flow_rate/sf: variable {} is not equal-style", *name);
    domain->h_rate[index] = input->variable->compute_equal(ivar);
  }
}

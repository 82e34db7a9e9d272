/* fix <ID> <group> stokes/sf <eta_f>
   Stokes drag on force and torque relative to the flow imposed by fix deform.
   See README.md in this folder. */

#ifndef SUSPENSION_FABRIC_FIX_STOKES_SF_H
#define SUSPENSION_FABRIC_FIX_STOKES_SF_H

#include "fix.h"

namespace LAMMPS_NS {

class FixStokesSF : public Fix {
 public:
  FixStokesSF(class LAMMPS *, int, char **);

  int setmask() override;
  void init() override;
  void setup(int) override;
  void min_setup(int) override;
  void post_force(int) override;
  void min_post_force(int) override;

 protected:
  double eta_f;
};

}    // namespace LAMMPS_NS

#endif

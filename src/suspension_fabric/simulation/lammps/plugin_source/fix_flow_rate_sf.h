/* fix <ID> <group> flow_rate/sf v_<xz rate> v_<yz rate>
   The imposed flow from the first step of a run on, when fix deform turns it through variables.
   See fix_flow_rate_sf.cpp. */

#ifndef SUSPENSION_FABRIC_FIX_FLOW_RATE_SF_H
#define SUSPENSION_FABRIC_FIX_FLOW_RATE_SF_H

#include "fix.h"

#include <string>

namespace LAMMPS_NS {

class FixFlowRateSF : public Fix {
 public:
  FixFlowRateSF(class LAMMPS *, int, char **);

  int setmask() override;
  void init() override;

 protected:
  std::string xz_rate, yz_rate;
};

}    // namespace LAMMPS_NS

#endif

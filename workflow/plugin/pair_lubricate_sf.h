/* pair_style lubricate/sf <eta_f> <delta> <h_out>
   Leading-order pairwise lubrication between spheres of any radii (Jeffrey & Onishi 1984
   resistance functions, as used by Mari et al. 2014).  See README.md in this folder. */

#ifndef SUSPENSION_FABRIC_PAIR_LUBRICATE_SF_H
#define SUSPENSION_FABRIC_PAIR_LUBRICATE_SF_H

#include "pair.h"

namespace LAMMPS_NS {

class PairLubricateSF : public Pair {
 public:
  PairLubricateSF(class LAMMPS *);
  ~PairLubricateSF() override;

  void compute(int, int) override;
  void settings(int, char **) override;
  void coeff(int, char **) override;
  void init_style() override;
  double init_one(int, int) override;
  void setup() override;
  double single(int, int, int, int, double, double, double, double &) override;

 protected:
  double eta_f;          // fluid viscosity
  double delta;          // regularisation of the reduced gap
  double gap_out;        // outer cutoff on the reduced gap xi = 2h/(a_i+a_j)
  double *maxrad_type;   // largest radius of each atom type (sets neighbour cutoffs)

  void allocate();
  void update_type_radii();
  bool pair_interaction(int, int, const double *, double *, double *, double *) const;
};

}    // namespace LAMMPS_NS

#endif

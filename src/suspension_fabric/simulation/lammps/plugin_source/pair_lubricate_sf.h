/* pair_style lubricate/sf <eta_f> <delta> <h_out> [implicit]
   Leading-order pairwise lubrication between spheres of any radii (Jeffrey & Onishi 1984
   resistance functions, as used by Mari et al. 2014).  See README.md in this folder. */

#ifndef SUSPENSION_FABRIC_PAIR_LUBRICATE_SF_H
#define SUSPENSION_FABRIC_PAIR_LUBRICATE_SF_H

#include "pair.h"

#include "imposed_flow.h"
#include "lubrication.h"

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

  // read by fix hydro/implicit/sf, which solves the same lubrication implicitly
  double eta_f;          // fluid viscosity
  double delta;          // regularisation of the reduced gap
  double gap_out;        // outer cutoff on the reduced gap xi = 2h/(a_i+a_j)
  bool implicit;         // forces left to fix hydro/implicit/sf (keyword "implicit")
  // resistance of the pair (i, j) at separation del = x_i - x_j; false beyond the cutoff
  bool resistance(int i, int j, const double *del, SuspensionFabric::PairResistance &) const;

 protected:
  double *maxrad_type;   // largest radius of each atom type (sets neighbour cutoffs)

  void allocate();
  void update_type_radii();
  // forces, torques and (if S is not null) the pair's stresslet
  bool pair_interaction(int, int, const SuspensionFabric::ImposedFlow &, double *, double *, double *,
                        double *S) const;
};

}    // namespace LAMMPS_NS

#endif

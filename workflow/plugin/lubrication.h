/* Leading-order pairwise lubrication resistance (Jeffrey & Onishi 1984; Mari et al. 2014),
   shared by pair_style lubricate/sf (explicit forces) and fix hydro/implicit/sf (implicit
   solve), so both use one set of formulas.  Conventions and prefactors: see the header
   comment of pair_lubricate_sf.cpp. */

#ifndef SUSPENSION_FABRIC_LUBRICATION_H
#define SUSPENSION_FABRIC_LUBRICATION_H

#include <cmath>

namespace SuspensionFabric {

// Resistance scalars of one pair and its unit vector n from i to j.
struct PairResistance {
  double n[3];
  double X, YA, YBi, YBj, YCi, YCj, YCx;
};

/* Resistances of the pair (i, j) with separation del = x_i - x_j and radii ai, aj.
   Returns false if the reduced gap xi = 2h/(ai + aj) is at or beyond gap_out. */
inline bool lubrication_resistance(const double del[3], double ai, double aj, double eta_f,
                                   double delta, double gap_out, PairResistance &out)
{
  const double rsq = del[0] * del[0] + del[1] * del[1] + del[2] * del[2];
  const double radsum = ai + aj;
  const double rcut = radsum * (1.0 + 0.5 * gap_out);
  if (rsq >= rcut * rcut) return false;

  const double r = std::sqrt(rsq);
  const double rinv = 1.0 / r;
  for (int k = 0; k < 3; k++) out.n[k] = -del[k] * rinv;    // from i to j

  const double gap = 2.0 * (r - radsum) / radsum;
  const double xi = (gap > 0.0 ? gap : 0.0) + delta;
  const double invxi = 1.0 / xi;
  const double logxi = std::log(invxi);

  const double pi_eta = M_PI * eta_f;
  const double l = aj / ai;
  const double ilp1 = 1.0 / (1.0 + l);
  const double ilp1_2 = ilp1 * ilp1;
  const double ilp1_3 = ilp1_2 * ilp1;

  out.X = 6.0 * pi_eta * ai * (2.0 * l * l * ilp1_3) * invxi;
  out.YA = 6.0 * pi_eta * ai * ((4.0 / 15.0) * l * (2.0 + l + 2.0 * l * l) * ilp1_3) * logxi;
  out.YBi = 4.0 * pi_eta * ai * ai * (-0.2 * l * (4.0 + l) * ilp1_2) * logxi;
  out.YBj = 4.0 * pi_eta * aj * aj * (-0.2 * (4.0 * l + 1.0) * ilp1_2) * logxi;
  out.YCi = 8.0 * pi_eta * ai * ai * ai * (0.4 * l * ilp1) * logxi;
  out.YCj = 8.0 * pi_eta * aj * aj * aj * (0.4 * ilp1) * logxi;
  out.YCx = pi_eta * radsum * radsum * radsum * (0.8 * l * l * ilp1_2 * ilp1_2) * logxi;
  return true;
}

/* Force on i (fi; j gets -fi) and torques on i and j for the relative velocity du and the
   angular velocities wi, wj (all relative to the imposed flow, see pair_lubricate_sf.cpp):
     F_i = -X (n.du) n - YA P du - YBi n x w_i - YBj n x w_j
     T_i = -YBi du x n - P (YCi w_i + YCx w_j),   T_j = -YBj du x n - P (YCx w_i + YCj w_j) */
inline void lubrication_forces(const PairResistance &R, const double du[3], const double wi[3],
                               const double wj[3], double fi[3], double ti[3], double tj[3])
{
  const double *n = R.n;
  const double un = du[0] * n[0] + du[1] * n[1] + du[2] * n[2];
  const double win = wi[0] * n[0] + wi[1] * n[1] + wi[2] * n[2];
  const double wjn = wj[0] * n[0] + wj[1] * n[1] + wj[2] * n[2];
  const double nxwi[3] = {n[1] * wi[2] - n[2] * wi[1], n[2] * wi[0] - n[0] * wi[2],
                          n[0] * wi[1] - n[1] * wi[0]};
  const double nxwj[3] = {n[1] * wj[2] - n[2] * wj[1], n[2] * wj[0] - n[0] * wj[2],
                          n[0] * wj[1] - n[1] * wj[0]};
  const double duxn[3] = {du[1] * n[2] - du[2] * n[1], du[2] * n[0] - du[0] * n[2],
                          du[0] * n[1] - du[1] * n[0]};
  for (int k = 0; k < 3; k++) {
    const double dut = du[k] - un * n[k];
    const double wit = wi[k] - win * n[k];
    const double wjt = wj[k] - wjn * n[k];
    fi[k] = -R.X * un * n[k] - R.YA * dut - R.YBi * nxwi[k] - R.YBj * nxwj[k];
    ti[k] = -R.YBi * duxn[k] - R.YCi * wit - R.YCx * wjt;
    tj[k] = -R.YBj * duxn[k] - R.YCx * wit - R.YCj * wjt;
  }
}

}    // namespace SuspensionFabric

#endif
